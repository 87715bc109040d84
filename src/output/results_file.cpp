// results.h5 writer (docs/theory.md §6) on the HDF5 C API, used serially with the
// default sec2 driver. Every call is checked; a failure throws
// std::runtime_error naming the file, the object and HDF5's own reason.
//
// Crash safety: datasets grow by one row per append and flush() writes the
// whole metadata cache, so a process killed after a flush leaves a file that
// opens with the rows flushed. The default (earliest) library version bounds
// keep the superblock at version 0, which has no "open for writing" flag that
// would stop readers opening a file that was never closed.
//
// Series are chunked by 1024 rows; field snapshots one per chunk, deflated
// (level 1, with shuffle) since each is written once and whole, unless the
// caller declares them uncompressed.
#include <fretsim/output/results_file.h>

#include "hdf5_handles.h"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace fretsim::output
{
  namespace
  {
    using namespace hdf5;

    /// Set once a file could not be closed: HDF5 would try again at exit.
    bool some_file_left_open = false;


    std::size_t product(const std::vector<std::size_t> &dims)
    {
      std::size_t n = 1;
      for (const std::size_t d : dims)
        n *= d;
      return n;
    }

    /// "/fields/risk_max" from "fields/risk_max" or "/fields//risk_max".
    std::string normalised_path(const std::string &path)
    {
      std::string result;
      std::string component;
      std::istringstream in(path);
      while (std::getline(in, component, '/'))
        if (!component.empty())
          {
            if (component == "." || component == "..")
              throw std::invalid_argument("results file: invalid dataset path '" + path + "'");
            result += "/" + component;
          }
      if (result.empty())
        throw std::invalid_argument("results file: empty dataset path '" + path + "'");
      return result;
    }

    void check_name(const std::string &name, const char *kind)
    {
      if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
        throw std::invalid_argument(std::string("results file: invalid ") + kind + " name '" + name + "'");
    }

    /// Whether an absolute path exists. H5Lexists fails when an intermediate
    /// group is missing, so the path is tested prefix by prefix.
    bool link_exists(hid_t file, const std::string &path, const std::string &file_name)
    {
      for (std::size_t end = path.find('/', 1);; end = path.find('/', end + 1))
        {
          const std::string prefix = path.substr(0, end);
          if (check(H5Lexists(file, prefix.c_str(), H5P_DEFAULT), file_name, prefix, "H5Lexists failed") <= 0)
            return false;
          if (end == std::string::npos)
            return true;
        }
    }

    Handle utf8_string_type(const std::string &file, const std::string &object)
    {
      Handle type = make(H5Tcopy(H5T_C_S1), H5Tclose, file, object, "H5Tcopy failed");
      check(H5Tset_size(type.get(), H5T_VARIABLE), file, object, "H5Tset_size failed");
      check(H5Tset_cset(type.get(), H5T_CSET_UTF8), file, object, "H5Tset_cset failed");
      return type;
    }

    void delete_attribute_if_present(hid_t object, const std::string &name, const std::string &file,
                                     const std::string &where)
    {
      if (check(H5Aexists(object, name.c_str()), file, where, "H5Aexists failed") > 0)
        check(H5Adelete(object, name.c_str()), file, where, "H5Adelete failed");
    }

    /// A variable-length UTF-8 string attribute (h5py reads it as str).
    void write_string_attribute(hid_t object, const std::string &name, const std::string &value,
                                const std::string &file, const std::string &object_name)
    {
      const std::string where = "attribute '" + name + "' of " + object_name;
      delete_attribute_if_present(object, name, file, where);
      Handle type      = utf8_string_type(file, where);
      Handle space     = make(H5Screate(H5S_SCALAR), H5Sclose, file, where, "H5Screate failed");
      Handle attribute = make(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                              H5Aclose, file, where, "H5Acreate2 failed");
      const char *text = value.c_str();
      check(H5Awrite(attribute.get(), type.get(), &text), file, where, "H5Awrite failed");
    }

    void write_double_attribute(hid_t object, const std::string &name, double value, const std::string &file,
                                const std::string &object_name)
    {
      const std::string where = "attribute '" + name + "' of " + object_name;
      delete_attribute_if_present(object, name, file, where);
      Handle space     = make(H5Screate(H5S_SCALAR), H5Sclose, file, where, "H5Screate failed");
      Handle attribute = make(H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                              H5Aclose, file, where, "H5Acreate2 failed");
      check(H5Awrite(attribute.get(), H5T_NATIVE_DOUBLE, &value), file, where, "H5Awrite failed");
    }

    /// Link creation that makes missing groups (/grid, /series, /fields) on demand.
    Handle intermediate_groups(const std::string &file)
    {
      Handle lcpl = make(H5Pcreate(H5P_LINK_CREATE), H5Pclose, file, "", "H5Pcreate failed");
      check(H5Pset_create_intermediate_group(lcpl.get(), 1), file, "", "H5Pset_create_intermediate_group failed");
      return lcpl;
    }

    Handle open_read_only(const std::string &path)
    {
      if (!std::filesystem::exists(path))
        throw std::runtime_error("results file '" + path + "': no such file");
      return make(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "", "cannot open for reading");
    }

    std::vector<hsize_t> dataset_dims(hid_t dataset, const std::string &file, const std::string &name,
                                      std::vector<hsize_t> *max_dims = nullptr)
    {
      Handle    space = make(H5Dget_space(dataset), H5Sclose, file, name, "H5Dget_space failed");
      const int rank  = check(H5Sget_simple_extent_ndims(space.get()), file, name, "H5Sget_simple_extent_ndims failed");
      std::vector<hsize_t> dims(rank), maxima(rank);
      check(H5Sget_simple_extent_dims(space.get(), dims.data(), maxima.data()), file, name,
            "H5Sget_simple_extent_dims failed");
      if (max_dims)
        *max_dims = maxima;
      return dims;
    }

    std::vector<double> read_all(hid_t file, const std::string &file_name, const std::string &name,
                                 std::vector<hsize_t> &dims)
    {
      Handle dataset = make(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose, file_name, "dataset " + name,
                            "cannot open dataset");
      dims           = dataset_dims(dataset.get(), file_name, "dataset " + name);
      hsize_t count  = 1;
      for (const hsize_t d : dims)
        count *= d;
      std::vector<double> values(count);
      if (count > 0)
        check(H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), file_name,
              "dataset " + name, "H5Dread failed");
      return values;
    }

    // ------------------------------------------------------------------ XDMF

    /// What the XDMF sidecar describes: the surface grid, the snapshot times,
    /// the time-dependent fields [nt, ..., ny, nx] and fixed ones [..., ny, nx].
    struct XdmfField
    {
      std::string          path; // "/fields/pressure"
      std::vector<hsize_t> dims; // without the time axis for time-dependent fields
    };
    struct XdmfDescription
    {
      std::string            h5_file; // as referenced from the XDMF
      std::vector<double>    x, y;    // cell centres
      std::vector<double>    times;
      std::vector<XdmfField> timed, fixed;
    };

    std::string xml_escape(const std::string &text)
    {
      std::string out;
      for (const char c : text)
        switch (c)
          {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
          }
      return out;
    }

    /// Shortest "%.Ng" text that reads back as the same double.
    std::string number(double value)
    {
      char buffer[32];
      for (int digits = 15; digits <= 17; ++digits)
        {
          std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
          if (std::strtod(buffer, nullptr) == value)
            break;
        }
      return buffer;
    }

    std::string joined(const std::vector<hsize_t> &values)
    {
      std::string text;
      for (std::size_t i = 0; i < values.size(); ++i)
        text += (i ? " " : "") + std::to_string(values[i]);
      return text;
    }

    /// Cell edges from uniformly spaced cell centres (one cell: unit width).
    std::vector<double> node_coordinates(const std::vector<double> &centres)
    {
      const std::size_t n       = centres.size();
      const double      spacing = n > 1 ? (centres[n - 1] - centres[0]) / static_cast<double>(n - 1) : 1.0;
      std::vector<double> nodes(n + 1);
      for (std::size_t i = 0; i <= n; ++i)
        nodes[i] = centres[0] + (static_cast<double>(i) - 0.5) * spacing;
      return nodes;
    }

    std::string data_item(const std::vector<double> &values, const std::string &indent)
    {
      std::string text = indent + "<DataItem Dimensions=\"" + std::to_string(values.size()) +
                         "\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">";
      for (std::size_t i = 0; i < values.size(); ++i)
        text += (i ? " " : "") + number(values[i]);
      return text + "</DataItem>\n";
    }

    /// Leaf name of "/fields/pressure".
    std::string leaf(const std::string &path) { return path.substr(path.rfind('/') + 1); }

    /// One cell attribute per [ny, nx] slice of a field (per depth layer of a
    /// [nz, ny, nx] field), selected from the dataset by a hyperslab. The
    /// selection's own shape is written as [ny, nx]: ParaView's XDMF 2 reader
    /// re-selects structured attributes by the grid's extents and needs a
    /// rank-2 shape for a 2-D mesh (a leading 1 would be read as the cell count
    /// along y).
    void write_slices(std::ostream &out, const XdmfDescription &d, const XdmfField &field, bool timed,
                      std::size_t snapshot, const std::string &indent)
    {
      const std::size_t rank = field.dims.size();
      if (rank < 2 || field.dims[rank - 2] != d.y.size() || field.dims[rank - 1] != d.x.size())
        return;
      std::vector<hsize_t> shape = field.dims;
      if (timed)
        shape.insert(shape.begin(), d.times.size());
      std::vector<hsize_t> layer_dims(field.dims.begin(), field.dims.end() - 2);
      const std::size_t    layers = std::max<std::size_t>(1, [&] {
        std::size_t n = 1;
        for (const hsize_t v : layer_dims)
          n *= v;
        return n;
      }());
      for (std::size_t layer = 0; layer < layers; ++layer)
        {
          // Index of this layer along each leading axis, and its name suffix.
          std::vector<hsize_t> index(layer_dims.size());
          std::size_t          rest = layer;
          for (std::size_t a = layer_dims.size(); a-- > 0;)
            index[a] = rest % layer_dims[a], rest /= layer_dims[a];
          std::string name = leaf(field.path);
          // A second axis of six is the Voigt axis of a stress field
          // [nz, 6, ny, nx]: name its components, e.g. stress_z0_xx.
          static const char *const voigt[] = {"xx", "yy", "zz", "yz", "xz", "xy"};
          for (std::size_t a = 0; a < index.size(); ++a)
            name += a == 0 ? "_z" + std::to_string(index[a]) :
                    a == 1 && layer_dims[a] == 6 ? "_" + std::string(voigt[index[a]]) :
                                                   "_" + std::to_string(index[a]);

          std::vector<hsize_t> start, stride(shape.size(), 1), count;
          if (timed)
            start.push_back(snapshot), count.push_back(1);
          for (const hsize_t i : index)
            start.push_back(i), count.push_back(1);
          start.push_back(0), start.push_back(0);
          count.push_back(d.y.size()), count.push_back(d.x.size());

          out << indent << "<Attribute Name=\"" << xml_escape(name) << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
              << indent << "  <DataItem ItemType=\"HyperSlab\" Type=\"HyperSlab\" Dimensions=\"" << d.y.size() << " "
              << d.x.size() << "\">\n"
              << indent << "    <DataItem Dimensions=\"3 " << shape.size() << "\" NumberType=\"Int\" Format=\"XML\">"
              << joined(start) << "  " << joined(stride) << "  " << joined(count) << "</DataItem>\n"
              << indent << "    <DataItem Dimensions=\"" << joined(shape)
              << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << xml_escape(d.h5_file) << ":"
              << xml_escape(field.path) << "</DataItem>\n"
              << indent << "  </DataItem>\n"
              << indent << "</Attribute>\n";
        }
    }

    void write_uniform_grid(std::ostream &out, const XdmfDescription &d, const std::string &name,
                            const double *time, std::size_t snapshot, const std::string &indent)
    {
      out << indent << "<Grid Name=\"" << name << "\" GridType=\"Uniform\">\n";
      if (time)
        out << indent << "  <Time Value=\"" << number(*time) << "\"/>\n";
      out << indent << "  <Topology TopologyType=\"2DRectMesh\" Dimensions=\"" << d.y.size() + 1 << " "
          << d.x.size() + 1 << "\"/>\n"
          << indent << "  <Geometry GeometryType=\"VXVY\">\n"
          << data_item(node_coordinates(d.x), indent + "    ") << data_item(node_coordinates(d.y), indent + "    ")
          << indent << "  </Geometry>\n";
      if (time)
        for (const auto &field : d.timed)
          write_slices(out, d, field, true, snapshot, indent + "  ");
      for (const auto &field : d.fixed)
        write_slices(out, d, field, false, 0, indent + "  ");
      out << indent << "</Grid>\n";
    }

    void write_xdmf_text(const XdmfDescription &d, const std::string &xdmf_path)
    {
      if (d.x.empty() || d.y.empty())
        throw std::runtime_error("XDMF file '" + xdmf_path + "': the results file '" + d.h5_file +
                                 "' has no surface grid (/grid/x, /grid/y)");
      std::ostringstream out;
      out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
          << "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
          << "<!-- FretSim results: surface grid x, y in m (cell edges), fields cell-centred, data in "
          << xml_escape(d.h5_file) << " -->\n"
          << "<Xdmf Version=\"3.0\">\n"
          << "  <Domain>\n";
      if (d.times.empty())
        write_uniform_grid(out, d, "surface", nullptr, 0, "    ");
      else
        {
          out << "    <Grid Name=\"surface\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
          for (std::size_t s = 0; s < d.times.size(); ++s)
            write_uniform_grid(out, d, "snapshot_" + std::to_string(s), &d.times[s], s, "      ");
          out << "    </Grid>\n";
        }
      out << "  </Domain>\n"
          << "</Xdmf>\n";

      const std::string temporary = xdmf_path + ".tmp";
      {
        std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
        file << out.str();
        file.close();
        if (!file)
          {
            std::remove(temporary.c_str());
            throw std::runtime_error("XDMF file '" + xdmf_path + "': cannot write '" + temporary + "'");
          }
      }
      if (std::rename(temporary.c_str(), xdmf_path.c_str()) != 0)
        {
          std::remove(temporary.c_str());
          throw std::runtime_error("XDMF file '" + xdmf_path + "': cannot rename '" + temporary + "'");
        }
    }

    /// The .h5 file name as seen from the XDMF file's folder.
    std::string relative_to_xdmf(const std::string &h5_path, const std::string &xdmf_path)
    {
      namespace fs = std::filesystem;
      std::error_code ec;
      const fs::path h5  = fs::absolute(h5_path, ec);
      const fs::path dir = fs::absolute(xdmf_path, ec).parent_path();
      if (!ec)
        {
          const fs::path relative = h5.lexically_normal().lexically_relative(dir.lexically_normal());
          if (!relative.empty())
            return relative.generic_string();
        }
      return h5_path;
    }

    /// Members of /fields: leaf name and whether it is a dataset.
    struct FieldIterationData
    {
      std::vector<std::pair<std::string, bool>> names;
    };

    herr_t collect_link(hid_t group, const char *name, const H5L_info_t *, void *client)
    {
      auto      &data    = *static_cast<FieldIterationData *>(client);
      bool       dataset = false;
      const hid_t object = H5Oopen(group, name, H5P_DEFAULT);
      if (object >= 0)
        {
          dataset = H5Iget_type(object) == H5I_DATASET;
          H5Oclose(object);
        }
      data.names.emplace_back(name, dataset);
      return 0;
    }
  } // namespace

  // ---------------------------------------------------------------- ResultsFile

  struct ResultsFile::Impl
  {
    /// One growing dataset: /series/<name> [rows] or /fields/<name> [rows, dims...].
    struct Growing
    {
      std::string          name; // full path
      std::vector<hsize_t> dims; // without the growing axis
      Handle               dataset;
    };

    std::string          path;
    Handle               file;
    Handle               row_space; // memory space for one series value
    std::vector<Growing> series;
    std::size_t          series_rows = 0;
    std::vector<Growing> fields;
    Growing              time{"/time", {}, Handle()};
    std::vector<double>  times;
    std::vector<double>  grid_x, grid_y;
    std::vector<XdmfField> fixed; // write_dataset() datasets under /fields

    /// Creates `name` [rows, dims...] growing along its first axis, filled with
    /// NaN where nothing was written (a series declared after rows exist).
    Handle create_growing(const std::string &name, const std::string &unit, const std::vector<hsize_t> &dims,
                          std::size_t rows, hsize_t chunk_rows, bool compress)
    {
      const std::string   object = "dataset " + name;
      std::vector<hsize_t> current{rows}, maximum{H5S_UNLIMITED}, chunk{chunk_rows};
      for (const hsize_t d : dims)
        current.push_back(d), maximum.push_back(d), chunk.push_back(d);
      // HDF5 limits a chunk to 4 GiB; keep it well below by splitting the
      // largest axis of a huge snapshot.
      auto chunk_bytes = [&] {
        hsize_t bytes = sizeof(double);
        for (const hsize_t c : chunk)
          bytes *= c;
        return bytes;
      };
      while (chunk_bytes() > (hsize_t(256) << 20))
        {
          auto largest = std::max_element(chunk.begin() + 1, chunk.end());
          *largest     = (*largest + 1) / 2;
        }

      Handle space = make(H5Screate_simple(static_cast<int>(current.size()), current.data(), maximum.data()),
                          H5Sclose, path, object, "H5Screate_simple failed");
      Handle dcpl  = make(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, path, object, "H5Pcreate failed");
      check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), path, object,
            "H5Pset_chunk failed");
      const double nan = std::numeric_limits<double>::quiet_NaN();
      check(H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &nan), path, object, "H5Pset_fill_value failed");
      if (compress && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0)
        {
          check(H5Pset_shuffle(dcpl.get()), path, object, "H5Pset_shuffle failed");
          check(H5Pset_deflate(dcpl.get(), 1), path, object, "H5Pset_deflate failed");
        }
      Handle lcpl    = intermediate_groups(path);
      Handle dataset = make(H5Dcreate2(file.get(), name.c_str(), H5T_IEEE_F64LE, space.get(), lcpl.get(), dcpl.get(),
                                       H5P_DEFAULT),
                            H5Dclose, path, object, "cannot create dataset");
      write_string_attribute(dataset.get(), "unit", unit, path, object);
      return dataset;
    }

    /// Grows `dataset` from `rows` to rows + 1 and writes `values` (prod(dims)) into the new row.
    void append_row(const Growing &target, std::size_t rows, const double *values)
    {
      const std::string   object = "dataset " + target.name;
      std::vector<hsize_t> extent{rows + 1}, start{rows}, count{1};
      for (const hsize_t d : target.dims)
        extent.push_back(d), start.push_back(0), count.push_back(d);
      check(H5Dset_extent(target.dataset.get(), extent.data()), path, object, "H5Dset_extent failed");
      Handle file_space = make(H5Dget_space(target.dataset.get()), H5Sclose, path, object, "H5Dget_space failed");
      check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr), path,
            object, "H5Sselect_hyperslab failed");
      Handle  own_space;
      hid_t   memory_space = row_space.get();
      if (!target.dims.empty())
        {
          own_space    = make(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose, path,
                              object, "H5Screate_simple failed");
          memory_space = own_space.get();
        }
      check(H5Dwrite(target.dataset.get(), H5T_NATIVE_DOUBLE, memory_space, file_space.get(), H5P_DEFAULT, values),
            path, object, "H5Dwrite failed");
    }

    bool has(const std::vector<Growing> &list, const std::string &name) const
    {
      return std::any_of(list.begin(), list.end(), [&](const Growing &g) { return g.name == name; });
    }
  };

  ResultsFile::ResultsFile(const std::string &path, const std::string &scene, const std::string &parameters)
    : impl(std::make_unique<Impl>())
  {
    QuietErrors quiet;
    impl->path = path;
    // Default file access: sec2 driver, earliest format bounds (see top).
    impl->file = make(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path, "",
                      "cannot create the file");
    const hsize_t one = 1;
    impl->row_space   = make(H5Screate_simple(1, &one, nullptr), H5Sclose, path, "", "H5Screate_simple failed");
    write_string_attribute(impl->file.get(), "scene", scene, path, "/");
    write_string_attribute(impl->file.get(), "parameters", parameters, path, "/");
    check(H5Fflush(impl->file.get(), H5F_SCOPE_GLOBAL), path, "", "H5Fflush failed");
  }

  ResultsFile::~ResultsFile()
  {
    if (!impl)
      return;
    QuietErrors quiet;
    bool        ok = true;
    for (auto &s : impl->series)
      ok = s.dataset.reset() && ok;
    for (auto &f : impl->fields)
      ok = f.dataset.reset() && ok;
    ok = impl->time.dataset.reset() && ok;
    ok = impl->row_space.reset() && ok;
    ok = impl->file.reset() && ok;
    // While an exception is on its way, its message already tells the failure.
    if (!ok && std::uncaught_exceptions() == 0)
      std::cerr << "fretsim: warning: closing results file '" << impl->path << "' failed: " << hdf5_reason() << "\n";
    some_file_left_open = some_file_left_open || !ok;
    H5Eclear2(H5E_DEFAULT);
  }

  bool ResultsFile::file_left_open() { return some_file_left_open; }

  void ResultsFile::write_grid(const std::vector<double> &x, const std::vector<double> &y,
                               const std::vector<double> &z)
  {
    write_dataset("/grid/x", "m", {x.size()}, x);
    write_dataset("/grid/y", "m", {y.size()}, y);
    write_dataset("/grid/z", "m", {z.size()}, z);
    impl->grid_x = x;
    impl->grid_y = y;
  }

  void ResultsFile::declare_series(const std::string &name, const std::string &unit)
  {
    QuietErrors quiet;
    check_name(name, "series");
    const std::string path = "/series/" + name;
    if (impl->has(impl->series, path))
      throw std::invalid_argument("results file '" + impl->path + "': series '" + name + "' declared twice");
    Handle dataset = impl->create_growing(path, unit, {}, impl->series_rows, 1024, false);
    impl->series.push_back({path, {}, std::move(dataset)});
  }

  void ResultsFile::append_series_row(const std::vector<double> &values)
  {
    if (values.size() != impl->series.size())
      throw std::invalid_argument("results file '" + impl->path + "': a series row has " +
                                  std::to_string(values.size()) + " values for " +
                                  std::to_string(impl->series.size()) + " declared series");
    QuietErrors quiet;
    for (std::size_t i = 0; i < values.size(); ++i)
      impl->append_row(impl->series[i], impl->series_rows, &values[i]);
    ++impl->series_rows;
  }

  void ResultsFile::declare_field(const std::string &name, const std::string &unit,
                                  const std::vector<std::size_t> &dims, bool compress)
  {
    QuietErrors quiet;
    check_name(name, "field");
    const std::string path = "/fields/" + name;
    if (impl->has(impl->fields, path))
      throw std::invalid_argument("results file '" + impl->path + "': field '" + name + "' declared twice");
    if (dims.empty() || std::find(dims.begin(), dims.end(), std::size_t(0)) != dims.end())
      throw std::invalid_argument("results file '" + impl->path + "': field '" + name +
                                  "' needs non-empty dimensions, each at least 1");
    if (!impl->time.dataset.valid())
      impl->time.dataset = impl->create_growing("/time", "s", {}, impl->times.size(), 1024, false);
    std::vector<hsize_t> field_dims(dims.begin(), dims.end());
    Handle dataset = impl->create_growing(path, unit, field_dims, impl->times.size(), 1, compress);
    impl->fields.push_back({path, field_dims, std::move(dataset)});
  }

  void ResultsFile::append_snapshot(double time, const std::vector<const std::vector<double> *> &values)
  {
    if (values.size() != impl->fields.size())
      throw std::invalid_argument("results file '" + impl->path + "': a snapshot has " +
                                  std::to_string(values.size()) + " fields for " +
                                  std::to_string(impl->fields.size()) + " declared fields");
    for (std::size_t i = 0; i < values.size(); ++i)
      {
        std::size_t expected = 1;
        for (const hsize_t d : impl->fields[i].dims)
          expected *= d;
        if (!values[i] || values[i]->size() != expected)
          throw std::invalid_argument("results file '" + impl->path + "': snapshot values for " +
                                      impl->fields[i].name + " have " +
                                      std::to_string(values[i] ? values[i]->size() : 0) + " entries, expected " +
                                      std::to_string(expected));
      }
    if (!impl->time.dataset.valid())
      throw std::logic_error("results file '" + impl->path + "': append_snapshot() before any declare_field()");
    QuietErrors       quiet;
    const std::size_t rows = impl->times.size();
    impl->append_row(impl->time, rows, &time);
    for (std::size_t i = 0; i < values.size(); ++i)
      impl->append_row(impl->fields[i], rows, values[i]->data());
    impl->times.push_back(time);
  }

  void ResultsFile::write_dataset(const std::string &path, const std::string &unit,
                                  const std::vector<std::size_t> &dims, const std::vector<double> &values)
  {
    const std::string name = normalised_path(path);
    if (product(dims) != values.size())
      throw std::invalid_argument("results file '" + impl->path + "': dataset " + name + " has " +
                                  std::to_string(values.size()) + " values for dimensions of " +
                                  std::to_string(product(dims)) + " entries");
    if (impl->has(impl->series, name) || impl->has(impl->fields, name) || name == "/time")
      throw std::invalid_argument("results file '" + impl->path + "': dataset " + name +
                                  " is a growing series or field");
    QuietErrors       quiet;
    const std::string object = "dataset " + name;
    hid_t             file   = impl->file.get();
    if (link_exists(file, name, impl->path))
      check(H5Ldelete(file, name.c_str(), H5P_DEFAULT), impl->path, object, "H5Ldelete failed");
    std::vector<hsize_t> shape(dims.begin(), dims.end());
    Handle               space =
      shape.empty() ? make(H5Screate(H5S_SCALAR), H5Sclose, impl->path, object, "H5Screate failed") :
                      make(H5Screate_simple(static_cast<int>(shape.size()), shape.data(), nullptr), H5Sclose,
                           impl->path, object, "H5Screate_simple failed");
    Handle lcpl    = intermediate_groups(impl->path);
    Handle dataset = make(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space.get(), lcpl.get(), H5P_DEFAULT,
                                     H5P_DEFAULT),
                          H5Dclose, impl->path, object, "cannot create dataset");
    if (!values.empty())
      check(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), impl->path,
            object, "H5Dwrite failed");
    write_string_attribute(dataset.get(), "unit", unit, impl->path, object);

    auto &fixed = impl->fixed;
    fixed.erase(std::remove_if(fixed.begin(), fixed.end(), [&](const XdmfField &f) { return f.path == name; }),
                fixed.end());
    if (name.rfind("/fields/", 0) == 0)
      fixed.push_back({name, shape});
  }

  void ResultsFile::set_root_attribute(const std::string &name, const std::string &value)
  {
    QuietErrors quiet;
    write_string_attribute(impl->file.get(), name, value, impl->path, "/");
  }

  void ResultsFile::set_root_attribute(const std::string &name, double value)
  {
    QuietErrors quiet;
    write_double_attribute(impl->file.get(), name, value, impl->path, "/");
  }

  void ResultsFile::flush()
  {
    QuietErrors quiet;
    check(H5Fflush(impl->file.get(), H5F_SCOPE_GLOBAL), impl->path, "", "H5Fflush failed");
  }

  std::size_t ResultsFile::n_series_rows() const { return impl->series_rows; }

  std::size_t ResultsFile::n_snapshots() const { return impl->times.size(); }

  void ResultsFile::write_xdmf(const std::string &xdmf_path) const
  {
    {
      QuietErrors quiet;
      check(H5Fflush(impl->file.get(), H5F_SCOPE_GLOBAL), impl->path, "", "H5Fflush failed");
    }
    XdmfDescription d;
    d.h5_file = relative_to_xdmf(impl->path, xdmf_path);
    d.x       = impl->grid_x;
    d.y       = impl->grid_y;
    d.times   = impl->times;
    for (const auto &field : impl->fields)
      d.timed.push_back({field.name, field.dims});
    d.fixed = impl->fixed;
    write_xdmf_text(d, xdmf_path);
  }

  void ResultsFile::write_xdmf(const std::string &results_path, const std::string &xdmf_path)
  {
    QuietErrors          quiet;
    Handle               file = open_read_only(results_path);
    std::vector<hsize_t> dims;
    XdmfDescription      d;
    d.h5_file = relative_to_xdmf(results_path, xdmf_path);
    if (link_exists(file.get(), "/grid/x", results_path) && link_exists(file.get(), "/grid/y", results_path))
      {
        d.x = read_all(file.get(), results_path, "/grid/x", dims);
        d.y = read_all(file.get(), results_path, "/grid/y", dims);
      }
    if (link_exists(file.get(), "/time", results_path))
      d.times = read_all(file.get(), results_path, "/time", dims);
    if (link_exists(file.get(), "/fields", results_path))
      {
        FieldIterationData data;
        check(H5Literate_by_name(file.get(), "/fields", H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_link, &data,
                                 H5P_DEFAULT),
              results_path, "group /fields", "H5Literate failed");
        std::size_t snapshots = d.times.size();
        std::vector<XdmfField> timed;
        for (const auto &[name, is_dataset] : data.names)
          {
            if (!is_dataset)
              continue;
            const std::string path    = "/fields/" + name;
            Handle            dataset = make(H5Dopen2(file.get(), path.c_str(), H5P_DEFAULT), H5Dclose, results_path,
                                             "dataset " + path, "cannot open dataset");
            std::vector<hsize_t> maxima;
            std::vector<hsize_t> shape = dataset_dims(dataset.get(), results_path, "dataset " + path, &maxima);
            if (!maxima.empty() && maxima[0] == H5S_UNLIMITED && shape.size() >= 3)
              {
                snapshots = std::min<std::size_t>(snapshots, shape[0]);
                timed.push_back({path, std::vector<hsize_t>(shape.begin() + 1, shape.end())});
              }
            else if (shape.size() >= 2)
              d.fixed.push_back({path, shape});
          }
        d.timed = timed;
        d.times.resize(snapshots); // a snapshot counts once every field has it
      }
    else
      d.times.clear();
    write_xdmf_text(d, xdmf_path);
  }

  std::vector<double> ResultsFile::read_dataset(const std::string &path, const std::string &dataset,
                                                std::vector<std::size_t> *dims)
  {
    QuietErrors          quiet;
    Handle               file = open_read_only(path);
    std::vector<hsize_t> shape;
    auto                 values = read_all(file.get(), path, normalised_path(dataset), shape);
    if (dims)
      dims->assign(shape.begin(), shape.end());
    return values;
  }

  std::string ResultsFile::read_string_attribute(const std::string &path, const std::string &object,
                                                 const std::string &name)
  {
    QuietErrors       quiet;
    Handle            file  = open_read_only(path);
    const std::string where = "attribute '" + name + "' of " + object;
    Handle attribute = make(H5Aopen_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                            H5Aclose, path, where, "cannot open attribute");
    Handle type = make(H5Aget_type(attribute.get()), H5Tclose, path, where, "H5Aget_type failed");
    if (H5Tget_class(type.get()) != H5T_STRING)
      fail(path, where, "not a string attribute");
    Handle space = make(H5Aget_space(attribute.get()), H5Sclose, path, where, "H5Aget_space failed");
    if (check(H5Sget_simple_extent_npoints(space.get()), path, where, "H5Sget_simple_extent_npoints failed") != 1)
      fail(path, where, "not a single string");
    const htri_t variable = check(H5Tis_variable_str(type.get()), path, where, "H5Tis_variable_str failed");
    if (variable > 0)
      {
        Handle memory_type = utf8_string_type(path, where);
        char  *text        = nullptr;
        check(H5Aread(attribute.get(), memory_type.get(), &text), path, where, "H5Aread failed");
        std::string value = text ? text : "";
        H5free_memory(text);
        return value;
      }
    const std::size_t size = H5Tget_size(type.get());
    std::string       value(size, '\0');
    if (size > 0)
      check(H5Aread(attribute.get(), type.get(), value.data()), path, where, "H5Aread failed");
    const auto end = value.find('\0');
    if (end != std::string::npos)
      value.resize(end);
    return value;
  }

  double ResultsFile::read_double_attribute(const std::string &path, const std::string &object,
                                            const std::string &name)
  {
    QuietErrors       quiet;
    Handle            file  = open_read_only(path);
    const std::string where = "attribute '" + name + "' of " + object;
    Handle attribute = make(H5Aopen_by_name(file.get(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                            H5Aclose, path, where, "cannot open attribute");
    Handle type = make(H5Aget_type(attribute.get()), H5Tclose, path, where, "H5Aget_type failed");
    const H5T_class_t type_class = H5Tget_class(type.get());
    if (type_class != H5T_FLOAT && type_class != H5T_INTEGER)
      fail(path, where, "not a number attribute");
    Handle space = make(H5Aget_space(attribute.get()), H5Sclose, path, where, "H5Aget_space failed");
    if (check(H5Sget_simple_extent_npoints(space.get()), path, where, "H5Sget_simple_extent_npoints failed") != 1)
      fail(path, where, "not a single number");
    double value = 0.0;
    check(H5Aread(attribute.get(), H5T_NATIVE_DOUBLE, &value), path, where, "H5Aread failed");
    return value;
  }
} // namespace fretsim::output
