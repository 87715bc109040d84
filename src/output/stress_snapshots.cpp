#include <fretsim/output/stress_snapshots.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace fretsim::output
{
  std::vector<std::string> StressSnapshotFile::component_names(const std::string &frame)
  {
    if (frame == "cartesian")
      return {"xx", "yy", "zz", "yz", "xz", "xy"};
    if (frame == "cylindrical")
      return {"rr", "tt", "zz", "tz", "rz", "rt"};
    throw std::invalid_argument("stress snapshots: unknown frame '" + frame + "' (cartesian or cylindrical)");
  }

  StressSnapshotFile::StressSnapshotFile(const std::string &path_in, const std::vector<std::array<double, 3>> &points,
                                         const std::string &frame_in, const std::string &scene,
                                         const std::string &parameters)
    : path(path_in)
    , n_points(points.size())
    , frame(frame_in)
    , file(path_in, scene, parameters)
  {
    std::string components;
    for (const auto &c : component_names(frame))
      components += (components.empty() ? "" : " ") + c;
    if (n_points == 0)
      throw std::invalid_argument("stress snapshots '" + path + "': no sample points");
    std::vector<double> xyz;
    xyz.reserve(3 * n_points);
    for (const auto &p : points)
      xyz.insert(xyz.end(), p.begin(), p.end());
    file.write_dataset("/points", "m", {n_points, 3}, xyz);
    file.set_root_attribute("stress_frame", frame);
    file.set_root_attribute("stress_components", components);
    file.declare_field("stress", "Pa", {n_points, 6});
    file.flush();
  }

  void StressSnapshotFile::append(const double time, const std::vector<double> &stress)
  {
    file.append_snapshot(time, {&stress});
    times.push_back(time);
    file.flush();
  }

  void StressSnapshotFile::write_xdmf(const std::string &xdmf_path) const
  {
    const std::string h5 = std::filesystem::relative(std::filesystem::absolute(path),
                                                     std::filesystem::absolute(xdmf_path).parent_path())
                             .string();
    const auto    names = component_names(frame);
    std::ofstream out(xdmf_path);
    out << std::setprecision(17)
        << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
           "<Grid Name=\"stress_snapshots\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (std::size_t s = 0; s < times.size(); ++s)
      {
        out << "  <Grid Name=\"snapshot_" << s << "\" GridType=\"Uniform\">\n"
            << "    <Time Value=\"" << times[s] << "\"/>\n"
            << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n_points
            << "\" NodesPerElement=\"1\"/>\n"
            << "    <Geometry GeometryType=\"XYZ\">\n      <DataItem Dimensions=\"" << n_points
            << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/points</DataItem>\n"
            << "    </Geometry>\n";
        for (std::size_t c = 0; c < 6; ++c)
          out << "    <Attribute Name=\"stress_" << names[c] << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
              << "      <DataItem ItemType=\"HyperSlab\" Dimensions=\"" << n_points << "\">\n"
              << "        <DataItem Dimensions=\"3 3\" NumberType=\"Int\" Format=\"XML\">" << s << " 0 " << c
              << "  1 1 1  1 " << n_points << " 1</DataItem>\n"
              << "        <DataItem Dimensions=\"" << times.size() << " " << n_points
              << " 6\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/fields/stress</DataItem>\n"
              << "      </DataItem>\n    </Attribute>\n";
        out << "  </Grid>\n";
      }
    out << "</Grid>\n</Domain>\n</Xdmf>\n";
    if (!out)
      throw std::runtime_error("cannot write " + xdmf_path);
  }
} // namespace fretsim::output
