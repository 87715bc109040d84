// `fretsim fe`: full-FE reference solutions of a ring_housing configuration.
// run_fe_command() reads and checks everything first (InputError, nothing
// written), then starts MPI, builds the model, solves the requested analysis
// and writes stress snapshots at sample points, displacement VTU and a summary.
#include "app/fe_command.h"

#include <fretsim/support/run_control.h>
#include <fretsim/output/stress_snapshots.h>
#include <fretsim/output/summary.h>
#include <fretsim/scenes/figures.h>

#include <fretsim/fem/parallel_environment.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/fem/transient.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>

namespace fretsim::app
{
  using models::RingHousingRequest;
  using models::boundary_named;
  using models::boundary_names;
  using models::build_ring_housing_mesh;
  using models::read_ring_housing_parameters;
  using models::read_ring_housing_request;

  namespace
  {
    using fem::BoundaryId;
    using Clock = std::chrono::steady_clock;

    constexpr double two_pi = 6.283185307179586;
    const std::string &section = models::fe_run_section;

    double seconds_since(const Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    /// Boundaries a parametric mesh of `bodies` has.
    std::vector<BoundaryId> boundaries_of(const RingHousingRequest &r)
    {
      std::vector<BoundaryId> ids{BoundaryId::side_faces};
      if (r.bodies != "housing")
        {
          ids.push_back(BoundaryId::raceway);
          if (r.ring.has_groove())
            ids.push_back(BoundaryId::ring_lands);
        }
      if (r.bodies == "ring")
        ids.push_back(BoundaryId::ring_outer);
      if (r.bodies == "housing")
        ids.push_back(BoundaryId::housing_bore);
      if (r.bodies != "ring")
        ids.push_back(BoundaryId::housing_outer);
      if (r.divisions.sector_angle < two_pi * (1 - 1e-12))
        {
          ids.push_back(BoundaryId::sector_start);
          ids.push_back(BoundaryId::sector_end);
        }
      return ids;
    }

    /// What the FE run section asks for, checked against the mesh.
    struct FeRequest
    {
      std::string                analysis;
      fem::SolverSettings        solver;
      unsigned int               n_modes = 10;
      std::vector<fem::Support>  supports;
      double                     interference = 0.0;
      std::optional<fem::PressureLoad> pressure;
      unsigned int               balls     = 0;
      double                     ball_load = 0.0;
      bool                       radial_distribution = false;
      double                     load_direction = 0.0, contact_angle = 0.0;
      double                     semi_axis_circumferential = 0.0, semi_axis_transverse = 0.0;
      double                     cage_speed = 0.0, time_step = 0.0;
      unsigned int               steps = 0, snapshot_interval = 1;
      unsigned int               points_per_line = 0, grid_circumferential = 0, grid_axial = 0;
      fem::RingGeometry          ring; ///< the ring the balls run in and the sample lines follow
    };

    /// The mesh as the request's checks see it (a Gmsh mesh: the whole ring,
    /// every boundary).
    struct MeshShape
    {
      bool                    parametric = true;
      double                  sector     = two_pi;
      bool                    full_ring  = true;
      std::vector<BoundaryId> present;

      bool has(BoundaryId id) const
      {
        return !parametric || std::find(present.begin(), present.end(), id) != present.end();
      }
    };

    MeshShape shape_of(const RingHousingRequest &mesh)
    {
      MeshShape shape;
      shape.parametric = mesh.gmsh_file.empty();
      shape.sector     = shape.parametric ? mesh.divisions.sector_angle : two_pi;
      shape.full_ring  = shape.sector >= two_pi * (1 - 1e-12);
      shape.present    = boundaries_of(mesh);
      return shape;
    }

    /// Clamped boundaries, held axial faces and symmetry planes: enough to
    /// hold the body unless only its modes are asked for.
    void read_supports(FeRequest &r, const SceneParameters &p, const RingHousingRequest &mesh,
                       const MeshShape &shape)
    {
      const std::string clamped_path = section + "Supports/Clamped";
      std::istringstream clamped(p.get(clamped_path));
      for (std::string name; std::getline(clamped, name, ',');)
        {
          name.erase(0, name.find_first_not_of(" \t"));
          name.erase(name.find_last_not_of(" \t") + 1);
          if (name.empty() || name == "none")
            continue;
          const auto id = boundary_named(name);
          if (!id)
            p.reject(clamped_path, "names an unknown boundary '" + name +
                                     "'; expected a comma-separated list of: " + boundary_names() + ", or none");
          if (!shape.has(*id))
            p.reject(clamped_path, "names the boundary '" + name + "', which Mesh/Bodies = " + mesh.bodies +
                                     " does not have");
          r.supports.push_back({*id, true, true, true});
        }
      const bool clamps = !r.supports.empty();
      if (p.get(section + "Supports/Axial faces") == "fixed")
        r.supports.push_back({BoundaryId::side_faces, false, false, true});
      if (p.get_bool(section + "Supports/Symmetry planes"))
        {
          if (!shape.parametric || std::abs(shape.sector - 0.25 * two_pi) > 1e-9)
            p.reject(section + "Supports/Symmetry planes",
                     "needs a parametric quarter model (Divisions/Sector angle = pi/2, cut faces on the planes "
                     "y = 0 and x = 0)");
          r.supports.push_back({BoundaryId::sector_start, false, true, false});
          r.supports.push_back({BoundaryId::sector_end, true, false, false});
        }
      const bool held = clamps || (p.get(section + "Supports/Axial faces") == "fixed" &&
                                   p.get_bool(section + "Supports/Symmetry planes"));
      if (r.analysis != "modes" && !held)
        p.reject(clamped_path, "leaves the body free: a " + r.analysis +
                                 " analysis needs a clamped boundary, or Axial faces = fixed with Symmetry planes = "
                                 "true on a quarter model");
    }

    /// The balls' checks: they run round a meshed full ring, their contact
    /// ellipse inside the groove.
    void check_balls(const FeRequest &r, const SceneParameters &p, const RingHousingRequest &mesh,
                     const MeshShape &shape)
    {
      if (mesh.bodies == "housing")
        p.reject(section + "Loads/Balls", "needs the ring meshed (Mesh/Bodies = ring or ring_in_housing)");
      if (!shape.full_ring)
        p.reject(section + "Loads/Balls", "needs the full ring (Divisions/Sector angle = 2 pi): the balls "
                                          "go round it");
      if (!r.ring.has_groove() && r.contact_angle != 0.0)
        p.reject(section + "Loads/Contact angle", "must be 0 on a plain bore (Ring/Groove radius = 0)");
      if (r.ring.has_groove())
        {
          const double edge = std::asin(std::min(1.0, r.ring.groove_half_width() / r.ring.groove_radius));
          if (std::abs(r.contact_angle) + r.semi_axis_transverse / r.ring.groove_radius >= edge)
            {
              std::ostringstream s;
              s << "with Contact angle " << r.contact_angle << " rad puts the contact ellipse over the groove "
                << "edge: expected |Contact angle| + b / Ring/Groove radius < " << edge << " rad";
              p.reject(section + "Loads/Semi-axis transverse", s.str());
            }
        }
    }

    /// The fit, a pressure and the balls; the analysis must have the load it needs.
    void read_loads(FeRequest &r, const SceneParameters &p, const RingHousingRequest &mesh, const MeshShape &shape)
    {
      r.interference = p.get_double(section + "Loads/Interference");
      if (r.interference > 0.0 && mesh.bodies != "ring_in_housing")
        p.reject(section + "Loads/Interference", "needs Mesh/Bodies = ring_in_housing (the ring fitted in the "
                                                 "housing), not " + mesh.bodies);
      const double pressure = p.get_double(section + "Loads/Pressure");
      if (pressure != 0.0)
        {
          const auto id = boundary_named(p.get(section + "Loads/Pressure boundary"));
          if (!shape.has(*id))
            p.reject(section + "Loads/Pressure boundary",
                     "is '" + fem::to_string(*id) + "', which Mesh/Bodies = " + mesh.bodies + " does not have");
          r.pressure = fem::PressureLoad{*id, pressure};
        }
      r.balls               = static_cast<unsigned int>(p.get_integer(section + "Loads/Balls"));
      r.ball_load           = p.get_double(section + "Loads/Ball load");
      r.radial_distribution = p.get(section + "Loads/Load distribution") == "radial";
      r.load_direction      = p.get_double(section + "Loads/Load direction");
      r.contact_angle       = p.get_double(section + "Loads/Contact angle");
      r.semi_axis_circumferential = p.get_double(section + "Loads/Semi-axis circumferential");
      r.semi_axis_transverse      = p.get_double(section + "Loads/Semi-axis transverse");
      if (r.balls > 0 && r.ball_load > 0.0)
        check_balls(r, p, mesh, shape);
      const bool loaded = r.interference > 0.0 || r.pressure || (r.balls > 0 && r.ball_load > 0.0);
      if (r.analysis == "static" && !loaded)
        p.reject(section + "Loads/Ball load", "is 0 and so are Interference and Pressure: a static analysis "
                                              "needs a load");
      if (r.analysis == "transient" && !(r.balls > 0 && r.ball_load > 0.0))
        p.reject(section + "Loads/Ball load", "must be > 0 with Balls > 0: the transient moves the balls");
    }

    /// The transient's steps and the stress sample lines and grid.
    void read_steps_and_sampling(FeRequest &r, const SceneParameters &p)
    {
      r.cage_speed        = p.get_double(section + "Transient/Cage speed");
      r.time_step         = p.get_double(section + "Transient/Time step");
      r.steps             = static_cast<unsigned int>(p.get_integer(section + "Transient/Steps"));
      r.snapshot_interval = static_cast<unsigned int>(p.get_integer(section + "Transient/Snapshot interval"));

      r.points_per_line      = static_cast<unsigned int>(p.get_integer(section + "Sampling/Points per line"));
      r.grid_circumferential = static_cast<unsigned int>(p.get_integer(section + "Sampling/Grid circumferential"));
      r.grid_axial           = static_cast<unsigned int>(p.get_integer(section + "Sampling/Grid axial"));
      if ((r.grid_circumferential == 0) != (r.grid_axial == 0))
        p.reject(section + "Sampling/Grid axial", "and Grid circumferential must both be 0 (no grid) or both > 0");
      if (r.points_per_line == 0 && r.grid_circumferential == 0)
        p.reject(section + "Sampling/Points per line", "is 0 and there is no grid: no stress sample points");
    }

    FeRequest read_fe_request(const SceneParameters &p, const RingHousingRequest &mesh)
    {
      FeRequest r;
      r.analysis = p.get(section + "Analysis");
      const std::string solver = p.get(section + "Solver");
      r.solver.type = solver == "direct" ? fem::LinearSolver::direct :
                      solver == "cg_amg" ? fem::LinearSolver::cg_amg :
                                           fem::LinearSolver::cg_gamg;
      r.solver.relative_tolerance = p.get_double(section + "Solver tolerance");
      r.solver.max_iterations     = static_cast<unsigned int>(p.get_integer(section + "Maximum iterations"));
      r.n_modes                   = static_cast<unsigned int>(p.get_integer(section + "Modes"));

      // The ring as the Ring section gives it (for a Gmsh mesh, it must describe the file's ring).
      r.ring.bore_radius          = p.get_double("Ring/Bore radius");
      r.ring.outer_radius         = p.get_double("Ring/Outer radius");
      r.ring.width                = p.get_double("Ring/Width");
      r.ring.groove_radius        = p.get_double("Ring/Groove radius");
      r.ring.groove_bottom_radius = p.get_double("Ring/Groove bottom radius");
      const MeshShape shape       = shape_of(mesh);
      read_supports(r, p, mesh, shape);
      read_loads(r, p, mesh, shape);
      read_steps_and_sampling(r, p);
      return r;
    }

    /// The balls at time t: positions, loads and Hertz semi-axes.
    std::vector<fem::RacewayBallLoad> ball_loads(const FeRequest &r, const double time)
    {
      std::vector<fem::RacewayBallLoad> balls;
      for (unsigned int i = 0; i < r.balls; ++i)
        {
          const double angle = r.load_direction + two_pi * i / r.balls + r.cage_speed * time;
          double       load  = r.ball_load;
          if (r.radial_distribution)
            {
              // Stribeck's distribution with a half-circle load zone (ε = 0.5):
              // Q(ψ) = Q_max cos^(3/2) ψ for |ψ| < π/2.
              const double psi = std::remainder(angle - r.load_direction, two_pi);
              load = std::abs(psi) < 0.25 * two_pi ? r.ball_load * std::pow(std::cos(psi), 1.5) : 0.0;
            }
          if (!(load > 0.0))
            continue;
          fem::RacewayBallLoad b;
          b.ring          = r.ring;
          b.angle         = angle;
          b.contact_angle = r.contact_angle;
          b.force         = load;
          // Hertz: the semi-axes grow as Q^(1/3).
          const double scale            = std::cbrt(load / r.ball_load);
          b.semi_axis_circumferential   = scale * r.semi_axis_circumferential;
          b.semi_axis_transverse        = scale * r.semi_axis_transverse;
          balls.push_back(b);
        }
      return balls;
    }

    fem::StaticLoad static_load(const FeRequest &r, const double time)
    {
      fem::StaticLoad load;
      if (r.interference > 0.0)
        load.expansions.push_back({fem::MaterialId::ring, r.interference / r.ring.outer_radius});
      if (r.pressure)
        load.pressures.push_back(*r.pressure);
      if (r.balls > 0 && r.ball_load > 0.0)
        load.ball_loads = ball_loads(r, time);
      return load;
    }

    /// Stress sample points and the index range of each group.
    struct SamplePoints
    {
      std::vector<fem::Point3>                                   points;
      std::vector<std::pair<std::string, std::array<std::size_t, 2>>> groups;
    };

    SamplePoints sample_points(const FeRequest &r, const RingHousingRequest &mesh, const SceneParameters &p)
    {
      const double sector = mesh.gmsh_file.empty() ? mesh.divisions.sector_angle : two_pi;
      // Mid-way between equal steps: off the cut faces of a sector, and off
      // the cell faces whenever the cells divide the points evenly (the
      // stress jumps across a face, and which side is sampled is arbitrary).
      auto theta = [&](const unsigned int k, const unsigned int n) { return sector * (k + 0.5) / n; };
      // A point on a bonded interface could be taken in either body's cell:
      // sample a thousandth of the wall inside the body meant.
      const bool   ring_meshed = mesh.bodies != "housing";
      const double inner = ring_meshed ? r.ring.bore_radius : r.ring.outer_radius;
      const double outer = ring_meshed ? r.ring.outer_radius : p.get_double("Housing/Outer radius");
      const double inset = 1e-3 * (outer - inner);

      SamplePoints s;
      auto         add_group = [&](const std::string &name, auto point_at, const unsigned int n) {
        const std::size_t first = s.points.size();
        for (unsigned int k = 0; k < n; ++k)
          s.points.push_back(point_at(theta(k, n)));
        s.groups.push_back({name, {first, s.points.size()}});
      };
      if (r.points_per_line > 0)
        {
          add_group(ring_meshed ? "ring_outer_line" : "housing_outer_line",
                    [&](double t) { return fem::Point3{(outer - inset) * std::cos(t), (outer - inset) * std::sin(t), 0.0}; },
                    r.points_per_line);
          if (ring_meshed)
            add_group("raceway_line",
                      [&](double t) {
                        const fem::Point3  x = fem::raceway_contact_point(r.ring, t, r.contact_angle);
                        const fem::Vector3 n = fem::raceway_contact_normal(t, r.contact_angle);
                        return fem::Point3{x[0] + inset * n[0], x[1] + inset * n[1], x[2] + inset * n[2]};
                      },
                      r.points_per_line);
          else
            add_group("housing_bore_line",
                      [&](double t) { return fem::Point3{(inner + inset) * std::cos(t), (inner + inset) * std::sin(t), 0.0}; },
                      r.points_per_line);
        }
      if (r.grid_circumferential > 0)
        {
          // Cell centres of a grid on the ring outer surface (housing: its
          // bore), circumferential index fastest as in contact::SurfaceGrid.
          const double radius = ring_meshed ? outer - inset : inner + inset;
          const double width  = r.ring.width;
          const std::size_t first = s.points.size();
          for (unsigned int j = 0; j < r.grid_axial; ++j)
            for (unsigned int i = 0; i < r.grid_circumferential; ++i)
              {
                const double t = sector * (i + 0.5) / r.grid_circumferential;
                const double z = -0.5 * width + width * (j + 0.5) / r.grid_axial;
                s.points.push_back({radius * std::cos(t), radius * std::sin(t), z});
              }
          s.groups.push_back({ring_meshed ? "ring_outer_grid" : "housing_bore_grid", {first, s.points.size()}});
        }
      return s;
    }

    /// Largest von Mises stress over all points and snapshots, where and when.
    struct StressExtremes
    {
      double      von_mises = -1.0;
      std::size_t point     = 0;
      double      time      = 0.0;
      std::array<double, 6> max{}, min{};
      bool        any = false;

      void add(const std::vector<double> &stress, const double t)
      {
        for (std::size_t k = 0; 6 * k < stress.size(); ++k)
          {
            const double *s  = &stress[6 * k];
            const double  vm = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                                (s[2] - s[0]) * (s[2] - s[0])) +
                                         3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
            if (vm > von_mises)
              von_mises = vm, point = k, time = t;
            for (unsigned int c = 0; c < 6; ++c)
              {
                max[c] = any ? std::max(max[c], s[c]) : s[c];
                min[c] = any ? std::min(min[c], s[c]) : s[c];
              }
            any = true;
          }
      }
    };

