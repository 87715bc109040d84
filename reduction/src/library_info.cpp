#include <fretsim/reduction/library_info.h>

#include <petscversion.h>
#include <slepcversion.h>

#include <string>

namespace fretsim::reduction
{
  std::string library_versions()
  {
    return "PETSc " + std::to_string(PETSC_VERSION_MAJOR) + "." + std::to_string(PETSC_VERSION_MINOR) + "." +
           std::to_string(PETSC_VERSION_SUBMINOR) + ", SLEPc " + std::to_string(SLEPC_VERSION_MAJOR) + "." +
           std::to_string(SLEPC_VERSION_MINOR) + "." + std::to_string(SLEPC_VERSION_SUBMINOR);
  }
} // namespace fretsim::reduction
