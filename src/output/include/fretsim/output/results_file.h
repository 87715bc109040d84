#pragma once
// results.h5 (docs/theory.md §6): grid, field snapshots and time series, flushed as
// the run goes so that a run that stops early leaves a readable file holding
// the steps done. HDF5 types stay inside results_file.cpp.
#include <memory>
#include <string>
#include <vector>

namespace fretsim::output
{
  class ResultsFile
  {
  public:
    /// Creates (truncates) the file. `parameters` is the full parameter set as
    /// text, stored as the root attribute "parameters"; `scene` as "scene".
    ResultsFile(const std::string &path, const std::string &scene, const std::string &parameters);
    ~ResultsFile(); // closes the file
    ResultsFile(const ResultsFile &) = delete;
    ResultsFile &operator=(const ResultsFile &) = delete;

    /// /grid/x [nx], /grid/y [ny], /grid/z [nz] (cell centres and depth layers, m).
    void write_grid(const std::vector<double> &x, const std::vector<double> &y,
                    const std::vector<double> &z);

    /// Declares /series/<name>, a 1-D dataset that grows by one value per
    /// append_series_row(). All series share one row count.
    void declare_series(const std::string &name, const std::string &unit);
    /// Appends one row: values in the order the series were declared.
    void append_series_row(const std::vector<double> &values);

    /// Declares /fields/<name> of shape [n_snapshots, dims...] growing along the
    /// first axis, and /time [n_snapshots] (s) shared by all declared fields.
    /// `compress`: deflated with shuffle (pays off for fields with zeros
    /// around the contact; dense stress fields shrink by little for the time
    /// deflate takes).
    void declare_field(const std::string &name, const std::string &unit,
                       const std::vector<std::size_t> &dims, bool compress = true);
    /// Appends one snapshot: /time gets `time`, each field gets its values
    /// (row-major, in declaration order, each of size prod(dims)).
    void append_snapshot(double time, const std::vector<const std::vector<double> *> &values);

    /// A fixed-size dataset written once, e.g. /fields/risk_max [nz, ny, nx].
    void write_dataset(const std::string &path, const std::string &unit,
                       const std::vector<std::size_t> &dims, const std::vector<double> &values);
    /// A string attribute on the root group (e.g. "status": "complete").
    void set_root_attribute(const std::string &name, const std::string &value);
    /// A floating-point attribute on the root group (e.g. "contact_radius_m").
    void set_root_attribute(const std::string &name, double value);

    /// Forces everything written so far to disk.
    void flush();

    std::size_t n_series_rows() const;
    std::size_t n_snapshots() const;

    /// Writes `<results>.xdmf` next to the file: the grid as a 2-D rectilinear
    /// mesh and one temporal collection over the snapshots, each [ny, nx] field
    /// (and each depth layer of 4-D fields) as a cell attribute, for ParaView.
    void write_xdmf(const std::string &xdmf_path) const;
    /// The same for an existing results file that is not open for writing
    /// (e.g. one left by a run that stopped): what the file holds is described.
    static void write_xdmf(const std::string &results_path, const std::string &xdmf_path);

    /// Readers for tests and tools (the file must not be open for writing in
    /// another process). read_dataset returns the values row-major as doubles
    /// and, if `dims` is given, the shape.
    static std::vector<double> read_dataset(const std::string &path, const std::string &dataset,
                                            std::vector<std::size_t> *dims = nullptr);
    /// A string attribute of `object` ("/" for the root), fixed or variable length.
    static std::string read_string_attribute(const std::string &path, const std::string &object,
                                             const std::string &name);
    static double      read_double_attribute(const std::string &path, const std::string &object,
                                             const std::string &name);

    /// True once a results file could not be closed (e.g. the disk is full).
    /// HDF5 (1.10) then retries at exit and may crash; a program that sees
    /// this ends without running the library's exit handlers.
    static bool file_left_open();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::output
