#pragma once
// Full-FE stress snapshots at sample points (docs/theory.md §3, §6): an HDF5 file
//   /points          [n_points, 3]               sample points, m
//   /time            [n_snapshots]               s
//   /fields/stress   [n_snapshots, n_points, 6]  Pa, Voigt order of the frame,
//                                                tension positive
// with root attributes "stress_frame" and "stress_components", flushed after
// every snapshot (a run that stops early leaves the snapshots done), and an
// XDMF sidecar that shows the points as a vertex cloud with one scalar per
// stress component and a temporal collection over the snapshots.
#include <fretsim/output/results_file.h>

#include <array>
#include <string>
#include <vector>

namespace fretsim::output
{
  class StressSnapshotFile
  {
  public:
    /// `frame` is "cartesian" (components xx yy zz yz xz xy) or "cylindrical"
    /// (rr tt zz tz rz rt about the z axis, t = θ).
    StressSnapshotFile(const std::string &path, const std::vector<std::array<double, 3>> &points,
                       const std::string &frame, const std::string &scene = "fem",
                       const std::string &parameters = "");

    /// One snapshot: `stress` row-major [n_points, 6] [Pa].
    void        append(double time, const std::vector<double> &stress);
    std::size_t n_snapshots() const { return file.n_snapshots(); }

    /// Writes the XDMF sidecar for the snapshots so far.
    void write_xdmf(const std::string &xdmf_path) const;

    static std::vector<std::string> component_names(const std::string &frame);

    /// The underlying results file, for datasets and attributes beside the
    /// snapshots (e.g. /frequencies of a modal run).
    ResultsFile &results() { return file; }

  private:
    std::string         path;
    std::size_t         n_points;
    std::string         frame;
    std::vector<double> times;
    ResultsFile         file;
  };
} // namespace fretsim::output