    /// The sampler at the request's points; a point off the mesh is the configuration's error.
    fem::StressSampler make_sampler(const fem::ElasticModel &model, const SamplePoints &samples,
                                    const std::string &config_file)
    {
      try
        {
          return fem::StressSampler(model, samples.points, fem::StressFrame::cylindrical);
        }
      catch (const std::invalid_argument &error)
        {
          // The lines follow the Ring section; a Gmsh mesh that is not that ring misses them.
          throw InputError(config_file, "Ring", std::string("sample points off the mesh: ") + error.what());
        }
    }

    /// An analysis under way: the model, where its stresses go, and what it
    /// has recorded for the summary.
    struct FeRun
    {
      const FeRequest                &request;
      fem::ElasticModel              &model;
      fem::StressSampler             &sampler;
      output::StressSnapshotFile     *file; ///< on rank 0 only
      const std::filesystem::path    &directory;
      StressExtremes                  extremes;
      output::Summary                 summary;
      double                          solve_seconds = 0.0, assembly_seconds = 0.0, sampling_seconds = 0.0;
      std::vector<double>             stress_offset; ///< a static state superposed on each snapshot
      std::vector<std::string>        vtu_names;

      FeRun(const FeRequest &r, fem::ElasticModel &m, fem::StressSampler &s, output::StressSnapshotFile *f,
            const std::filesystem::path &d)
        : request(r)
        , model(m)
        , sampler(s)
        , file(f)
        , directory(d)
      {}

