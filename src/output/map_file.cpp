// map.h5 writer on the HDF5 C API. Layout: root attributes "scene",
// "definition" (what makes two maps the same map) and "axes"; /points/<name>
// one row per record: "index" (int64), "axis_values" [n, n_axes], one 1-D
// dataset per number, and "status", "message", "regime", "parameters"
// (variable-length strings).
//
// Crash safety: every change writes the whole file anew beside it
// (map.h5.part) and renames it over map.h5, so map.h5 is always a whole file,
// the last one or the one before, whenever the process is killed. (Appending
// in place and flushing is not enough: HDF5 writes a flush's metadata in no
// particular order, and a kill during one left a file whose chunk index
// pointed past its end.) A map's records are small and a point's run long:
// the rewrite costs milliseconds.
#include <fretsim/output/map_file.h>

#include "hdf5_handles.h"

#include <cmath>
#include <filesystem>
#include <limits>

namespace fretsim::output
{
  namespace
  {
    using namespace hdf5;

    const char *const text_columns[] = {"status", "message", "regime", "parameters"};

    /// A record's text column (`Record`: MapRecord or const MapRecord).
    template <class Record>
    auto &text_of(Record &record, int column)
    {
      switch (column)
        {
          case 0: return record.status;
          case 1: return record.message;
          case 2: return record.regime;
          default: return record.parameters;
        }
    }

    Handle string_type(const std::string &file)
    {
      Handle type = make(H5Tcopy(H5T_C_S1), H5Tclose, file, "", "cannot make a string type");
      check(H5Tset_size(type.get(), H5T_VARIABLE), file, "", "cannot make a string type");
      check(H5Tset_cset(type.get(), H5T_CSET_UTF8), file, "", "cannot make a string type");
      return type;
    }

    void write_string_attribute(hid_t object, const std::string &name, const std::string &value,
                                const std::string &file)
    {
      const Handle type  = string_type(file);
      const Handle space = make(H5Screate(H5S_SCALAR), H5Sclose, file, name, "cannot make a dataspace");
      const Handle attribute =
        make(H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose, file,
             name, "cannot create the attribute");
      const char *text = value.c_str();
      check(H5Awrite(attribute.get(), type.get(), &text), file, name, "cannot write the attribute");
    }

    std::string read_string_attribute(hid_t object, const std::string &name, const std::string &file)
    {
      if (H5Aexists(object, name.c_str()) <= 0)
        return "";
      const Handle attribute = make(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, file, name,
                                    "cannot open the attribute");
      const Handle type = string_type(file);
      char        *text = nullptr;
      check(H5Aread(attribute.get(), type.get(), &text), file, name, "cannot read the attribute");
      std::string value = text ? text : "";
      H5free_memory(text);
      return value;
    }

    /// A dataset of `rows` rows of `width` values of `type` (width 0: 1-D), written whole.
    void write_rows(hid_t group, const std::string &name, hid_t type, hsize_t rows, hsize_t width, const void *data,
                    const std::string &file)
    {
      const int     rank    = width == 0 ? 1 : 2;
      const hsize_t dims[2] = {rows, width};
      const Handle  space   = make(H5Screate_simple(rank, dims, nullptr), H5Sclose, file, name, "dataspace");
      const Handle  dataset = make(H5Dcreate2(group, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                                              H5P_DEFAULT),
                                   H5Dclose, file, name, "cannot create the dataset");
      if (rows > 0)
        check(H5Dwrite(dataset.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), file, name, "cannot write");
    }

    /// The whole dataset as rows of `width` values of `type` (1-D: width 1).
    template <typename T>
    std::vector<T> read_all(hid_t group, const std::string &name, hid_t type, const std::string &file)
    {
      const Handle dataset = make(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, file, name, "cannot open");
      const Handle space   = make(H5Dget_space(dataset.get()), H5Sclose, file, name, "dataspace");
      const hssize_t n     = check(H5Sget_simple_extent_npoints(space.get()), file, name, "dataspace");
      std::vector<T> values(static_cast<std::size_t>(n));
      if (n > 0)
        check(H5Dread(dataset.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), file, name,
              "cannot read the dataset");
      return values;
    }

