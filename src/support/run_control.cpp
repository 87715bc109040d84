#include <fretsim/support/run_control.h>

#include <fretsim/support/parameters.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <fcntl.h>
#include <fnmatch.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

namespace fretsim::app
{
  namespace
  {
    namespace fs = std::filesystem;

    volatile std::sig_atomic_t received_signal = 0;

    extern "C" void on_signal(int signal_number) { received_signal = signal_number; }

    /// The lock file's name: hidden, and never one of a command's own files.
    constexpr const char *lock_name = ".fretsim.lock";

    [[noreturn]] void refuse(const OutputPolicy &policy, const std::string &path, const std::string &problem)
    {
      throw InputError("(command line)", policy.option, "'" + path + "': " + problem);
    }

    /// The nearest part of `path` (itself or a parent) that exists.
    fs::path nearest_existing(const fs::path &path)
    {
      fs::path candidate = fs::absolute(path).lexically_normal();
      std::error_code error;
      while (!fs::exists(candidate, error) && candidate.has_relative_path())
        candidate = candidate.parent_path();
      return candidate;
    }

    /// Where drives are mounted: a folder to be made right under one of
    /// these is far more likely a drive that is not mounted than a wish.
    bool is_mount_parent(const fs::path &folder)
    {
      const std::string text = folder.lexically_normal().string();
      for (const char *parent : {"/", "/mnt", "/media", "/run/media", "/Volumes"})
        if (text == parent || text == std::string(parent) + "/")
          return true;
      return false;
    }

    /// The checks every output path shares: the folder it would be written
    /// into (`folder`) can be made, and written.
    void check_parent_chain(const fs::path &folder, const std::string &given, const OutputPolicy &policy)
    {
      const fs::path existing = nearest_existing(folder);
      std::error_code error;
      if (!fs::is_directory(existing, error))
        refuse(policy, given, "'" + existing.string() + "' is a file, so no folder can be made under it");
      if (existing != fs::absolute(folder).lexically_normal() && is_mount_parent(existing))
        {
          auto missing = fs::absolute(folder).lexically_normal().lexically_relative(existing);
          refuse(policy, given, "'" + (existing / *missing.begin()).string() +
                                  "' does not exist (a drive that is not mounted?); expected a folder under an "
                                  "existing one");
        }
      if (::access(existing.c_str(), W_OK | X_OK) != 0)
        refuse(policy, given, "cannot write into '" + existing.string() + "' (" + std::strerror(errno) + ")");
    }

    /// Names of `folder`'s entries that match one of the patterns ('*', '?' as
    /// in the shell; a trailing '/' matches a folder).
    std::vector<fs::path> own_entries(const fs::path &folder, const std::vector<std::string> &patterns)
    {
      std::vector<fs::path> found;
      std::error_code       error;
      for (const auto &entry : fs::directory_iterator(folder, error))
        {
          const std::string name = entry.path().filename().string();
          for (std::string pattern : patterns)
            {
              const bool folder_pattern = !pattern.empty() && pattern.back() == '/';
              if (folder_pattern)
                pattern.pop_back();
              if (fnmatch(pattern.c_str(), name.c_str(), FNM_PERIOD) == 0 &&
                  entry.is_directory(error) == folder_pattern)
                {
                  found.push_back(entry.path());
                  break;
                }
            }
        }
      return found;
    }

    bool is_empty_but_lock(const fs::path &folder)
    {
      std::error_code error;
      for (const auto &entry : fs::directory_iterator(folder, error))
        if (entry.path().filename() != lock_name)
          return false;
      return !error;
    }

    bool resumable(const fs::path &folder, const OutputPolicy &policy)
    {
      std::error_code error;
      return !policy.resume_file.empty() && fs::exists(folder / policy.resume_file, error);
    }

    void check_folder(const std::string &path, const OutputPolicy &policy)
    {
      if (path.empty())
        throw InputError("(command line)", policy.option, "expected a folder, got ''");
      std::error_code error;
      const fs::path  folder(path);
      if (fs::exists(folder, error) && !fs::is_directory(folder, error))
        refuse(policy, path, "is a file; expected a folder (a new one, or one holding a previous result)");
      check_parent_chain(folder, path, policy);
      if (!policy.force && fs::is_directory(folder, error) && !resumable(folder, policy))
        {
          const auto previous = own_entries(folder, policy.own_files);
          if (!previous.empty())
            refuse(policy, path, "holds a previous result ('" + previous.front().filename().string() +
                                   "'); expected a new folder, or --force to replace that result");
        }
    }
  } // namespace

  void install_interrupt_handlers()
  {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
  }

  bool interrupt_requested() { return received_signal != 0; }

  int interrupt_signal() { return received_signal; }

  std::vector<std::string> scene_output_files()
  {
    // results.xdmf and summary.json are written through a temporary file and a rename.
    return {"results.h5",  "results.xdmf",  "results.xdmf.tmp",  "summary.json",      "summary.json.tmp",
            "loop.png",    "surface_fields.png", "risk.png",     "interface_maps.png", "risk_circumference.png",
            "ball_loads.png"};
  }