      /// The stresses of u at the sample points, recorded at `time`.
      void snapshot(const fem::DisplacementField &u, const double time)
      {
        const auto t0     = Clock::now();
        auto       stress = sampler.evaluate(u);
        for (std::size_t k = 0; k < stress_offset.size(); ++k)
          stress[k] += stress_offset[k];
        extremes.add(stress, time);
        if (file)
          file->append(time, stress);
        sampling_seconds += seconds_since(t0);
      }

      void write_vtu(const fem::DisplacementField &u, const std::string &name)
      {
        u.write_vtu(directory.string(), name);
        vtu_names.push_back(name);
      }
    };

    void run_static(FeRun &run, const std::string &bodies)
    {
      const auto                  &request = run.request;
      auto                        &model   = run.model;
      const fem::DisplacementField u       = model.solve_static(static_load(request, 0.0), request.solver);
      run.snapshot(u, 0.0);
      run.write_vtu(u, "displacement");
      run.summary.set("strain_energy_J", u.strain_energy());
      if (bodies == "ring_in_housing")
        {
          // The contact pressure of the fit, the mean of both sides' σ_rr.
          const auto housing = u.average_on_interface(fem::MaterialId::housing, fem::MaterialId::ring);
          const auto ring    = u.average_on_interface(fem::MaterialId::ring, fem::MaterialId::housing);
          run.summary.set("interface_pressure_Pa", -0.5 * (housing.s_rr + ring.s_rr));
        }
      run.assembly_seconds = model.timings().assemble_stiffness + model.timings().assemble_load;
      run.solve_seconds    = model.timings().solve;
      run.summary.set("iterations", static_cast<long long>(model.timings().iterations));
    }