    std::vector<std::string> split_lines(const std::string &text)
    {
      std::vector<std::string> lines;
      std::size_t              start = 0;
      while (start < text.size())
        {
          const auto end = text.find('\n', start);
          lines.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
          start = end == std::string::npos ? text.size() : end + 1;
        }
      return lines;
    }

    std::string join_lines(const std::vector<std::string> &lines)
    {
      std::string text;
      for (const auto &line : lines)
        text += line + "\n";
      return text;
    }
  } // namespace

  struct MapFile::Impl
  {
    std::string              path, scene, definition;
    std::vector<std::string> axis_names, number_names;
    /// The last /boundary (MapFile::write_boundary), written with every save.
    bool                     has_boundary = false;
    std::vector<double>      boundary_other_axes, boundary, bracket_low, bracket_high;

    /// The whole file, as `records` and the boundary make it, written to
    /// path.part and renamed over path.
    void save(const std::vector<MapRecord> &records) const;
  };

  void MapFile::Impl::save(const std::vector<MapRecord> &records) const
  {
    const QuietErrors quiet;
    const std::string part = path + ".part";
    {
      const Handle file = make(H5Fcreate(part.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, part, "",
                               "cannot create the file");
      const Handle root = make(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, part, "/", "cannot open");
      write_string_attribute(root.get(), "scene", scene, part);
      write_string_attribute(root.get(), "definition", definition, part);
      write_string_attribute(root.get(), "axes", join_lines(axis_names), part);
      write_string_attribute(root.get(), "numbers", join_lines(number_names), part);
      const Handle points = make(H5Gcreate2(file.get(), "/points", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                                 part, "/points", "cannot create the group");
      const hsize_t rows = records.size(), width = axis_names.size();
      std::vector<std::int64_t> index;
      std::vector<double>       axes;
      for (const auto &record : records)
        {
          index.push_back(record.index);
          std::vector<double> values = record.axis_values;
          values.resize(width, std::numeric_limits<double>::quiet_NaN());
          axes.insert(axes.end(), values.begin(), values.end());
        }
      write_rows(points.get(), "index", H5T_NATIVE_INT64, rows, 0, index.data(), part);
      write_rows(points.get(), "axis_values", H5T_NATIVE_DOUBLE, rows, width, axes.data(), part);
      for (const auto &name : number_names)
        {
          std::vector<double> column;
          for (const auto &record : records)
            {
              const auto found = record.numbers.find(name);
              column.push_back(found == record.numbers.end() ? std::numeric_limits<double>::quiet_NaN() : found->second);
            }
          write_rows(points.get(), name, H5T_NATIVE_DOUBLE, rows, 0, column.data(), part);
        }
      const Handle type = string_type(part);
      for (int column = 0; column < 4; ++column)
        {
          std::vector<const char *> texts;
          for (const auto &record : records)
            texts.push_back(text_of(record, column).c_str());
          write_rows(points.get(), text_columns[column], type.get(), rows, 0, texts.data(), part);
        }
      if (has_boundary)
        {
          const Handle group = make(H5Gcreate2(file.get(), "/boundary", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                    H5Gclose, part, "/boundary", "cannot create the group");
          const hsize_t lines = boundary.size(), others = width > 1 ? width - 1 : 0;
          const auto    write = [&](const std::string &name, const std::vector<double> &values, hsize_t columns) {
            const hsize_t dims[2] = {lines, columns};
            const Handle  space = make(H5Screate_simple(columns == 0 ? 1 : 2, dims, nullptr), H5Sclose, part, name,
                                       "dataspace");
            const Handle  dataset = make(H5Dcreate2(group.get(), name.c_str(), H5T_NATIVE_DOUBLE, space.get(),
                                                    H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                         H5Dclose, part, name, "cannot create the dataset");
            if (!values.empty())
              check(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), part,
                    name, "cannot write");
          };
          if (others > 0)
            write("other_axis_values", boundary_other_axes, others);
          write("first_axis_value", boundary, 0);
          write("bracket_low", bracket_low, 0);
          write("bracket_high", bracket_high, 0);
        }
    } // closed: on disk as far as the process goes
    std::error_code error;
    std::filesystem::rename(part, path, error);
    if (error)
      throw std::runtime_error("cannot replace '" + path + "' by '" + part + "': " + error.message());
  }

  MapFile::MapFile(const std::string &path, const std::string &scene, const std::string &definition,
                   const std::vector<std::string> &axis_names, const std::vector<std::string> &number_names)
    : impl(std::make_unique<Impl>())
  {
    const QuietErrors quiet;
    impl->path         = path;
    impl->scene        = scene;
    impl->definition   = definition;
    impl->axis_names   = axis_names;
    impl->number_names = number_names;
    if (std::filesystem::exists(path))
      {
        {
          const Handle file = make(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "",
                                   "cannot open");
          const Handle root = make(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "cannot open");
          const std::string held = read_string_attribute(root.get(), "definition", path);
          if (held != definition || read_string_attribute(root.get(), "scene", path) != scene)
            throw MapFileMismatch("'" + path + "' holds another map (other scene, parameters or axes)");
        }
        written = read(path);
        std::error_code ignored;
        std::filesystem::remove(path + ".part", ignored); // a save that was killed: map.h5 is the one before it
        return;
      }
    impl->save(written);
  }

  MapFile::~MapFile() = default;

  void MapFile::append(const MapRecord &record)
  {
    written.push_back(record);
    try
      {
        impl->save(written);
      }
    catch (...)
      {
        written.pop_back();
        throw;
      }
  }

  void MapFile::write_boundary(const std::vector<std::vector<double>> &line_values, const std::vector<double> &boundary,
                               const std::vector<double> &bracket_low, const std::vector<double> &bracket_high)
  {
    impl->has_boundary = true;
    impl->boundary_other_axes.clear();
    for (const auto &values : line_values)
      impl->boundary_other_axes.insert(impl->boundary_other_axes.end(), values.begin(), values.end());
    impl->boundary     = boundary;
    impl->bracket_low  = bracket_low;
    impl->bracket_high = bracket_high;
    impl->save(written);
  }

  std::vector<MapRecord> MapFile::read(const std::string &path)
  {
    const QuietErrors quiet;
    const Handle file   = make(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "", "cannot open");
    const Handle root   = make(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "cannot open");
    const Handle points = make(H5Gopen2(file.get(), "/points", H5P_DEFAULT), H5Gclose, path, "/points", "cannot open");
    const auto   axis_names   = split_lines(read_string_attribute(root.get(), "axes", path));
    const auto   number_names = split_lines(read_string_attribute(root.get(), "numbers", path));
    const auto   index = read_all<std::int64_t>(points.get(), "index", H5T_NATIVE_INT64, path);
    const auto   axes  = read_all<double>(points.get(), "axis_values", H5T_NATIVE_DOUBLE, path);
    // Only full rows count: the shortest column bounds them.
    std::size_t rows = index.size();
    std::vector<std::vector<double>> numbers;
    for (const auto &name : number_names)
      {
        numbers.push_back(read_all<double>(points.get(), name, H5T_NATIVE_DOUBLE, path));
        rows = std::min(rows, numbers.back().size());
      }
    std::vector<std::vector<std::string>> texts;
    const Handle type = string_type(path);
    for (const char *name : text_columns)
      {
        auto raw = read_all<char *>(points.get(), name, type.get(), path);
        std::vector<std::string> column;
        for (char *text : raw)
          {
            column.emplace_back(text ? text : "");
            H5free_memory(text);
          }
        rows = std::min(rows, column.size());
        texts.push_back(std::move(column));
      }
    const std::size_t      width = axis_names.size();
    rows = width > 0 ? std::min(rows, axes.size() / width) : rows;
    std::vector<MapRecord> records(rows);
    for (std::size_t r = 0; r < rows; ++r)
      {
        auto &record = records[r];
        record.index = static_cast<long>(index[r]);
        record.axis_values.assign(axes.begin() + r * width, axes.begin() + (r + 1) * width);
        for (std::size_t k = 0; k < number_names.size(); ++k)
          if (!std::isnan(numbers[k][r]))
            record.numbers[number_names[k]] = numbers[k][r];
        for (int column = 0; column < 4; ++column)
          text_of(record, column) = texts[column][r];
      }
    return records;
  }
} // namespace fretsim::output
