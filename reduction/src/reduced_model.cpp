// Model file (HDF5) and modal operators of a reduced model.
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/reduction/reduced_model.h>

#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <sstream>

namespace fretsim::reduction
{
  ModelFileError::ModelFileError(const std::string &file, const std::string &problem)
    : std::runtime_error("model file '" + file + "': " + problem)
  {}

  std::string fingerprint(const std::string &text)
  {
    std::uint64_t hash = 14695981039346656037ull;
    for (const unsigned char c : text)
      {
        hash ^= c;
        hash *= 1099511628211ull;
      }
    std::ostringstream out;
    out << std::hex << std::setw(16) << std::setfill('0') << hash;
    return out.str();
  }

  namespace
  {
    constexpr const char *format_name    = "fretsim reduced model";
    // 2: the ring's residual flexibility; 3: the housing's; 4: raceway footprints that follow the ball load (older
    // files: rebuilt)
    constexpr int format_version = 4;

    /// An HDF5 id closed on scope exit.
    class Id
    {
    public:
      Id(hid_t id, herr_t (*close)(hid_t))
        : id(id)
        , close(close)
      {}
      ~Id()
      {
        if (id >= 0)
          close(id);
      }
      Id(const Id &)            = delete;
      Id &operator=(const Id &) = delete;
      operator hid_t() const { return id; }
      bool valid() const { return id >= 0; }

    private:
      hid_t id;
      herr_t (*close)(hid_t);
    };

    void write_array(hid_t file, const std::string &name, const std::vector<hsize_t> &dims,
                     const std::vector<double> &values)
    {
      hsize_t count = 1;
      for (const hsize_t d : dims)
        count *= d;
      if (count != values.size())
        throw std::logic_error("model file: dataset " + name + " has the wrong size");
      Id lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
      H5Pset_create_intermediate_group(lcpl, 1);
      Id space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
      Id set(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
      if (!set.valid() || (count > 0 && H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                                                 values.data()) < 0))
        throw std::runtime_error("cannot write dataset " + name);
    }

