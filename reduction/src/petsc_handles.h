#pragma once
// Owning handles for PETSc/SLEPc objects and an error check that throws, for
// the reduction sources (never installed).
#include <petscksp.h>
#include <slepceps.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace fretsim::reduction
{
  inline void petsc_check(const PetscErrorCode code, const char *call)
  {
    if (code != 0)
      throw std::runtime_error(std::string("reduction: PETSc/SLEPc error ") + std::to_string(static_cast<int>(code)) +
                               " in " + call);
  }
#define FRETSIM_PETSC(call) ::fretsim::reduction::petsc_check((call), #call)

  template <typename Handle, PetscErrorCode (*destroy)(Handle *)>
  class Owned
  {
  public:
    Owned() = default;
    ~Owned() { reset(); }
    Owned(Owned &&other) noexcept
      : handle(std::exchange(other.handle, nullptr))
    {}
    Owned &operator=(Owned &&other) noexcept
    {
      reset();
      handle = std::exchange(other.handle, nullptr);
      return *this;
    }
    Owned(const Owned &)            = delete;
    Owned &operator=(const Owned &) = delete;

    void reset()
    {
      if (handle != nullptr)
        destroy(&handle);
      handle = nullptr;
    }
    /// For PETSc's create functions: releases what was held.
    Handle *out()
    {
      reset();
      return &handle;
    }
    operator Handle() const { return handle; }

  private:
    Handle handle = nullptr;
  };

  using OwnedMat = Owned<Mat, MatDestroy>;
  using OwnedVec = Owned<Vec, VecDestroy>;
  using OwnedKSP = Owned<KSP, KSPDestroy>;
  using OwnedIS  = Owned<IS, ISDestroy>;
  using OwnedEPS = Owned<EPS, EPSDestroy>;
} // namespace fretsim::reduction