    void run_modes(FeRun &run)
    {
      fem::ModalSettings settings;
      settings.n_modes               = run.request.n_modes;
      const fem::ModalSolution modes = run.model.solve_modes(settings);
      for (std::size_t i = 0; i < modes.shapes.size(); ++i)
        run.snapshot(modes.shapes[i], static_cast<double>(i));
      for (std::size_t i = 0; i < std::min<std::size_t>(modes.shapes.size(), 6); ++i)
        {
          std::ostringstream name;
          name << "mode_" << std::setw(2) << std::setfill('0') << i + 1;
          run.write_vtu(modes.shapes[i], name.str());
        }
      if (run.file)
        run.file->results().write_dataset("/frequencies", "Hz", {modes.frequencies_hz.size()}, modes.frequencies_hz);
      run.summary.set("frequencies_hz", modes.frequencies_hz);
      run.summary.set("rigid_body_modes", static_cast<long long>(modes.n_rigid_body_modes));
      run.assembly_seconds = run.model.timings().assemble_stiffness + run.model.timings().assemble_mass;
      run.solve_seconds    = modes.seconds;
    }

    void run_transient(FeRun &run)
    {
      const auto &request = run.request;
      auto       &model   = run.model;
      // The fit is static: solved once and superposed (linear elasticity),
      // which also keeps its eigenstrain out of the integrator (whose
      // displacement() does not carry eigenstrains, so its stresses would
      // count the ring's free expansion as strain).
      FeRequest dynamic    = request;
      dynamic.interference = 0.0;
      if (request.interference > 0.0)
        {
          fem::StaticLoad fit;
          fit.expansions.push_back({fem::MaterialId::ring, request.interference / request.ring.outer_radius});
          const fem::DisplacementField u_fit = model.solve_static(fit, request.solver);
          run.stress_offset                  = run.sampler.evaluate(u_fit);
          run.write_vtu(u_fit, "fit_displacement");
        }
      // Start from the static state under the balls at t = 0, so that the
      // run shows the balls' passage rather than a sudden load's ringing.
      const fem::StaticLoad        initial = static_load(dynamic, 0.0);
      const fem::DisplacementField u0      = model.solve_static(initial, request.solver);
      run.snapshot(u0, 0.0);
      fem::NewmarkIntegrator integrator(model, request.time_step, initial, &u0, 0.0);
      unsigned int           done = 0;
      for (unsigned int step = 1; step <= request.steps && !interrupt_requested(); ++step, ++done)
        {
          integrator.advance(static_load(dynamic, step * request.time_step));
          if (step % request.snapshot_interval == 0 || step == request.steps)
            run.snapshot(integrator.displacement(), integrator.time());
        }
      run.write_vtu(integrator.displacement(), "displacement");
      run.summary.set("steps_done", static_cast<long long>(done));
      run.summary.set("final_time_s", integrator.time());
      run.summary.set("kinetic_energy_J", integrator.kinetic_energy());
      run.summary.set("strain_energy_J", integrator.strain_energy());
      run.assembly_seconds = model.timings().assemble_stiffness + model.timings().assemble_mass +
                             model.timings().assemble_load + integrator.factorisation_seconds();
      run.solve_seconds = model.timings().solve + integrator.step_seconds();
      run.summary.set("factorisation_s", integrator.factorisation_seconds());
    }

