#pragma once
// MPI/PETSc/SLEPc for a whole fem test program: started before the first test
// and finalised after the last, inside main (gtest's global environment).
#include <fretsim/fem/parallel_environment.h>

#include <gtest/gtest.h>

#include <memory>

namespace fretsim::fem_testing
{
  class ParallelTestEnvironment : public ::testing::Environment
  {
  public:
    void SetUp() override { environment = std::make_unique<fem::ParallelEnvironment>(); }
    void TearDown() override { environment.reset(); }

  private:
    std::unique_ptr<fem::ParallelEnvironment> environment;
  };

  inline ::testing::Environment *const registered_environment =
    ::testing::AddGlobalTestEnvironment(new ParallelTestEnvironment);

  /// Relative difference |a - b| / |b|.
  inline double relative_error(double a, double b) { return std::abs(a - b) / std::abs(b); }
} // namespace fretsim::fem_testing