    void write_string_attribute(hid_t object, const std::string &name, const std::string &value)
    {
      Id type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(type, std::max<std::size_t>(1, value.size()));
      Id space(H5Screate(H5S_SCALAR), H5Sclose);
      Id attribute(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      if (!attribute.valid() || H5Awrite(attribute, type, value.empty() ? " " : value.c_str()) < 0)
        throw std::runtime_error("cannot write attribute " + name);
    }

    void write_number_attribute(hid_t object, const std::string &name, const double value)
    {
      Id space(H5Screate(H5S_SCALAR), H5Sclose);
      Id attribute(H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      if (!attribute.valid() || H5Awrite(attribute, H5T_NATIVE_DOUBLE, &value) < 0)
        throw std::runtime_error("cannot write attribute " + name);
    }

    std::vector<double> read_array(hid_t file, const std::string &name, std::vector<hsize_t> &dims)
    {
      Id set(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose);
      if (!set.valid())
        throw std::runtime_error("dataset " + name + " is missing");
      Id        space(H5Dget_space(set), H5Sclose);
      const int rank = H5Sget_simple_extent_ndims(space);
      dims.assign(static_cast<std::size_t>(std::max(rank, 0)), 0);
      H5Sget_simple_extent_dims(space, dims.data(), nullptr);
      hsize_t count = 1;
      for (const hsize_t d : dims)
        count *= d;
      std::vector<double> values(count);
      if (count > 0 && H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
        throw std::runtime_error("dataset " + name + " cannot be read (truncated file?)");
      return values;
    }

    std::vector<double> read_array(hid_t file, const std::string &name)
    {
      std::vector<hsize_t> dims;
      return read_array(file, name, dims);
    }

    std::string read_string_attribute(hid_t object, const std::string &name)
    {
      if (H5Aexists(object, name.c_str()) <= 0)
        throw std::runtime_error("attribute " + name + " is missing");
      Id          attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
      Id          type(H5Aget_type(attribute), H5Tclose);
      std::string value(H5Tget_size(type), '\0');
      Id          memory_type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(memory_type, value.size());
      if (H5Aread(attribute, memory_type, value.data()) < 0)
        throw std::runtime_error("attribute " + name + " cannot be read");
      return value.substr(0, value.find('\0'));
    }

    double read_number_attribute(hid_t object, const std::string &name)
    {
      if (H5Aexists(object, name.c_str()) <= 0)
        throw std::runtime_error("attribute " + name + " is missing");
      Id     attribute(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
      double value = 0.0;
      if (H5Aread(attribute, H5T_NATIVE_DOUBLE, &value) < 0)
        throw std::runtime_error("attribute " + name + " cannot be read");
      return value;
    }

    /// Timings as name → seconds, in one place for writing and reading.
    std::vector<std::pair<std::string, double *>> timing_fields(ReductionTimings &t)
    {
      return {{"partition", &t.partition},
              {"factorisation", &t.factorisation},
              {"fixed_interface_modes", &t.fixed_interface_modes},
              {"interface_modes", &t.interface_modes},
              {"constraint_modes", &t.constraint_modes},
              {"reduced_matrices", &t.reduced_matrices},
              {"total", &t.total}};
    }

    /// The operator [item][components][n] of `fields`: for basis field j,
    /// `evaluate(j)` returns the [item][components] values.
    std::vector<double> assemble_operator(const CraigBampton &basis, std::size_t n_items, std::size_t n_components,
                                          const std::function<std::vector<double>(const fem::DisplacementField &)> &evaluate)
    {
      const std::size_t   n = basis.size();
      std::vector<double> result(n_items * n_components * n);
      for (std::size_t j = 0; j < n; ++j)
        {
          const std::vector<double> values = evaluate(basis.basis_field(static_cast<unsigned int>(j)));
          for (std::size_t item = 0; item < n_items * n_components; ++item)
            result[item * n + j] = values[item];
        }
      return result;
    }
  } // namespace

  GridOperators grid_operators(const CraigBampton &basis, const fem::ElasticModel &model, const fem::BoundaryId surface,
                               const fem::CylinderGrid &grid)
  {
    GridOperators           result;
    result.grid = grid;
    const fem::SurfaceGridMap map(model, surface, grid);
    result.displacement = assemble_operator(basis, grid.size(), 3, [&](const fem::DisplacementField &u) {
      const fem::GridDisplacements d = map.interpolate(u);
      std::vector<double>          values(3 * grid.size());
      for (std::size_t c = 0; c < grid.size(); ++c)
        {
          values[3 * c]     = d.u_r[c];
          values[3 * c + 1] = d.u_theta[c];
          values[3 * c + 2] = d.u_z[c];
        }
      return values;
    });
    const fem::StressSampler sampler = fem::StressSampler::on_grid(model, grid, fem::StressFrame::cylindrical);
    result.stress = assemble_operator(basis, grid.size(), 6, [&](const fem::DisplacementField &u) { return sampler.evaluate(u); });
    return result;
  }

  PointOperators point_operators(const CraigBampton &basis, const fem::ElasticModel &model,
                                 const std::vector<fem::Point3> &points)
  {
    PointOperators result;
    result.points = points;
    if (points.empty())
      return result;
    const fem::StressSampler sampler(model, points, fem::StressFrame::cylindrical);
    result.stress = assemble_operator(basis, points.size(), 6, [&](const fem::DisplacementField &u) { return sampler.evaluate(u); });
    return result;
  }

  std::vector<double> RacewayOperators::footprint_loads() const
  {
    std::vector<double> loads;
    if (follows_load())
      for (const BallFootprint &f : footprints)
        loads.push_back(f.load);
    return loads;
  }

  BallFootprint RacewayOperators::footprint_at(const double load) const
  {
    if (footprints.empty())
      throw std::logic_error("reduction::RacewayOperators: no footprint");
    BallFootprint f = footprints.back();
    if (!follows_load())
      return f;
    if (!(load > 0.0)) // no ellipse: the smallest footprint stands for it
      return footprints.front();
    const double scale = std::cbrt(load / f.load);
    return {scale * f.semi_axis_circumferential, scale * f.semi_axis_transverse, load};
  }

  void check_footprints(const std::vector<BallFootprint> &footprints)
  {
    const auto fail = [](const std::string &problem) { throw std::invalid_argument(problem); };
    if (footprints.empty())
      fail("no footprint");
    for (const BallFootprint &f : footprints)
      if (!(f.semi_axis_circumferential > 0.0 && f.semi_axis_transverse > 0.0 && f.load >= 0.0))
        fail("footprint semi-axes must be > 0 and loads >= 0");
    if (footprints.size() == 1 && footprints.front().load == 0.0)
      return;
    const BallFootprint &last = footprints.back();
    for (std::size_t i = 0; i < footprints.size(); ++i)
      {
        const BallFootprint &f = footprints[i];
        if (!(f.load > 0.0) || (i > 0 && !(f.load > footprints[i - 1].load)))
          fail("footprint loads must be > 0 and increasing (one footprint of load 0: a fixed footprint)");
        const double scale = std::cbrt(f.load / last.load);
        if (std::abs(f.semi_axis_circumferential / (scale * last.semi_axis_circumferential) - 1.0) > 1e-6 ||
            std::abs(f.semi_axis_transverse / (scale * last.semi_axis_transverse) - 1.0) > 1e-6)
          fail("footprints of different loads must be the Hertz ellipses of those loads (semi-axes as load^(1/3))");
      }
  }

  fem::RacewayBallLoad unit_ball(const fem::RingGeometry &ring, const double angle, const BallFootprint &footprint)
  {
    fem::RacewayBallLoad ball;
    ball.ring                      = ring;
    ball.angle                     = angle;
    ball.force                     = 1.0;
    ball.semi_axis_circumferential = footprint.semi_axis_circumferential;
    ball.semi_axis_transverse      = footprint.semi_axis_transverse;
    return ball;
  }

  RacewayOperators raceway_operators(const CraigBampton &basis, const fem::ElasticModel &model,
                                     const fem::RingGeometry &ring, const unsigned int n_angles,
                                     const std::vector<BallFootprint> &footprints)
  {
    check_footprints(footprints);
    RacewayOperators result;
    result.footprints = footprints;
    if (n_angles == 0)
      return result;
    // One point map per ball, located exactly as project_load() locates a
    // single ball: a patch point within the search tolerance of two cells is
    // placed by whichever the search meets first (and moved onto that cell),
    // so only the same search gives the same row. The maps are built once and
    // each basis field sampled through all of them: one pass over the n
    // basis fields instead of n_angles load assemblies projected on all n.
    std::vector<fem::PatchForces>     patches;
    std::vector<fem::SurfacePointMap> maps;
    for (unsigned int k = 0; k < n_angles; ++k)
      result.angles.push_back(2.0 * M_PI * k / n_angles);
    for (const BallFootprint &footprint : footprints)
      for (const double angle : result.angles)
        {
          fem::RacewayBallLoad ball = unit_ball(ring, angle, footprint);
          ball.contact_angle        = result.contact_angle;
          patches.push_back(fem::raceway_patch_forces(ball));
          maps.emplace_back(model, patches.back().points, fem::BoundaryId::raceway);
        }
    // f_kᵀ t_j = Σ_p F_p · (H_p t_j): the load vector is Hᵀ F (surface_point_map.h).
    result.approach = assemble_operator(basis, patches.size(), 1, [&](const fem::DisplacementField &u) {
      std::vector<double> work(patches.size(), 0.0);
      for (std::size_t k = 0; k < patches.size(); ++k)
        {
          const std::vector<fem::Vector3> at_points = maps[k].interpolate(u);
          for (std::size_t p = 0; p < at_points.size(); ++p)
            for (unsigned int d = 0; d < 3; ++d)
              work[k] += patches[k].forces[p][d] * at_points[p][d];
        }
      return work;
    });
    return result;
  }

  void write_model_file(const std::string &path, const ReducedModel &model)
  {
    const std::string temporary = path + ".tmp";
    try
      {
        {
          Id file(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
          if (!file.valid())
            throw std::runtime_error("cannot create the file");
          const ReducedMatrices &m = model.matrices;
          const hsize_t          n = m.size();
          write_string_attribute(file, "format", format_name);
          write_number_attribute(file, "format_version", format_version);
          write_string_attribute(file, "input_hash", model.input_hash);
          write_number_attribute(file, "n_constraint_coordinates", m.n_constraint);
          write_number_attribute(file, "n_modal_coordinates", m.n_modal);
          write_number_attribute(file, "n_boundary_dofs", static_cast<double>(m.n_boundary_dofs));
          write_number_attribute(file, "n_interior_dofs", static_cast<double>(m.n_interior_dofs));
          write_number_attribute(file, "stiffness_asymmetry", m.stiffness_asymmetry);
          write_number_attribute(file, "mass_asymmetry", m.mass_asymmetry);
          for (const auto &[key, value] : model.provenance)
            write_string_attribute(file, "provenance_" + key, value);
          ReductionTimings timings = model.timings;
          for (const auto &[name, seconds] : timing_fields(timings))
            write_number_attribute(file, "time_" + name + "_s", *seconds);

          write_array(file, "/matrices/mass", {n, n}, m.mass);
          write_array(file, "/matrices/stiffness", {n, n}, m.stiffness);
          write_array(file, "/frequencies/fixed_interface_hz", {m.fixed_interface_frequencies_hz.size()},
                      m.fixed_interface_frequencies_hz);
          write_array(file, "/frequencies/interface_hz", {m.interface_frequencies_hz.size()},
                      m.interface_frequencies_hz);
          write_array(file, "/frequencies/reduced_free_hz", {model.free_frequencies_hz.size()},
                      model.free_frequencies_hz);

          const GridOperators &g = model.interface_grid;
          const hsize_t        cells = g.grid.size();
          write_array(file, "/operators/interface_grid/displacement", {cells, 3, cells > 0 ? n : 0}, g.displacement);
          write_array(file, "/operators/interface_grid/stress", {cells, 6, cells > 0 ? n : 0}, g.stress);
          Id grid_group(H5Gopen2(file, "/operators/interface_grid", H5P_DEFAULT), H5Gclose);
          write_number_attribute(grid_group, "radius_m", g.grid.radius);
          write_number_attribute(grid_group, "nx", g.grid.nx);
          write_number_attribute(grid_group, "ny", g.grid.ny);
          write_number_attribute(grid_group, "hx_m", g.grid.hx);
          write_number_attribute(grid_group, "hy_m", g.grid.hy);
          write_number_attribute(grid_group, "x_min_m", g.grid.x_min);
          write_number_attribute(grid_group, "y_min_m", g.grid.y_min);

          const PointOperators &p = model.sample_points;
          const hsize_t         n_points = p.points.size();
          std::vector<double>   xyz;
          for (const auto &point : p.points)
            xyz.insert(xyz.end(), point.begin(), point.end());
          write_array(file, "/operators/sample_points/points", {n_points, 3}, xyz);
          write_array(file, "/operators/sample_points/stress", {n_points, 6, n_points > 0 ? n : 0}, p.stress);
          write_array(file, "/operators/sample_points/displacement",
                      {p.displacement.empty() ? 0 : n_points, 3, p.displacement.empty() ? 0 : n}, p.displacement);

          const RacewayOperators &r          = model.raceway;
          const hsize_t           n_angles   = r.angles.size();
          const hsize_t           footprints = r.footprints.size();
          write_array(file, "/operators/raceway/angles", {n_angles}, r.angles);
          write_array(file, "/operators/raceway/approach", {footprints, n_angles, n_angles > 0 ? n : 0}, r.approach);
          std::vector<double> footprint_table;
          for (const BallFootprint &f : r.footprints)
            footprint_table.insert(footprint_table.end(),
                                   {f.semi_axis_circumferential, f.semi_axis_transverse, f.load});
          write_array(file, "/operators/raceway/footprints", {footprints, 3}, footprint_table);
          Id raceway_group(H5Gopen2(file, "/operators/raceway", H5P_DEFAULT), H5Gclose);
          write_number_attribute(raceway_group, "contact_angle_rad", r.contact_angle);
          if (const ResidualFlexibility &residual = model.residual; !residual.empty())
            {
              const hsize_t cells = g.grid.size(), rows = static_cast<hsize_t>(g.grid.ny);
              const char   *names[3] = {"pressure", "shear_x", "shear_y"};
              for (int k = 0; k < 3; ++k)
                if (!residual.traction[k].empty())
                  write_array(file, std::string("/residual_flexibility/") + names[k], {rows, cells},
                              residual.traction[k]);
              if (!residual.ball.empty()) // a housing has no raceway
                write_array(file, "/residual_flexibility/ball", {residual.ball.size() / cells, cells}, residual.ball);
              Id group(H5Gopen2(file, "/residual_flexibility", H5P_DEFAULT), H5Gclose);
              write_number_attribute(group, "column_angle_rad", residual.column_angle);
              write_number_attribute(group, "solves", residual.solves);
              write_number_attribute(group, "seconds", residual.seconds);
            }
          if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
            throw std::runtime_error("cannot flush");
        }
        if (std::rename(temporary.c_str(), path.c_str()) != 0)
          throw std::runtime_error("cannot rename " + temporary);
      }
    catch (const std::runtime_error &error)
      {
        std::remove(temporary.c_str());
        throw ModelFileError(path, error.what());
      }
  }

  ReducedModel read_model_file(const std::string &path, const std::string &expected_hash)
  {
    // HDF5 prints its own error stack on failures; the ModelFileError says it in one line.
    H5E_auto2_t old_handler;
    void       *old_data;
    H5Eget_auto2(H5E_DEFAULT, &old_handler, &old_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    struct RestoreHandler
    {
      H5E_auto2_t handler;
      void       *data;
      ~RestoreHandler() { H5Eset_auto2(H5E_DEFAULT, handler, data); }
    } restore{old_handler, old_data};

    Id file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!file.valid())
      throw ModelFileError(path, "cannot be opened as HDF5 (missing, truncated or not a model file)");
    ReducedModel model;
    try
      {
        if (read_string_attribute(file, "format") != format_name)
          throw std::runtime_error("is not a FretSim reduced model");
        const double version = read_number_attribute(file, "format_version");
        if (version != format_version)
          throw std::runtime_error("has format version " + std::to_string(static_cast<int>(version)) +
                                   ", this program reads version " + std::to_string(format_version));
        model.input_hash = read_string_attribute(file, "input_hash");
        if (!expected_hash.empty() && model.input_hash != expected_hash)
          throw std::runtime_error("was made from other inputs (input hash " + model.input_hash + ", the scene's is " +
                                   expected_hash + "): run `fretsim reduce` again for this scene");
        ReducedMatrices &m = model.matrices;
        m.n_constraint     = static_cast<unsigned int>(read_number_attribute(file, "n_constraint_coordinates"));
        m.n_modal          = static_cast<unsigned int>(read_number_attribute(file, "n_modal_coordinates"));
        m.n_boundary_dofs  = static_cast<unsigned long>(read_number_attribute(file, "n_boundary_dofs"));
        m.n_interior_dofs  = static_cast<unsigned long>(read_number_attribute(file, "n_interior_dofs"));
        m.stiffness_asymmetry = read_number_attribute(file, "stiffness_asymmetry");
        m.mass_asymmetry      = read_number_attribute(file, "mass_asymmetry");
        for (const auto &[name, seconds] : timing_fields(model.timings))
          *seconds = read_number_attribute(file, "time_" + name + "_s");
        const std::size_t n = m.size();
        m.mass      = read_array(file, "/matrices/mass");
        m.stiffness = read_array(file, "/matrices/stiffness");
        if (m.mass.size() != n * n || m.stiffness.size() != n * n)
          throw std::runtime_error("matrices do not match the coordinate counts");
        m.fixed_interface_frequencies_hz = read_array(file, "/frequencies/fixed_interface_hz");
        m.interface_frequencies_hz       = read_array(file, "/frequencies/interface_hz");
        model.free_frequencies_hz        = read_array(file, "/frequencies/reduced_free_hz");

        GridOperators &g = model.interface_grid;
        g.displacement   = read_array(file, "/operators/interface_grid/displacement");
        g.stress         = read_array(file, "/operators/interface_grid/stress");
        Id grid_group(H5Gopen2(file, "/operators/interface_grid", H5P_DEFAULT), H5Gclose);
        g.grid.radius = read_number_attribute(grid_group, "radius_m");
        g.grid.nx     = static_cast<int>(read_number_attribute(grid_group, "nx"));
        g.grid.ny     = static_cast<int>(read_number_attribute(grid_group, "ny"));
        g.grid.hx     = read_number_attribute(grid_group, "hx_m");
        g.grid.hy     = read_number_attribute(grid_group, "hy_m");
        g.grid.x_min  = read_number_attribute(grid_group, "x_min_m");
        g.grid.y_min  = read_number_attribute(grid_group, "y_min_m");
        if (g.displacement.size() != g.grid.size() * 3 * n || g.stress.size() != g.grid.size() * 6 * n)
          throw std::runtime_error("interface grid operators do not match the grid and coordinate counts");

        PointOperators           &p   = model.sample_points;
        const std::vector<double> xyz = read_array(file, "/operators/sample_points/points");
        for (std::size_t k = 0; k + 2 < xyz.size(); k += 3)
          p.points.push_back({xyz[k], xyz[k + 1], xyz[k + 2]});
        p.stress       = read_array(file, "/operators/sample_points/stress");
        p.displacement = read_array(file, "/operators/sample_points/displacement");
        if (p.stress.size() != p.points.size() * 6 * n)
          throw std::runtime_error("sample point operators do not match the points and coordinate counts");

        // Files written before the raceway operator existed have no group: empty.
        if (H5Lexists(file, "/operators/raceway", H5P_DEFAULT) > 0)
          {
            RacewayOperators &r = model.raceway;
            r.angles            = read_array(file, "/operators/raceway/angles");
            r.approach          = read_array(file, "/operators/raceway/approach");
            const std::vector<double> table = read_array(file, "/operators/raceway/footprints");
            for (std::size_t f = 0; f + 2 < table.size(); f += 3)
              r.footprints.push_back({table[f], table[f + 1], table[f + 2]});
            Id raceway_group(H5Gopen2(file, "/operators/raceway", H5P_DEFAULT), H5Gclose);
            r.contact_angle = read_number_attribute(raceway_group, "contact_angle_rad");
            if (r.approach.size() != r.footprints.size() * r.angles.size() * n || table.size() % 3 != 0)
              throw std::runtime_error("raceway operator does not match the footprint, angle and coordinate counts");
            try
              {
                if (!r.angles.empty())
                  check_footprints(r.footprints);
              }
            catch (const std::invalid_argument &error)
              {
                throw std::runtime_error(std::string("raceway footprints: ") + error.what());
              }
          }

        if (H5Lexists(file, "/residual_flexibility", H5P_DEFAULT) > 0)
          {
            ResidualFlexibility &residual = model.residual;
            if (H5Lexists(file, "/residual_flexibility/ball", H5P_DEFAULT) > 0)
              residual.ball = read_array(file, "/residual_flexibility/ball");
            const char *names[3]          = {"pressure", "shear_x", "shear_y"};
            for (int k = 0; k < 3; ++k)
              if (const std::string name = std::string("/residual_flexibility/") + names[k];
                  H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0)
                {
                  residual.traction[k] = read_array(file, name);
                  if (residual.traction[k].size() != g.grid.size() * g.grid.ny)
                    throw std::runtime_error("residual flexibility " + name + " does not match the interface grid");
                }
            Id group(H5Gopen2(file, "/residual_flexibility", H5P_DEFAULT), H5Gclose);
            residual.column_angle = read_number_attribute(group, "column_angle_rad");
            residual.solves       = static_cast<unsigned int>(read_number_attribute(group, "solves"));
            residual.seconds      = read_number_attribute(group, "seconds");
            if ((!residual.ball.empty() &&
                 residual.ball.size() != std::max<std::size_t>(1, model.raceway.footprints.size()) * g.grid.size()) ||
                residual.traction[0].empty())
              throw std::runtime_error("residual flexibility does not match the interface grid");
          }

        // Provenance: every root attribute named provenance_*.
        std::vector<std::string> names;
        hsize_t                  index = 0;
        H5Aiterate2(file, H5_INDEX_NAME, H5_ITER_INC, &index,
                    [](hid_t, const char *name, const H5A_info_t *, void *data) -> herr_t {
                      static_cast<std::vector<std::string> *>(data)->emplace_back(name);
                      return 0;
                    },
                    &names);
        for (const std::string &key : names)
          if (key.rfind("provenance_", 0) == 0)
            model.provenance[key.substr(11)] = read_string_attribute(file, key);
      }
    catch (const std::runtime_error &error)
      {
        throw ModelFileError(path, error.what());
      }
    return model;
  }
} // namespace fretsim::reduction