    /// The model's size and set-up time, for the summary and the report line.
    struct ModelFacts
    {
      const RingHousingRequest &mesh;
      unsigned long             cells;
      double                    setup_seconds;
    };

    /// The summary's description of the run, after what the analysis recorded.
    void add_run_summary(FeRun &run, const ModelFacts &facts, const SamplePoints &samples,
                         const Clock::time_point start)
    {
      const auto &request = run.request;
      auto       &summary = run.summary;
      summary.set("scene", ring_housing_scene);
      summary.set("command", std::string("fe"));
      summary.set("analysis", request.analysis);
      summary.set("bodies", facts.mesh.bodies);
      summary.set("element_degree", static_cast<long long>(facts.mesh.degree));
      summary.set("cells", static_cast<long long>(facts.cells));
      summary.set("dofs", static_cast<long long>(run.model.n_dofs()));
      summary.set("ranks", static_cast<long long>(fem::ParallelEnvironment::n_ranks()));
      summary.set("sample_points", static_cast<long long>(samples.points.size()));
      for (const auto &[name, range] : samples.groups)
        summary.set("points_" + name, std::vector<double>{double(range[0]), double(range[1])});
      double total_ball_load = 0.0;
      for (const auto &b : ball_loads(request, 0.0))
        total_ball_load += b.force;
      summary.set("ball_load_sum_N", total_ball_load);
      // Mode shapes are mass-normalised: their stresses have no absolute scale.
      const auto &extremes = run.extremes;
      if (extremes.any && request.analysis != "modes")
        {
          summary.set("max_von_mises_Pa", extremes.von_mises);
          const auto &x = samples.points[extremes.point];
          summary.set("max_von_mises_point_m", std::vector<double>{x[0], x[1], x[2]});
          summary.set("max_von_mises_snapshot", extremes.time);
          summary.set("stress_max_Pa", std::vector<double>(extremes.max.begin(), extremes.max.end()));
          summary.set("stress_min_Pa", std::vector<double>(extremes.min.begin(), extremes.min.end()));
          summary.set("stress_components", std::string("rr tt zz tz rz rt (cylindrical, tension positive)"));
        }
      output::Summary stages;
      stages.set("setup", facts.setup_seconds);
      stages.set("assembly", run.assembly_seconds);
      stages.set("solve", run.solve_seconds);
      stages.set("stress_sampling", run.sampling_seconds);
      summary.set_object("stage_times_s", stages);
      summary.set("wall_time_s", seconds_since(start));
      summary.set("interrupted", interrupt_requested());
    }

