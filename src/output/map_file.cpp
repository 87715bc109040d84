// map.h5 writer on the HDF5 C API. Layout: root attributes "scene",
// "definition" (what makes two maps the same map) and "axes"; /points/<name>
// one row per record: "index" (int64), "axis_values" [n, n_axes], one 1-D
// dataset per number, and "status", "message", "regime", "parameters"
// (variable-length strings). Rows are appended and the file flushed after
// each, as results.h5 does (results_file.cpp: crash safety).
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

    std::string &text_of(MapRecord &record, int column)
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

    /// A dataset of rows that grows along its first axis (width 0: 1-D).
    Handle create_rows(hid_t group, const std::string &name, hid_t type, hsize_t width, const std::string &file)
    {
      const int     rank          = width == 0 ? 1 : 2;
      const hsize_t dims[2]       = {0, width}, max_dims[2] = {H5S_UNLIMITED, width};
      const hsize_t chunk[2]      = {64, width == 0 ? 1 : width};
      const Handle  space         = make(H5Screate_simple(rank, dims, max_dims), H5Sclose, file, name, "dataspace");
      const Handle  properties    = make(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, file, name, "properties");
      check(H5Pset_chunk(properties.get(), rank, chunk), file, name, "cannot chunk");
      return make(H5Dcreate2(group, name.c_str(), type, space.get(), H5P_DEFAULT, properties.get(), H5P_DEFAULT),
                  H5Dclose, file, name, "cannot create the dataset");
    }

    /// Writes `data` (one row) at row `row`, growing the dataset by one.
    void append_row(hid_t group, const std::string &name, hid_t type, hsize_t row, hsize_t width, const void *data,
                    const std::string &file)
    {
      const Handle  dataset = make(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, file, name, "cannot open");
      const int     rank    = width == 0 ? 1 : 2;
      const hsize_t size[2] = {row + 1, width}, start[2] = {row, 0}, count[2] = {1, width == 0 ? 1 : width};
      check(H5Dset_extent(dataset.get(), size), file, name, "cannot grow the dataset");
      const Handle file_space = make(H5Dget_space(dataset.get()), H5Sclose, file, name, "dataspace");
      check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), file, name,
            "cannot select the row");
      const Handle memory = make(H5Screate_simple(rank, count, nullptr), H5Sclose, file, name, "dataspace");
      check(H5Dwrite(dataset.get(), type, memory.get(), file_space.get(), H5P_DEFAULT, data), file, name,
            "cannot write the row");
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
    std::string              path;
    Handle                   file, points;
    std::vector<std::string> axis_names, number_names;
  };

  MapFile::MapFile(const std::string &path, const std::string &scene, const std::string &definition,
                   const std::vector<std::string> &axis_names, const std::vector<std::string> &number_names)
    : impl(std::make_unique<Impl>())
  {
    const QuietErrors quiet;
    impl->path         = path;
    impl->axis_names   = axis_names;
    impl->number_names = number_names;
    if (std::filesystem::exists(path))
      {
        written = read(path);
        {
          const Handle file = make(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path, "",
                                   "cannot open");
          const Handle root = make(H5Gopen2(file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "cannot open");
          const std::string held = read_string_attribute(root.get(), "definition", path);
          if (held != definition || read_string_attribute(root.get(), "scene", path) != scene)
            throw MapFileMismatch("'" + path + "' holds another map (other scene, parameters or axes)");
        }
        impl->file   = make(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, path, "", "cannot open");
        impl->points = make(H5Gopen2(impl->file.get(), "/points", H5P_DEFAULT), H5Gclose, path, "/points",
                            "cannot open");
        return;
      }
    impl->file   = make(H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path, "",
                        "cannot create the file");
    const Handle root = make(H5Gopen2(impl->file.get(), "/", H5P_DEFAULT), H5Gclose, path, "/", "cannot open");
    write_string_attribute(root.get(), "scene", scene, path);
    write_string_attribute(root.get(), "definition", definition, path);
    write_string_attribute(root.get(), "axes", join_lines(axis_names), path);
    write_string_attribute(root.get(), "numbers", join_lines(number_names), path);
    impl->points = make(H5Gcreate2(impl->file.get(), "/points", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                        path, "/points", "cannot create the group");
    const hid_t group = impl->points.get();
    create_rows(group, "index", H5T_NATIVE_INT64, 0, path);
    create_rows(group, "axis_values", H5T_NATIVE_DOUBLE, axis_names.size(), path);
    for (const auto &name : number_names)
      create_rows(group, name, H5T_NATIVE_DOUBLE, 0, path);
    const Handle type = string_type(path);
    for (const char *name : text_columns)
      create_rows(group, name, type.get(), 0, path);
    check(H5Fflush(impl->file.get(), H5F_SCOPE_GLOBAL), path, "", "cannot flush");
  }

  MapFile::~MapFile() = default;

  void MapFile::append(const MapRecord &record)
  {
    const QuietErrors  quiet;
    const std::string &path  = impl->path;
    const hid_t        group = impl->points.get();
    const hsize_t      row   = written.size();
    const std::int64_t index = record.index;
    append_row(group, "index", H5T_NATIVE_INT64, row, 0, &index, path);
    std::vector<double> axes = record.axis_values;
    axes.resize(impl->axis_names.size(), std::numeric_limits<double>::quiet_NaN());
    append_row(group, "axis_values", H5T_NATIVE_DOUBLE, row, axes.size(), axes.data(), path);
    for (const auto &name : impl->number_names)
      {
        const auto   found = record.numbers.find(name);
        const double value = found == record.numbers.end() ? std::numeric_limits<double>::quiet_NaN() : found->second;
        append_row(group, name, H5T_NATIVE_DOUBLE, row, 0, &value, path);
      }
    const Handle type = string_type(path);
    MapRecord    copy = record;
    for (int column = 0; column < 4; ++column)
      {
        const char *text = text_of(copy, column).c_str();
        append_row(group, text_columns[column], type.get(), row, 0, &text, path);
      }
    check(H5Fflush(impl->file.get(), H5F_SCOPE_GLOBAL), path, "", "cannot flush");
    written.push_back(record);
  }

  void MapFile::write_boundary(const std::vector<std::vector<double>> &line_values, const std::vector<double> &boundary,
                               const std::vector<double> &bracket_low, const std::vector<double> &bracket_high)
  {
    const QuietErrors  quiet;
    const std::string &path = impl->path;
    const hid_t        file = impl->file.get();
    if (H5Lexists(file, "/boundary", H5P_DEFAULT) > 0)
      check(H5Ldelete(file, "/boundary", H5P_DEFAULT), path, "/boundary", "cannot replace");
    const Handle group = make(H5Gcreate2(file, "/boundary", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, path,
                              "/boundary", "cannot create the group");
    const hsize_t lines = boundary.size();
    const auto    write = [&](const std::string &name, const std::vector<double> &values, hsize_t width) {
      const hsize_t dims[2] = {lines, width};
      const Handle  space   = make(H5Screate_simple(width == 0 ? 1 : 2, dims, nullptr), H5Sclose, path, name, "dataspace");
      const Handle  dataset = make(H5Dcreate2(group.get(), name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                                              H5P_DEFAULT, H5P_DEFAULT),
                                   H5Dclose, path, name, "cannot create the dataset");
      if (!values.empty())
        check(H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), path, name,
              "cannot write");
    };
    const hsize_t       others = impl->axis_names.size() > 1 ? impl->axis_names.size() - 1 : 0;
    std::vector<double> flat;
    for (const auto &values : line_values)
      flat.insert(flat.end(), values.begin(), values.end());
    if (others > 0)
      write("other_axis_values", flat, others);
    write("first_axis_value", boundary, 0);
    write("bracket_low", bracket_low, 0);
    write("bracket_high", bracket_high, 0);
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), path, "", "cannot flush");
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
    // A record is complete once its last column is written: a map killed
    // inside an append leaves shorter columns, and only full rows count.
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