  void OutputFolder::check(const std::string &path, const OutputPolicy &policy) { check_folder(path, policy); }

  OutputFolder::OutputFolder(const std::string &path, const OutputPolicy &policy)
    : folder(path)
  {
    check_folder(path, policy);
    std::error_code error;
    created = !fs::exists(path, error);
    fs::create_directories(path, error);
    if (error)
      refuse(policy, path, "cannot create the folder (" + error.message() + ")");
    lock_file = (fs::path(path) / lock_name).string();
    // Lock, then make sure the lock file is still the one in the folder: a
    // finishing run removes it, and a lock on a removed file guards nothing.
    for (;;)
      {
        lock_descriptor = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (lock_descriptor < 0)
          refuse(policy, path, std::string("cannot create the lock file (") + std::strerror(errno) + ")");
        if (::flock(lock_descriptor, LOCK_EX | LOCK_NB) != 0)
          {
            const int reason = errno;
            ::close(lock_descriptor);
            lock_descriptor = -1;
            refuse(policy, path, reason == EWOULDBLOCK ?
                                   "another fretsim command is writing into this folder; expected a folder of "
                                   "its own" :
                                   std::string("cannot lock the folder (") + std::strerror(reason) + ")");
          }
        struct stat held, named;
        if (::fstat(lock_descriptor, &held) == 0 && ::stat(lock_file.c_str(), &named) == 0 &&
            held.st_ino == named.st_ino && held.st_dev == named.st_dev)
          break;
        ::close(lock_descriptor);
      }
    try
      {
        // Checked again under the lock: a run that finished meanwhile left its result.
        check_folder(path, policy);
        const bool resuming = !policy.force && resumable(path, policy);
        for (const auto &previous : own_entries(path, policy.own_files))
          {
            if (resuming && previous.filename() == policy.resume_file)
              continue;
            fs::remove_all(previous, error);
            if (error)
              refuse(policy, path, "cannot remove the previous result's '" + previous.filename().string() + "' (" +
                                     error.message() + ")");
          }
      }
    catch (...)
      {
        release();
        throw;
      }
  }

  OutputFolder::~OutputFolder() { release(); }

  void OutputFolder::release()
  {
    if (lock_descriptor < 0)
      return;
    std::error_code error;
    fs::remove(lock_file, error);
    ::close(lock_descriptor);
    lock_descriptor = -1;
    if (created && is_empty_but_lock(folder))
      fs::remove(folder, error);
  }

  void prepare_output_file(const std::string &path, const std::string &option, bool force)
  {
    OutputPolicy policy;
    policy.option = option;
    if (path.empty())
      throw InputError("(command line)", option, "expected a file name, got ''");
    std::error_code error;
    const fs::path  file(path);
    if (fs::is_directory(file, error))
      refuse(policy, path, "is a folder; expected a file name");
    const fs::path parent = fs::absolute(file).parent_path();
    check_parent_chain(parent, path, policy);
    if (!force && fs::exists(file, error))
      {
        // A model file (HDF5) is fretsim's own to rebuild; anything else is kept.
        std::ifstream in(path, std::ios::binary);
        char          signature[8] = {};
        in.read(signature, sizeof signature);
        if (std::memcmp(signature, "\x89HDF\r\n\x1a\n", 8) != 0)
          refuse(policy, path, "exists and is not an HDF5 model file; expected a new file name, or --force");
      }
    fs::create_directories(parent, error);
    if (error)
      refuse(policy, path, "cannot create '" + parent.string() + "' (" + error.message() + ")");
  }

  double available_memory_bytes()
  {
    std::ifstream meminfo("/proc/meminfo");
    std::string   key;
    double        kilobytes = 0.0;
    std::string   unit;
    while (meminfo >> key >> kilobytes >> unit)
      if (key == "MemAvailable:")
        return 1024.0 * kilobytes;
    return std::numeric_limits<double>::infinity();
  }

  double free_disk_bytes(const std::string &path)
  {
    struct statvfs info;
    if (::statvfs(nearest_existing(path.empty() ? "." : path).c_str(), &info) != 0)
      return std::numeric_limits<double>::infinity();
    return static_cast<double>(info.f_bavail) * static_cast<double>(info.f_frsize);
  }

  std::string format_bytes(double bytes)
  {
    const char *units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
    int         unit    = 0;
    while (std::abs(bytes) >= 1000.0 && unit < 6)
      bytes /= 1000.0, ++unit;
    std::ostringstream out;
    out.precision(bytes < 10.0 ? 2 : 3);
    out << bytes << " " << units[unit];
    return out.str();
  }

  bool started_by_mpi_launcher()
  {
    for (const char *name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"})
      if (std::getenv(name) != nullptr)
        return true;
    return false;
  }

  int launcher_rank()
  {
    for (const char *name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
      if (const char *value = std::getenv(name))
        return std::atoi(value);
    return 0;
  }
} // namespace fretsim::app
