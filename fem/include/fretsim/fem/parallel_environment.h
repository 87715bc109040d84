#pragma once
// MPI, PETSc, SLEPc and p4est for the lifetime of one object, created once per
// process before any fem object (the program's main, a command, or a test
// environment). deal.II's MPI_InitFinalize does the work inside.
#include <memory>

namespace fretsim::fem
{
  class ParallelEnvironment
  {
  public:
    /// Initialises with the program's arguments (PETSc reads its options from them).
    ParallelEnvironment(int &argc, char **&argv);
    /// Initialises with no arguments.
    ParallelEnvironment();
    /// Finalises; fem objects must be gone by then.
    ~ParallelEnvironment();
    ParallelEnvironment(const ParallelEnvironment &) = delete;
    ParallelEnvironment &operator=(const ParallelEnvironment &) = delete;

    /// Whether MPI is running (initialised and not yet finalised).
    static bool active();
    /// Ranks in MPI_COMM_WORLD and this process's rank.
    static unsigned int n_ranks();
    static unsigned int rank();
    /// Waits for every rank (e.g. until rank 0 has written a file the
    /// others read next); nothing without MPI running.
    static void barrier();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::fem
