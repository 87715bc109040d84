#include <fretsim/fem/elastic_model.h>
#include <fretsim/models/reduction.h>
#include <fretsim/models/ring_housing.h>
#include <fretsim/models/ring_stress.h>
#include <fretsim/output/results_file.h>
#include <fretsim/reduction/reduced_model.h>

#include "table_convolution.h"

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace fretsim::models
{
  struct RingStressTable::Impl
  {
    InterfaceInfluence                                       tables;
    std::vector<std::unique_ptr<detail::StackedConvolution>> layers; ///< per depth layer
    mutable detail::Vector                                   load, field;

    explicit Impl(InterfaceInfluence tables_in)
      : tables(std::move(tables_in))
    {
      const auto &t     = tables;
      const int   nx    = t.grid.nx, ny = t.grid.ny;
      const auto  cells = t.cells();
      if (t.layers() == 0 || t.stress.size() != static_cast<std::size_t>(t.period) * 3 * ny * t.layers() * cells * 6 ||
          t.ball_stress.size() != t.ball_footprints() * static_cast<std::size_t>(t.period) * t.layers() * cells * 6)
        throw std::invalid_argument("models::RingStressTable: tables without stresses on their layers or a ball table");
      const double area = t.grid.cell_area();
      // Rows 3 ny .. 6 ny of the load are empty: one square kernel for the
      // tractions' three components in and the six stress components out.
      for (std::size_t layer = 0; layer < t.layers(); ++layer)
        layers.push_back(std::make_unique<detail::StackedConvolution>(
          nx, 6 * ny, t.period, [this, layer, nx, ny, area](int ph, int b_row, int i, int a_row) {
            const int k = b_row / ny, b = b_row % ny, c = a_row / ny, a = a_row % ny;
            if (k >= 3)
              return 0.0;
            const std::size_t cell = static_cast<std::size_t>(a) * nx + i; // i: the column, the load on column ph
            return area * tables.stress[tables.stress_index(ph, k, b, layer, cell, c)];
          }));
    }
  };

  RingStressTable::RingStressTable(InterfaceInfluence tables)
    : impl(std::make_unique<Impl>(std::move(tables)))
  {}
  RingStressTable::~RingStressTable()                          = default;
  RingStressTable::RingStressTable(RingStressTable &&) noexcept = default;

  const InterfaceInfluence &RingStressTable::tables() const { return impl->tables; }

  void RingStressTable::evaluate(const std::vector<double> &ball_angles, const std::vector<double> &ball_loads,
                                 const std::vector<double> &pressure, const std::vector<double> &shear_x,
                                 const std::vector<double> &shear_y, std::vector<double> &stress) const
  {
    const Impl       &m     = *impl;
    const auto       &t     = m.tables;
    const std::size_t cells = t.cells(), layers = t.layers();
    if (pressure.size() != cells || shear_x.size() != cells || shear_y.size() != cells ||
        ball_angles.size() != ball_loads.size())
      throw std::invalid_argument("models::RingStressTable: tractions off the grid or balls without loads");
    m.load.assign(6 * cells, 0.0);
    std::copy(pressure.begin(), pressure.end(), m.load.begin());
    std::copy(shear_x.begin(), shear_x.end(), m.load.begin() + static_cast<std::ptrdiff_t>(cells));
    std::copy(shear_y.begin(), shear_y.end(), m.load.begin() + static_cast<std::ptrdiff_t>(2 * cells));
    stress.assign(layers * 6 * cells, 0.0);
    for (std::size_t layer = 0; layer < layers; ++layer)
      {
        m.layers[layer]->apply(m.load, m.field);
        std::copy(m.field.begin(), m.field.end(), stress.begin() + static_cast<std::ptrdiff_t>(layer * 6 * cells));
      }
    for (std::size_t b = 0; b < ball_angles.size(); ++b)
      if (ball_loads[b] != 0.0)
        detail::add_ball_tables(t.grid, t.period, t.ball_footprint_loads, ball_angles[b], ball_loads[b], t.ball_stress, 6,
                                layers,
                               [&](std::size_t point, int comp, double value) {
                                 const std::size_t layer = point / cells, cell = point % cells;
                                 stress[(layer * 6 + static_cast<std::size_t>(comp)) * cells + cell] += value;
                               });
  }

  InterfaceInfluence ring_influence(const RingHousingRequest &ring_in, const std::string &config_file,
                                    const reduction::ReducedModel &model, const fem::MeshDivisions &divisions,
                                    const std::vector<double> &depths, int points_per_side)
  {
    RingHousingRequest ring = ring_in;
    ring.bodies             = "ring";
    ring.gmsh_file.clear(); // the tables' mesh is the parametric one of `divisions`
    ring.divisions          = divisions;
    ring.refinements        = 0;
    auto mesh = std::make_shared<const fem::Mesh>(build_ring_housing_mesh(ring, config_file));
    fem::ElasticModel fe(mesh, ring.materials, ring.degree);
    InfluenceRequest  request;
    request.support               = InfluenceSupport::free_ring;
    request.circumferential_cells = divisions.circumferential;
    request.depths                = depths;
    request.points_per_side       = points_per_side;
    request.ball_footprint_loads  = model.raceway.footprint_loads();
    request.balls                 = [&](double angle) {
      std::vector<fem::RacewayBallLoad> balls;
      for (const reduction::BallFootprint &footprint : model.raceway.footprints)
        {
          balls.push_back(reduction::unit_ball(ring.ring, angle, footprint));
          balls.back().contact_angle = model.raceway.contact_angle;
        }
      return balls;
    };
    return interface_influence(fe, model.interface_grid.grid, request);
  }

  std::string ring_stress_hash(const RingStressSource &source)
  {
    std::ostringstream text;
    const auto        &d = source.divisions;
    text << std::setprecision(17) << "ring stress tables 3\n"
         << reduce_input_hash(source.config, source.footprint_overrides) << '\n'
         << d.circumferential << ' ' << d.radial_ring << ' ' << d.axial << ' ' << d.axial_land << ' '
         << d.radial_grading << '\n'
         << source.points_per_side << '\n';
    for (const double z : source.depths)
      text << z << ' ';
    return reduction::fingerprint(text.str());
  }

  namespace
  {
    constexpr const char *format_name = "fretsim ring stress tables";
  }

  void write_ring_stress_file(const std::string &path, const InterfaceInfluence &t, const std::string &hash)
  {
    // Written beside and renamed over: an interrupted write leaves no half file.
    const std::string temporary = path + "." + std::to_string(::getpid()) + ".tmp";
    try
      {
        {
          output::ResultsFile file(temporary, format_name, "");
          file.set_root_attribute("input_hash", hash);
          const fem::CylinderGrid &g = t.grid;
          for (const auto &[name, value] : {std::pair<const char *, double>{"radius_m", g.radius},
                                            {"nx", g.nx},
                                            {"ny", g.ny},
                                            {"hx_m", g.hx},
                                            {"hy_m", g.hy},
                                            {"x_min_m", g.x_min},
                                            {"y_min_m", g.y_min},
                                            {"period", t.period},
                                            {"dofs", static_cast<double>(t.dofs)},
                                            {"solves", t.solves},
                                            {"seconds", t.seconds}})
            file.set_root_attribute(name, value);
          const std::size_t P = static_cast<std::size_t>(t.period), cells = t.cells(), layers = t.layers();
          file.write_dataset("/depths", "m", {layers}, t.depths);
          file.write_dataset("/stress", "Pa/N", {P, 3, static_cast<std::size_t>(g.ny), layers, cells, 6}, t.stress);
          file.write_dataset("/ball_stress", "Pa/N", {t.ball_footprints(), P, layers, cells, 6}, t.ball_stress);
          file.write_dataset("/ball_footprint_loads", "N", {t.ball_footprint_loads.size()}, t.ball_footprint_loads);
        }
        std::filesystem::rename(temporary, path);
      }
    catch (const std::exception &)
      {
        std::remove(temporary.c_str());
        throw;
      }
  }

  InterfaceInfluence read_ring_stress_file(const std::string &path, const std::string &expected_hash)
  {
    using output::ResultsFile;
    if (!std::filesystem::is_regular_file(path))
      throw std::runtime_error("ring stress tables '" + path + "' do not exist");
    InterfaceInfluence t;
    try
      {
        if (ResultsFile::read_string_attribute(path, "/", "scene") != format_name)
          throw std::runtime_error("not ring stress tables");
        const std::string hash = ResultsFile::read_string_attribute(path, "/", "input_hash");
        if (hash != expected_hash)
          throw std::runtime_error("made from other inputs (input hash " + hash + ", expected " + expected_hash + ")");
        const auto number = [&](const char *name) { return ResultsFile::read_double_attribute(path, "/", name); };
        t.grid.radius = number("radius_m");
        t.grid.nx     = static_cast<int>(number("nx"));
        t.grid.ny     = static_cast<int>(number("ny"));
        t.grid.hx     = number("hx_m");
        t.grid.hy     = number("hy_m");
        t.grid.x_min  = number("x_min_m");
        t.grid.y_min  = number("y_min_m");
        t.period      = static_cast<int>(number("period"));
        t.dofs        = static_cast<unsigned long>(number("dofs"));
        t.solves      = static_cast<unsigned int>(number("solves"));
        t.seconds     = number("seconds");
        t.depths      = ResultsFile::read_dataset(path, "/depths");
        t.stress      = ResultsFile::read_dataset(path, "/stress");
        t.ball_stress = ResultsFile::read_dataset(path, "/ball_stress");
        t.ball_footprint_loads = ResultsFile::read_dataset(path, "/ball_footprint_loads");
      }
    catch (const std::exception &error)
      {
        throw std::runtime_error("ring stress tables '" + path + "': " + error.what());
      }
    return t;
  }
} // namespace fretsim::models