    /// The results file, its XDMF and the VTU records written (deal.II
    /// names a record <name>.pvtu or <name>_0.pvtu depending on its version).
    std::vector<std::string> written_files(const FeRun &run, const std::string &results_path)
    {
      const auto              &directory = run.directory;
      std::vector<std::string> files{results_path, (directory / "results.xdmf").string()};
      for (const auto &name : run.vtu_names)
        files.push_back(std::filesystem::exists(directory / (name + ".pvtu")) ?
                          (directory / (name + ".pvtu")).string() :
                          (directory / (name + "_0.pvtu")).string());
      return files;
    }

    void report(std::ostream &out, const FeRun &run, const ModelFacts &facts)
    {
      out << "fe " << run.request.analysis << ": " << run.model.n_dofs() << " DoFs (FE_Q" << facts.mesh.degree
          << ", " << facts.cells << " cells, " << fem::ParallelEnvironment::n_ranks() << " rank(s)), setup "
          << std::setprecision(3) << facts.setup_seconds << " s, assembly " << run.assembly_seconds << " s, solve "
          << run.solve_seconds << " s\n";
      if (run.extremes.any)
        out << "max von Mises stress at the sample points: " << std::setprecision(6) << run.extremes.von_mises
            << " Pa\n";
    }
  } // namespace

