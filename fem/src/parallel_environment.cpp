#include <fretsim/fem/parallel_environment.h>

#include <deal.II/base/mpi.h>

#include <mpi.h>

namespace fretsim::fem
{
  struct ParallelEnvironment::Impl
  {
    Impl(int &argc, char **&argv)
      // One thread per rank: the ranks share the machine's few cores.
      : mpi(argc, argv, 1)
    {}
    dealii::Utilities::MPI::MPI_InitFinalize mpi;
  };

  ParallelEnvironment::ParallelEnvironment(int &argc, char **&argv)
    : impl(std::make_unique<Impl>(argc, argv))
  {}

  ParallelEnvironment::ParallelEnvironment()
  {
    static char  name[] = "fretsim";
    static char *args[] = {name, nullptr};
    int          argc   = 1;
    char       **argv   = args;
    impl                = std::make_unique<Impl>(argc, argv);
  }

  ParallelEnvironment::~ParallelEnvironment() = default;

  bool ParallelEnvironment::active()
  {
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    return initialized && !finalized;
  }

  unsigned int ParallelEnvironment::n_ranks() { return dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD); }
  unsigned int ParallelEnvironment::rank() { return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD); }
  void         ParallelEnvironment::barrier()
  {
    if (active())
      MPI_Barrier(MPI_COMM_WORLD);
  }
} // namespace fretsim::fem
