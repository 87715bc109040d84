#pragma once
// Run control: what a command checks and holds around its computing.
// - Interruption: SIGINT/SIGTERM ask the running scene to stop after the
//   current step, so the results file is closed cleanly with the steps done.
// - The output folder: checked, locked and cleared of a previous run's files
//   before anything is computed (OutputFolder).
// - The machine: memory and disk a run can count on, for refusing up front a
//   run that cannot fit rather than failing hours in.
#include <string>
#include <vector>

namespace fretsim::app
{
  /// Installs the handlers (idempotent).
  void install_interrupt_handlers();
  /// True once SIGINT or SIGTERM was received.
  bool interrupt_requested();
  /// The signal number received, 0 if none.
  int interrupt_signal();

  /// Whether an MPI launcher (mpirun, mpiexec, srun: Open MPI, PMIx or
  /// MPICH's PMI) started this process, read from its environment before MPI
  /// starts.
  bool started_by_mpi_launcher();
  /// This process's rank in that launch (0 when not launched).
  int launcher_rank();

  /// What a command writes into its output folder, by name relative to the
  /// folder: the files that mark a previous result, and that `--force` removes
  /// (nothing else is ever removed). A name ending in '/' is a folder of the
  /// command's own (removed with its contents).
  struct OutputPolicy
  {
    std::string              option = "-o"; ///< how the user gave the folder, for messages
    std::vector<std::string> own_files;
    bool                     force = false; ///< replace a previous result
    /// One of own_files that a restarted command continues from (a map's
    /// map.h5): without force its presence is no previous result, and it is
    /// kept while the command's other files are replaced.
    std::string resume_file;
  };

  /// The file names a scene run writes (results, summary, figures).
  std::vector<std::string> scene_output_files();

  /// The folder a command writes into, claimed for the command's lifetime.
  /// The constructor checks the path (InputError naming the option and the
  /// reason: empty, a file, under a file, unwritable, no such drive), creates
  /// the folder, takes an exclusive lock (a second command into the same
  /// folder is refused while this one runs) and refuses a folder holding a
  /// previous result unless `policy.force`, in which case that result's files
  /// are removed first. The destructor releases the lock and removes the
  /// folder again if this object created it and nothing was written into it.
  class OutputFolder
  {
  public:
    OutputFolder(const std::string &path, const OutputPolicy &policy);
    ~OutputFolder();
    OutputFolder(const OutputFolder &)            = delete;
    OutputFolder &operator=(const OutputFolder &) = delete;

    const std::string &path() const { return folder; }

    /// The checks of the constructor that need no writing (for --dry-run):
    /// throws the same InputErrors, creates and locks nothing.
    static void check(const std::string &path, const OutputPolicy &policy);

  private:
    void release();

    std::string folder, lock_file;
    int         lock_descriptor = -1;
    bool        created         = false;
  };

  /// Checks a single output file's path (e.g. `reduce -o model.h5`): not
  /// empty, not a folder, under a writable folder; an existing file that is
  /// not HDF5 is kept unless `force`. Creates the missing parent folders.
  void prepare_output_file(const std::string &path, const std::string &option, bool force);

  /// Memory the kernel expects to be available without swapping
  /// (MemAvailable of /proc/meminfo) [bytes]; infinity if unknown.
  double available_memory_bytes();
  /// Free space for an unprivileged writer on the file system that holds
  /// `path` or its nearest existing parent [bytes]; infinity if unknown.
  double free_disk_bytes(const std::string &path);
  /// "1.5 GB", "320 MB": a size for messages.
  std::string format_bytes(double bytes);
} // namespace fretsim::app