  std::vector<std::string> run_fe_command(const RingHousingCommandOptions &options, std::ostream &out)
  {
    const auto start = Clock::now();
    // Everything that can be checked without MPI is checked before MPI starts
    // and before anything is written.
    const SceneParameters    parameters = read_ring_housing_parameters(options.config_file, options.overrides);
    const RingHousingRequest mesh_request = read_ring_housing_request(parameters);
    const FeRequest          request      = read_fe_request(parameters, mesh_request);
    const SamplePoints       samples      = sample_points(request, mesh_request, parameters);
    const std::filesystem::path directory =
      options.output.empty() ?
        std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + "-fe") :
        std::filesystem::path(options.output);

    const fem::ParallelEnvironment mpi;
    const bool                     root = fem::ParallelEnvironment::rank() == 0;
    auto mesh = std::make_shared<fem::Mesh>(build_ring_housing_mesh(mesh_request, options.config_file));
    const unsigned long n_cells = mesh->summary(1).n_cells;
    std::map<fem::MaterialId, fem::Material> materials = mesh_request.materials;
    fem::ElasticModel model(mesh, materials, mesh_request.degree, request.supports);
    const ModelFacts  facts{mesh_request, n_cells, seconds_since(start)};
    fem::StressSampler sampler = make_sampler(model, samples, options.config_file);

    std::filesystem::create_directories(directory);
    const std::string results_path = (directory / "results.h5").string();
    std::optional<output::StressSnapshotFile> file;
    if (root)
      {
        file.emplace(results_path, samples.points, "cylindrical", ring_housing_scene, parameters.to_prm());
        std::string groups;
        for (const auto &[name, range] : samples.groups)
          groups += (groups.empty() ? "" : "; ") + name + " " + std::to_string(range[0]) + " " +
                    std::to_string(range[1]);
        file->results().set_root_attribute("point_groups", groups);
        file->results().set_root_attribute("analysis", request.analysis);
      }

    FeRun run(request, model, sampler, root ? &*file : nullptr, directory);
    if (request.analysis == "static")
      run_static(run, mesh_request.bodies);
    else if (request.analysis == "modes")
      run_modes(run);
    else
      run_transient(run);
    if (!root)
      return {};

    file->write_xdmf((directory / "results.xdmf").string());
    file.reset(); // closes results.h5 before the plot script reads it
    std::vector<std::string> files = written_files(run, results_path);
    add_run_summary(run, facts, samples, start);
    run.summary.write((directory / "summary.json").string());
    files.push_back((directory / "summary.json").string());
    report(out, run, facts);
    if (options.plots)
      for (const auto &figure : scenes::run_plot_script("plot_fe_results.py", {directory.string()}))
        files.push_back(figure);
    return files;
  }
} // namespace fretsim::app
