#include <fretsim/models/reduction.h>

#include <fretsim/models/reduced_statics.h>

#include <fretsim/support/progress.h>

#include <fretsim/fem/parallel_environment.h>
#include <fretsim/fem/shifted_static_solver.h>
#include <fretsim/fem/stress_sampler.h>
#include <fretsim/fem/surface_point_map.h>
#include <fretsim/fem/transient.h>
#include <fretsim/reduction/craig_bampton.h>
#include <fretsim/reduction/reduced_model.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

#include <fretsim/support/build_info.h>

namespace fretsim::models
{
  namespace
  {
    using fem::BoundaryId;
    using Clock = std::chrono::steady_clock;

    double seconds_since(const Clock::time_point start)
    {
      return std::chrono::duration<double>(Clock::now() - start).count();
    }

    /// What `reduce` is asked for, read and cross-checked before MPI starts.
    struct ReduceRequest
    {
      RingHousingRequest            body;
      reduction::ReductionSettings  settings;
      unsigned int                  grid_cells_circumferential = 0, grid_cells_axial = 0;
      unsigned int                  points_per_line            = 0;
      unsigned int                  raceway_ball_positions     = 0;
      std::vector<reduction::BallFootprint> footprints; ///< one fixed, or Hertz ellipses of increasing loads
      bool                          compare_with_full          = true;
      std::vector<unsigned int>     study_fixed_interface, study_interface;
      /// Zero-displacement supports of the body (a housing is held at its outside).
      std::vector<BoundaryId>       clamped_surfaces;
      /// Where the interface grid lies: the ring's outer surface, or the housing's bore.
      BoundaryId                    grid_surface = BoundaryId::ring_outer;
      std::string                   input_hash;
      std::map<std::string, std::string> provenance;
    };

    std::vector<BoundaryId> parse_surfaces(const SceneParameters &p, const std::string &path, const bool may_be_empty = false)
    {
      std::vector<BoundaryId> surfaces;
      std::stringstream       list(p.get(path));
      for (std::string name; std::getline(list, name, ',');)
        {
          name.erase(0, name.find_first_not_of(" \t"));
          name.erase(name.find_last_not_of(" \t") + 1);
          if (const auto id = boundary_named(name))
            surfaces.push_back(*id);
          else
            p.reject(path, "expected a comma-separated list of boundary names (raceway, ring_lands, ring_outer, "
                           "housing_bore, housing_outer, side_faces, sector_start, sector_end), got '" +
                             name + "'");
        }
      if (surfaces.empty() && !may_be_empty)
        p.reject(path, "names no surface; at least one coupling surface is needed");
      return surfaces;
    }

    std::vector<fem::Support> supports(const std::vector<BoundaryId> &surfaces)
    {
      std::vector<fem::Support> result;
      for (const BoundaryId surface : surfaces)
        result.push_back({surface});
      return result;
    }

    std::vector<unsigned int> counts(const SceneParameters &p, const std::string &path)
    {
      std::vector<unsigned int> result;
      for (const double value : p.get_double_list(path))
        {
          if (value != std::floor(value))
            p.reject(path, "expected whole numbers, got " + std::to_string(value));
          result.push_back(static_cast<unsigned int>(value));
        }
      return result;
    }

    /// The inputs that define the reduced model, as canonical text: every
    /// parameter of the body and reduction sections (not the study lists, not
    /// the comparison switch, not the output), plus the mesh file's bytes.
    std::string input_text(const SceneParameters &p, const RingHousingRequest &body)
    {
      std::ostringstream text;
      for (const auto &spec : p.specs())
        if (spec.path.rfind("Reduction/Study", 0) != 0 && spec.path.rfind("FE run", 0) != 0 &&
            spec.path != "Reduction/Compare with full FE")
          text << spec.path << '=' << p.get(spec.path) << '\n';
      if (!body.gmsh_file.empty())
        {
          std::ifstream mesh(body.gmsh_file, std::ios::binary);
          text << mesh.rdbuf();
        }
      return text.str();
    }

    /// The raceway footprints: Reduction/Ball footprint loads with their
    /// ellipses' semi-axes, or one fixed footprint (no loads).
    std::vector<reduction::BallFootprint> read_footprints(const SceneParameters &p)
    {
      const std::string         a_path = "Reduction/Ball footprint circumferential semi-axis",
                                b_path = "Reduction/Ball footprint transverse semi-axis",
                                q_path = "Reduction/Ball footprint loads";
      const std::vector<double> a = p.get_double_list(a_path), b = p.get_double_list(b_path),
                                loads = p.get_double_list(q_path);
      const std::size_t count = std::max<std::size_t>(1, loads.size());
      if (a.size() != count || b.size() != count)
        p.reject(loads.empty() ? a_path : q_path,
                 "expected one semi-axis of each kind per footprint load (one of each and no load: a fixed "
                 "footprint), got " + std::to_string(a.size()) + " and " + std::to_string(b.size()) + " semi-axes for " +
                   std::to_string(loads.size()) + " loads");
      std::vector<reduction::BallFootprint> footprints;
      for (std::size_t f = 0; f < count; ++f)
        footprints.push_back({a[f], b[f], loads.empty() ? 0.0 : loads[f]});
      try
        {
          reduction::check_footprints(footprints);
        }
      catch (const std::invalid_argument &error)
        {
          p.reject(q_path, error.what());
        }
      return footprints;
    }

    /// The patch of a ball of `load` [N] among the request's footprints.
    reduction::BallFootprint footprint_at(const ReduceRequest &r, double load)
    {
      reduction::RacewayOperators table;
      table.footprints = r.footprints;
      return table.footprint_at(load);
    }

    ReduceRequest read_request(const SceneParameters &p)
    {
      ReduceRequest r;
      r.body = read_ring_housing_request(p);
      if (r.body.bodies == "ring_in_housing")
        p.reject("Mesh/Bodies", "must be 'ring' or 'housing' for `reduce`: each body gets its own model (the "
                                "co-simulation couples them through the interface contact)");
      const bool housing = r.body.bodies == "housing";
      r.grid_surface     = housing ? BoundaryId::housing_bore : BoundaryId::ring_outer;
      r.settings.coupling_surfaces                 = parse_surfaces(p, "Reduction/Coupling surfaces");
      r.clamped_surfaces                           = parse_surfaces(p, "Reduction/Clamped surfaces", true);
      r.settings.n_fixed_interface_modes           = static_cast<unsigned int>(p.get_integer("Reduction/Fixed-interface modes"));
      r.settings.n_characteristic_constraint_modes = static_cast<unsigned int>(p.get_integer("Reduction/Characteristic constraint modes"));
      r.settings.interface_shift_hz                = p.get_double("Reduction/Interface shift");
      r.settings.eigen_tolerance                   = p.get_double("Reduction/Eigen tolerance");
      r.grid_cells_circumferential = static_cast<unsigned int>(p.get_integer("Reduction/Interface grid circumferential cells"));
      r.grid_cells_axial           = static_cast<unsigned int>(p.get_integer("Reduction/Interface grid axial cells"));
      r.points_per_line            = static_cast<unsigned int>(p.get_integer("Reduction/Sample points per line"));
      r.compare_with_full          = p.get_bool("Reduction/Compare with full FE");
      r.raceway_ball_positions     = static_cast<unsigned int>(p.get_integer("Reduction/Raceway ball positions"));
      r.footprints                 = read_footprints(p);
      r.study_fixed_interface      = counts(p, "Reduction/Study fixed-interface modes");
      r.study_interface            = counts(p, "Reduction/Study characteristic constraint modes");
      if (r.settings.n_fixed_interface_modes == 0 && r.settings.n_characteristic_constraint_modes > 0 &&
          r.settings.interface_shift_hz == 0.0)
        p.reject("Reduction/Interface shift", "must be > 0 when no fixed-interface mode is kept (it is derived from "
                                              "the lowest one otherwise)");
      const auto has = [&](BoundaryId id) {
        return std::find(r.settings.coupling_surfaces.begin(), r.settings.coupling_surfaces.end(), id) !=
               r.settings.coupling_surfaces.end();
      };
      if (r.grid_cells_circumferential > 0 && !has(r.grid_surface))
        p.reject("Reduction/Interface grid circumferential cells",
                 "needs " + fem::to_string(r.grid_surface) + " among Reduction/Coupling surfaces (the grid lies on " +
                   (housing ? "the housing bore" : "the ring outer surface") + "); set it to 0 for no grid");
      for (const BoundaryId clamped : r.clamped_surfaces)
        if (has(clamped))
          p.reject("Reduction/Clamped surfaces", fem::to_string(clamped) + " is also a coupling surface; a surface "
                                                 "is either held fixed or coupled");
      if (housing && r.raceway_ball_positions > 0)
        p.reject("Reduction/Raceway ball positions", "must be 0 for a housing (it has no raceway)");
      if (r.raceway_ball_positions > 0)
        {
          // The balls are placed on the Ring section's raceway all round.
          if (!r.body.gmsh_file.empty())
            p.reject("Reduction/Raceway ball positions", "needs Mesh/Source = parametric (the balls are placed on the "
                                                         "Ring section's raceway); set it to 0 for none");
          if (r.body.divisions.sector_angle < 2.0 * M_PI * (1 - 1e-12))
            p.reject("Reduction/Raceway ball positions", "needs the full ring (Divisions/Sector angle = 2 pi): the "
                                                         "balls go all round; set it to 0 for none");
          try
            {
              fem::raceway_patch_forces(reduction::unit_ball(r.body.ring, 0.0, r.footprints.back())); // the widest
            }
          catch (const std::invalid_argument &error)
            {
              p.reject("Reduction/Ball footprint transverse semi-axis", error.what());
            }
        }
      r.input_hash = reduction::fingerprint(input_text(p, r.body));
      r.provenance["program"]  = std::string("fretsim ") + FRETSIM_VERSION;
      r.provenance["mesh"]     = r.body.gmsh_file.empty() ? "parametric" : r.body.gmsh_file;
      r.provenance["coupling_surfaces"] = p.get("Reduction/Coupling surfaces");
      r.provenance["configuration"]     = p.file();
      r.provenance["parameters"]        = input_text(p, {});
      return r;
    }

    /// Progress of the reduction stages on one terminal line.
    class StageDisplay
    {
    public:
      explicit StageDisplay(bool enabled)
        : enabled(enabled && fem::ParallelEnvironment::rank() == 0)
      {}
      void operator()(const std::string &stage, double fraction)
      {
        if (!enabled)
          return;
        if (stage != current)
          {
            progress.reset();
            progress = std::make_unique<app::Progress>("reduce: " + stage, 1000, true);
            current  = stage;
          }
        progress->update(static_cast<long>(1000 * fraction), 0.0);
      }

    private:
      bool                      enabled;
      std::string               current;
      std::unique_ptr<app::Progress> progress;
    };

    fem::CylinderGrid interface_grid(const ReduceRequest &r)
    {
      if (r.grid_cells_circumferential == 0)
        return {};
      // the housing's bore too (line-to-line in the geometry)
      return fem::CylinderGrid::around(r.body.ring.outer_radius, r.body.ring.width,
                                       static_cast<int>(r.grid_cells_circumferential),
                                       static_cast<int>(r.grid_cells_axial));
    }

    /// Circumferential lines in the mid-plane, points at equal angles: the
    /// ring's raceway bottom (or bore) and outer surface, or the housing's bore
    /// and outside.
    std::vector<fem::Point3> sample_points(const ReduceRequest &r)
    {
      std::vector<fem::Point3> points;
      const auto &ring  = r.body.ring;
      const double inner = r.body.bodies == "housing" ? r.body.housing.bore_radius
                           : ring.has_groove()        ? ring.groove_bottom_radius
                                                      : ring.bore_radius;
      const double outer = r.body.bodies == "housing" ? r.body.housing.outer_radius : ring.outer_radius;
      for (const double radius : {inner, outer})
        for (unsigned int k = 0; k < r.points_per_line; ++k)
          {
            const double theta = 2.0 * M_PI * (k + 0.5) / r.points_per_line;
            points.push_back({radius * std::cos(theta), radius * std::sin(theta), 0.0});
          }
      return points;
    }

    /// Lowest `count` elastic frequencies (≥ 1 Hz) of a list.
    std::vector<double> elastic(const std::vector<double> &all, std::size_t count)
    {
      std::vector<double> result;
      for (const double f : all)
        if (f >= 1.0 && result.size() < count)
          result.push_back(f);
      return result;
    }

    /// Two opposite Hertz pressure patches on the outer surface (θ = 90° and
    /// 270°): a self-equilibrated squeeze such as a housing contact gives.
    fem::GridTractions squeeze_patches(const fem::CylinderGrid &grid, double force)
    {
      const double a = 0.004, b = 0.25 * grid.hy * grid.ny; // [m]
      return fem::hertz_patch_tractions(grid, {{0.25 * grid.nx * grid.hx, 0.0, a, b, force},
                                               {0.75 * grid.nx * grid.hx, 0.0, a, b, force}});
    }

    /// max |a - b| / max |b| over the entries.
    double relative_max_error(const std::vector<double> &a, const std::vector<double> &b)
    {
      double difference = 0.0, scale = 0.0;
      for (std::size_t k = 0; k < b.size(); ++k)
        {
          difference = std::max(difference, std::abs(a[k] - b[k]));
          scale      = std::max(scale, std::abs(b[k]));
        }
      return scale > 0.0 ? difference / scale : difference;
    }

    /// The full-FE references the reduced models are measured against.
    struct FullReference
    {
      std::vector<double> free_frequencies_hz; ///< lowest 10 elastic
      double              modal_seconds = 0.0;
      fem::GridTractions  squeeze;
      std::vector<double> squeeze_u_r, squeeze_stress; ///< on the interface grid
      double              static_seconds = 0.0;
      fem::StaticLoad     balls;                       ///< two opposite balls on the raceway
      std::vector<double> balls_u_r, balls_stress;
    };

    struct Accuracy
    {
      double frequency_error = 0.0;     ///< max relative error, lowest 10 free
      double static_displacement = -1;  ///< squeeze: max |Δu_r| / max |u_r| on the grid
      double static_stress       = -1;  ///< squeeze: max |Δσ| / max |σ| on the grid
      double balls_displacement  = -1;  ///< balls on the raceway: the same on the outer-surface grid
      double balls_stress        = -1;
      double reduced_static_seconds = 0.0;
    };

    std::vector<double> radial(const fem::GridDisplacements &d) { return d.u_r; }

    Accuracy measure(const reduction::CraigBampton &cb, const reduction::ReducedMatrices &reduced,
                     const std::vector<double> &free_hz, const FullReference &full, const fem::ElasticModel &model,
                     const fem::SurfaceGridMap *map, const fem::StressSampler *sampler)
    {
      Accuracy   a;
      const auto reduced_free = elastic(free_hz, full.free_frequencies_hz.size());
      for (std::size_t k = 0; k < std::min(reduced_free.size(), full.free_frequencies_hz.size()); ++k)
        a.frequency_error = std::max(a.frequency_error, std::abs(reduced_free[k] / full.free_frequencies_hz[k] - 1.0));
      if (reduced_free.size() < full.free_frequencies_hz.size())
        a.frequency_error = 1.0; // fewer modes than asked: the model cannot represent them
      if (map != nullptr)
        {
          fem::StaticLoad load;
          load.grid_tractions.push_back({map, &full.squeeze});
          const auto start      = Clock::now();
          const auto u          = cb.reduced_static(load, reduced);
          a.reduced_static_seconds = seconds_since(start);
          a.static_displacement = relative_max_error(radial(map->interpolate(u)), full.squeeze_u_r);
          a.static_stress       = relative_max_error(sampler->evaluate(u), full.squeeze_stress);
          if (full.balls.ball_loads.empty())
            return a;
          const auto u_balls    = cb.reduced_static(full.balls, reduced);
          a.balls_displacement  = relative_max_error(radial(map->interpolate(u_balls)), full.balls_u_r);
          a.balls_stress        = relative_max_error(sampler->evaluate(u_balls), full.balls_stress);
        }
      (void)model;
      return a;
    }

    void print_comparison(std::ostream &out, const std::vector<double> &full, const std::vector<double> &reduced)
    {
      out << "  mode   full FE [Hz]   reduced [Hz]   error\n";
      for (std::size_t k = 0; k < full.size(); ++k)
        {
          const double r = k < reduced.size() ? reduced[k] : 0.0;
          out << "  " << std::setw(4) << k + 1 << std::setw(15) << std::fixed << std::setprecision(2) << full[k]
              << std::setw(15) << r << "   " << std::scientific << std::setprecision(2) << (r / full[k] - 1.0)
              << std::defaultfloat << "\n";
        }
    }

    /// The full-FE references: lowest 10 free modes, and the static squeeze
    /// on the interface grid (if there is one).
    FullReference full_reference(fem::ElasticModel &model, const reduction::CraigBampton &cb,
                                 const fem::CylinderGrid &grid, const ReduceRequest &request,
                                 std::unique_ptr<fem::SurfaceGridMap> &map,
                                 std::unique_ptr<fem::StressSampler> &sampler)
    {
      FullReference      full;
      fem::ModalSettings modal;
      modal.n_modes            = 10;
      modal.tolerance          = request.settings.eigen_tolerance;
      const auto modes         = model.solve_modes(modal);
      full.free_frequencies_hz = modes.frequencies_hz;
      full.modal_seconds       = modes.seconds;
      // Two balls pressing outwards at θ = 90° and 270° (2 kN each, with the
      // raceway operator's footprint of that load; the fixed default is near
      // the ellipse of a 6208 ball at 2 kN): self-equilibrated, so the free
      // ring needs no support. A housing has no raceway.
      if (request.body.bodies == "ring")
        for (const double angle : {0.5 * M_PI, 1.5 * M_PI})
          {
            constexpr double     force = 2000.0;
            fem::RacewayBallLoad ball  = reduction::unit_ball(request.body.ring, angle, footprint_at(request, force));
            ball.force                 = force;
            full.balls.ball_loads.push_back(ball);
          }
      if (grid.nx > 0)
        {
          map          = std::make_unique<fem::SurfaceGridMap>(model, request.grid_surface, grid);
          sampler      = std::make_unique<fem::StressSampler>(fem::StressSampler::on_grid(model, grid));
          full.squeeze = squeeze_patches(grid, 5000.0);
          fem::StaticLoad load;
          load.grid_tractions.push_back({map.get(), &full.squeeze});
          const auto start    = Clock::now();
          const auto u        = cb.full_static(load);
          full.static_seconds = seconds_since(start);
          full.squeeze_u_r    = radial(map->interpolate(u));
          full.squeeze_stress = sampler->evaluate(u);
          if (full.balls.ball_loads.empty())
            return full;
          const auto u_balls  = cb.full_static(full.balls);
          full.balls_u_r      = radial(map->interpolate(u_balls));
          full.balls_stress   = sampler->evaluate(u_balls);
        }
      return full;
    }

    /// The raceway's outward approach at the first ball of `balls`, in the
    /// full FE solution and in the reduced one: fᵀu with f the load vector of
    /// that ball at 1 N, the work-conjugate measure that the raceway operator
    /// stores (one point map on both fields, so both are measured alike) [m].
    struct RacewayApproach
    {
      double full = 0.0, reduced = 0.0;
    };

    RacewayApproach raceway_approach(const fem::ElasticModel &model, const reduction::CraigBampton &cb,
                                     const reduction::ReducedMatrices &reduced, const fem::StaticLoad &balls)
    {
      fem::RacewayBallLoad unit = balls.ball_loads.front();
      unit.force                = 1.0;
      const fem::PatchForces     patch = fem::raceway_patch_forces(unit);
      const fem::SurfacePointMap map(model, patch.points, BoundaryId::raceway);
      const auto approach = [&](const fem::DisplacementField &u) {
        const std::vector<fem::Vector3> at_points = map.interpolate(u);
        double                          work      = 0.0;
        for (std::size_t p = 0; p < at_points.size(); ++p)
          for (unsigned int d = 0; d < 3; ++d)
            work += patch.forces[p][d] * at_points[p][d];
        return work;
      };
      return {approach(cb.full_static(balls)), approach(cb.reduced_static(balls, reduced))};
    }

    std::string default_output(const RingHousingCommandOptions &options, const std::string &suffix)
    {
      return (std::filesystem::path("results") / (std::filesystem::path(options.config_file).stem().string() + suffix))
        .string();
    }
  } // namespace

  namespace
  {
    ParameterSpec real_list(ParameterSpec spec)
    {
      spec.kind = ParameterSpec::Kind::real_list;
      return spec;
    }

    ParameterSpec increasing_real_list(ParameterSpec spec)
    {
      spec.increasing = true;
      return real_list(spec);
    }
  } // namespace

  std::vector<ParameterSpec> reduce_parameter_specs()
  {
    using Spec = ParameterSpec;
    Spec surfaces;
    surfaces.path          = "Reduction/Coupling surfaces";
    surfaces.kind          = Spec::Kind::text;
    surfaces.default_value = "ring_outer";
    surfaces.doc = "Comma-separated boundary names whose nodes are the Craig-Bampton boundary DoFs: ring_outer (the "
                   "housing interface, where the contact grid lies), optionally raceway; for a housing (Mesh/Bodies "
                   "= housing) housing_bore [-].";
    Spec clamped = surfaces;
    clamped.path          = "Reduction/Clamped surfaces";
    clamped.default_value = "";
    clamped.doc = "Comma-separated boundary names held fixed (zero displacement), e.g. housing_outer for a housing "
                  "held at its outside; empty: a free body (the outer ring) [-].";
    Spec study_m = Spec::real_range("Reduction/Study fixed-interface modes", "5, 10, 20, 40",
                                    "Fixed-interface mode counts m tried by `reduce --study` [-].", 0, 5000);
    study_m.kind = Spec::Kind::real_list;
    Spec study_cc = Spec::real_range("Reduction/Study characteristic constraint modes", "20, 40, 80, 120",
                                     "Characteristic constraint mode counts n_cc tried by `reduce --study` [-].", 1,
                                     5000);
    study_cc.kind = Spec::Kind::real_list;
    return {surfaces,
            clamped,
            Spec::integer_range("Reduction/Fixed-interface modes", "40",
                                "m: fixed-interface normal modes kept (boundary clamped) [-].", 0, 5000),
            Spec::integer_range("Reduction/Characteristic constraint modes", "120",
                                "n_cc: characteristic constraint modes kept (eigenmodes of the Guyan-condensed "
                                "interface, the six rigid-body motions among them); 0 keeps one constraint mode per "
                                "boundary DoF (small meshes only) [-].",
                                0, 5000),
            Spec::non_negative("Reduction/Interface shift", "0",
                               "Steering shift f of the interface eigen-search, sigma = -(2 pi f)^2; 0 picks f_1/50 "
                               "with f_1 the lowest fixed-interface frequency [Hz]."),
            Spec::real_range("Reduction/Eigen tolerance", "1e-10", "Relative residual of the eigen-solves [-].",
                             1e-14, 1e-3),
            Spec::integer_range("Reduction/Interface grid circumferential cells", "360",
                                "Cells around the ring outer surface of the contact grid whose modal displacement "
                                "and stress operators are stored; 0: no grid [-].",
                                0, 100000),
            Spec::integer_range("Reduction/Interface grid axial cells", "16",
                                "Cells across the width of that grid [-].", 1, 10000),
            Spec::integer_range("Reduction/Sample points per line", "72",
                                "Stress sample points on each of two circumferential lines in the mid-plane: the "
                                "raceway bottom and the outer surface [-].",
                                0, 100000),
            Spec::integer_range("Reduction/Raceway ball positions", "720",
                                "Ball positions psi_k = 2 pi k / n around the raceway (contact angle 0) at which the "
                                "raceway operator is stored: the generalised force of a unit ball load there, whose "
                                "product with the modal coordinates is the raceway's outward approach; the "
                                "co-simulation interpolates linearly between them. Needs the full parametric ring; "
                                "0: none [-].",
                                0, 100000),
            real_list(Spec::real_range("Reduction/Ball footprint circumferential semi-axis", "0.3e-3",
                                            "Semi-axis a along the circumference of the Hertz ellipse of the unit "
                                            "ball loads, one per Ball footprint load; with no load one fixed "
                                            "footprint (near that of a 6208 ball at 2 kN) [m].",
                                            0.0, 0.01, true)),
            real_list(Spec::real_range("Reduction/Ball footprint transverse semi-axis", "1.3e-3",
                                            "Semi-axis b of those ellipses along the groove arc, or axially on a plain "
                                            "bore; each must stay on the groove arc [m].",
                                            0.0, 0.01, true)),
            increasing_real_list(Spec::real_range("Reduction/Ball footprint loads", "",
                                             "Ball loads whose Hertz ellipses the footprints are (semi-axes as "
                                             "load^(1/3)): the raceway operator and the ring's residual flexibility "
                                             "under a ball are stored for each, and a run interpolates each ball's "
                                             "between them at its load; empty: one fixed footprint (the bearing scene "
                                             "sets them from its balls unless Model/Ball footprint = fixed) [N].",
                                             0.0, 1e9, true)),
            Spec::selection("Reduction/Compare with full FE", "true",
                            "Also solve the full FE model (lowest 10 free modes, a static squeeze of the outer "
                            "surface, two balls on the raceway and the raceway approach under them) and report the "
                            "reduced model's error against it [-].",
                            "true|false"),
            study_m,
            study_cc};
  }

  namespace
  {
    /// The full FE model of the body the request names, its supports applied.
    /// Prints its size and set-up time on rank 0.
    fem::ElasticModel build_full_model(const ReduceRequest &request, const std::string &config_file,
                                       std::ostream &out)
    {
      const auto start = Clock::now();
      auto mesh = std::make_shared<const fem::Mesh>(build_ring_housing_mesh(request.body, config_file));
      fem::ElasticModel model(mesh, request.body.materials, request.body.degree, supports(request.clamped_surfaces));
      const double      setup_seconds = seconds_since(start);
      if (fem::ParallelEnvironment::rank() == 0)
        out << "full model:   " << model.n_dofs() << " DoFs (FE_Q" << request.body.degree
            << "), set up and K assembled in " << std::fixed << std::setprecision(2) << setup_seconds << " s\n"
            << std::defaultfloat;
      return model;
    }

    /// The reduced matrices and their frequencies; a basis the settings
    /// cannot make is an InputError of the Reduction section.
    void reduce_matrices(reduction::CraigBampton &cb, const std::string &config_file, reduction::ReducedModel &result)
    {
      try
        {
          result.matrices = cb.run();
        }
      catch (const std::invalid_argument &error)
        {
          throw InputError(config_file, "Reduction", error.what());
        }
      result.free_frequencies_hz = reduction::reduced_frequencies_hz(result.matrices);
      result.timings             = cb.timings();
    }

    struct OperatorTimes
    {
      double grid_and_points = 0.0, raceway = 0.0; ///< [s]
    };

    /// The interface grid, sample point and raceway operators of the basis.
    OperatorTimes add_operators(const reduction::CraigBampton &cb, const fem::ElasticModel &model,
                                const ReduceRequest &request, const fem::CylinderGrid &grid,
                                const std::string &config_file, reduction::ReducedModel &result)
    {
      OperatorTimes times;
      const auto    operator_start = Clock::now();
      if (grid.nx > 0)
        result.interface_grid = reduction::grid_operators(cb, model, request.grid_surface, grid);
      result.sample_points  = reduction::point_operators(cb, model, sample_points(request));
      times.grid_and_points = seconds_since(operator_start);
      const auto raceway_start = Clock::now();
      try
        {
          result.raceway = reduction::raceway_operators(cb, model, request.body.ring, request.raceway_ball_positions,
                                                        request.footprints);
        }
      catch (const std::invalid_argument &error) // a patch point the mesh's raceway does not hold
        {
          throw InputError(config_file, "Reduction/Raceway ball positions", error.what());
        }
      times.raceway = seconds_since(raceway_start);
      return times;
    }

    /// The basis's residual flexibility on the interface grid, for the
    /// co-simulation's local compliance (Interface/Ring residual flexibility,
    /// Interface/Housing residual flexibility): a free ring with a raceway and
    /// a grid (inertia relief needs the six rigid motions among the
    /// coordinates), or a housing held somewhere with a grid on its bore.
    /// Pressure only: that is what the co-simulation uses.
    void add_residual_flexibility(fem::ElasticModel &model, const ReduceRequest &request,
                                  const fem::CylinderGrid &grid, StageDisplay &display,
                                  reduction::ReducedModel &result)
    {
      if (request.body.bodies == "housing" && !request.clamped_surfaces.empty() && grid.nx > 0 &&
          request.grid_surface == fem::BoundaryId::housing_bore)
        {
          display("residual flexibility", 0.0);
          fem::ShiftedStaticSolver  solver(model, 0.0);
          const fem::SurfaceGridMap map(model, request.grid_surface, grid);
          result.residual = residual_flexibility(solver, map, whole_model(result, 0.0), grid, request.body.ring, {}, 1,
                                                 true);
        }
      if (request.body.bodies == "ring" && request.clamped_surfaces.empty() && grid.nx > 0 &&
          !result.raceway.angles.empty() && starts_with_rigid_motions(result.matrices))
        {
          display("residual flexibility", 0.0);
          fem::ShiftedStaticSolver  solver(model, request.settings.static_shift_hz, /*inertia_relief=*/true);
          const fem::SurfaceGridMap map(model, request.grid_surface, grid);
          const Truncation          whole = whole_model(result, solver.shift());
          result.residual = residual_flexibility(solver, map, whole, grid, request.body.ring, request.footprints, 1);
        }
    }

    /// What the reduction made and how long it took (rank 0 prints).
    void print_reduction(std::ostream &out, const reduction::ReducedModel &result, const ReduceRequest &request,
                         const std::string &coupling_surfaces, const OperatorTimes &times)
    {
      const auto &m = result.matrices;
      out << "boundary:     " << m.n_boundary_dofs << " DoFs on " << coupling_surfaces << ", interior "
          << m.n_interior_dofs << "\n"
          << "reduced:      " << m.size() << " coordinates = " << m.n_constraint
          << " characteristic constraint modes + " << m.n_modal << " fixed-interface modes\n"
          << std::fixed << std::setprecision(2) << "reduction:    " << result.timings.total << " s (partition "
          << result.timings.partition << ", factorisation " << result.timings.factorisation
          << ", fixed-interface modes " << result.timings.fixed_interface_modes << ", interface modes "
          << result.timings.interface_modes << ", constraint modes " << result.timings.constraint_modes
          << ", reduced matrices " << result.timings.reduced_matrices << "); operators " << times.grid_and_points
          << " s\n";
      if (!result.raceway.angles.empty())
        {
          out << "raceway:      " << result.raceway.angles.size() << " ball positions, footprint" << std::defaultfloat
              << std::setprecision(3);
          for (const reduction::BallFootprint &f : request.footprints)
            {
              out << (&f == &request.footprints.front() ? " " : ", ") << 1e3 * f.semi_axis_circumferential << " x "
                  << 1e3 * f.semi_axis_transverse << " mm";
              if (f.load > 0.0)
                out << " (" << f.load << " N)";
            }
          out << " in " << std::fixed << std::setprecision(2) << times.raceway << " s\n";
        }
      if (!result.residual.empty())
        out << "residual:     R = K^-1 - T K_r^-1 T^T of the pressure on the interface grid"
            << (result.residual.ball.empty() ? "" : " and of a ball") << ", from " << result.residual.solves
            << " full and reduced solves in " << std::setprecision(2) << result.residual.seconds << " s\n";
      out << std::scientific << std::setprecision(1) << "symmetry:     |K_r - K_r^T| " << m.stiffness_asymmetry
          << ", |M_r - M_r^T| " << m.mass_asymmetry << " (relative)\n"
          << std::defaultfloat;
    }

    /// Reduced against full FE: frequencies, a static squeeze, two balls and
    /// the raceway approach, printed on rank 0; the full frequencies and the
    /// frequency error go into the provenance.
    void compare_with_full_model(fem::ElasticModel &model, const reduction::CraigBampton &cb,
                                 const fem::CylinderGrid &grid, const ReduceRequest &request, std::ostream &out,
                                 reduction::ReducedModel &result)
    {
      const bool                           root = fem::ParallelEnvironment::rank() == 0;
      const auto                          &m    = result.matrices;
      std::unique_ptr<fem::SurfaceGridMap> map;
      std::unique_ptr<fem::StressSampler>  sampler;
      const FullReference full     = full_reference(model, cb, grid, request, map, sampler);
      const Accuracy      accuracy = measure(cb, m, result.free_frequencies_hz, full, model, map.get(), sampler.get());
      if (root)
        {
          out << (request.clamped_surfaces.empty() ? "lowest 10 free-free elastic modes"
                                                   : "lowest 10 modes (clamped supports)")
              << " (full FE modal solve " << std::fixed << std::setprecision(2) << full.modal_seconds << " s):\n"
              << std::defaultfloat;
          print_comparison(out, full.free_frequencies_hz, elastic(result.free_frequencies_hz, 10));
          out << std::scientific << std::setprecision(2) << "max frequency error: " << accuracy.frequency_error
              << "\n";
          if (map)
            out << "static squeeze of the interface surface (2 x 5 kN Hertz patches): u_r error "
                << accuracy.static_displacement << ", stress error " << accuracy.static_stress
                << " (max-norm, relative); full solve " << std::fixed << std::setprecision(3) << full.static_seconds
                << " s (factorisation included), reduced " << accuracy.reduced_static_seconds << " s\n";
          if (map && !full.balls.ball_loads.empty())
            out << "static balls on the raceway (2 x 2 kN, opposite): outer-surface u_r error " << std::scientific
                << std::setprecision(2) << accuracy.balls_displacement << ", stress error " << accuracy.balls_stress
                << "\n";
          out << std::defaultfloat;
        }
      if (!result.raceway.angles.empty())
        {
          // The difference is the indentation-scale compliance under the
          // footprint, which the reduced model does not carry (docs/bearing.md).
          const RacewayApproach approach = raceway_approach(model, cb, m, full.balls);
          if (root)
            out << std::scientific << std::setprecision(4)
                << "raceway approach under a 2 kN ball at 90 deg (the opposite one at 270 deg): full "
                << approach.full << " m, reduced " << approach.reduced << " m, difference "
                << approach.full - approach.reduced << " m\n"
                << std::defaultfloat;
        }
      std::ostringstream frequencies;
      frequencies << std::setprecision(10);
      for (const double f : full.free_frequencies_hz)
        frequencies << f << ' ';
      result.provenance["full_free_frequencies_hz"]      = frequencies.str();
      result.provenance["max_frequency_error_lowest_10"] = std::to_string(accuracy.frequency_error);
    }
  } // namespace

  std::vector<std::string> write_reduced_model(const RingHousingCommandOptions &options, std::ostream &out)
  {
    // Everything that can be checked without MPI is checked before MPI starts.
    const SceneParameters parameters = read_ring_housing_parameters(options.config_file, options.overrides);
    ReduceRequest         request    = read_request(parameters);
    const std::string     model_path = options.output.empty() ? default_output(options, "-model.h5") : options.output;

    // MPI starts once per process: a scene building two models runs both in its own.
    std::unique_ptr<fem::ParallelEnvironment> mpi;
    if (!fem::ParallelEnvironment::active())
      mpi = std::make_unique<fem::ParallelEnvironment>();
    const bool        root  = fem::ParallelEnvironment::rank() == 0;
    fem::ElasticModel model = build_full_model(request, options.config_file, out);

    StageDisplay display(options.progress);
    request.settings.progress = [&](const std::string &stage, double fraction) { display(stage, fraction); };
    reduction::CraigBampton cb(model, request.settings);
    reduction::ReducedModel result;
    reduce_matrices(cb, options.config_file, result);
    const fem::CylinderGrid grid  = interface_grid(request);
    const OperatorTimes     times = add_operators(cb, model, request, grid, options.config_file, result);
    add_residual_flexibility(model, request, grid, display, result);
    display("done", 1.0);

    result.input_hash = request.input_hash;
    result.provenance = request.provenance;
    result.provenance["boundary_dofs"]  = std::to_string(result.matrices.n_boundary_dofs);
    result.provenance["full_dofs"]      = std::to_string(model.n_dofs());
    result.provenance["element_degree"] = std::to_string(request.body.degree);
    if (root)
      print_reduction(out, result, request, parameters.get("Reduction/Coupling surfaces"), times);
    if (request.compare_with_full)
      compare_with_full_model(model, cb, grid, request, out, result);

    std::vector<std::string> files;
    if (root) // one list for the whole job: the CLI prints what it gets back
      {
        if (const auto parent = std::filesystem::path(model_path).parent_path(); !parent.empty())
          std::filesystem::create_directories(parent);
        reduction::write_model_file(model_path, result);
        out << "input hash:   " << result.input_hash << "\n";
        files.push_back(model_path);
      }
    return files;
  }

  std::string reduce_input_hash(const std::string &config_file,
                                const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    return read_request(read_ring_housing_parameters(config_file, overrides)).input_hash;
  }

  std::vector<fem::Support> reduction_supports(const std::string &config_file)
  {
    return supports(read_request(read_ring_housing_parameters(config_file, {})).clamped_surfaces);
  }

  HousingAround read_housing_around(const std::string &config_file, const fem::RingGeometry &ring,
                                    const std::string &source, const std::string &parameter)
  {
    const auto reject = [&](const std::string &problem) { throw InputError(source, parameter, problem); };
    HousingAround housing;
    housing.request = read_ring_housing_request(read_ring_housing_parameters(config_file, {}));
    if (housing.request.bodies != "housing")
      reject("names '" + config_file + "' with Mesh/Bodies = " + housing.request.bodies +
             "; expected the housing alone (Mesh/Bodies = housing)");
    const fem::HousingGeometry &bore = housing.request.housing;
    if (std::abs(bore.bore_radius - ring.outer_radius) > 1e-9 * ring.outer_radius ||
        std::abs(bore.width - ring.width) > 1e-9 * ring.width)
      reject("the housing bore in '" + config_file +
             "' must have the ring's outer radius and width (Ring/Outer radius, Ring/Width): the fit is set by "
             "Interface/Radial interference");
    housing.supports = reduction_supports(config_file);
    if (housing.supports.empty())
      reject("names '" + config_file + "', which holds the housing nowhere (Reduction/Clamped surfaces is empty)");
    return housing;
  }

  std::vector<std::string> run_reduction_study(const RingHousingCommandOptions &options, std::ostream &out)
  {
    const SceneParameters parameters = read_ring_housing_parameters(options.config_file, options.overrides);
    ReduceRequest         request    = read_request(parameters);
    const std::string directory = options.output.empty() ? default_output(options, "-reduction-study") : options.output;

    const fem::ParallelEnvironment mpi;
    const bool                     root = fem::ParallelEnvironment::rank() == 0;
    auto mesh = std::make_shared<const fem::Mesh>(build_ring_housing_mesh(request.body, options.config_file));
    fem::ElasticModel model(mesh, request.body.materials, request.body.degree, supports(request.clamped_surfaces));
    const fem::CylinderGrid grid = interface_grid(request);

    // The references, with the boundary free and with it clamped.
    reduction::ReductionSettings reference_settings = request.settings;
    reference_settings.n_fixed_interface_modes      = 10;
    reference_settings.n_characteristic_constraint_modes = std::max(request.study_interface.front(), 7u);
    reduction::CraigBampton reference_basis(model, reference_settings);
    reference_basis.run();
    std::unique_ptr<fem::SurfaceGridMap> map;
    std::unique_ptr<fem::StressSampler>  sampler;
    const FullReference full = full_reference(model, reference_basis, grid, request, map, sampler);
    auto all_clamped = request.clamped_surfaces;
    all_clamped.insert(all_clamped.end(), request.settings.coupling_surfaces.begin(),
                       request.settings.coupling_surfaces.end());
    fem::ElasticModel  clamped(mesh, request.body.materials, request.body.degree, supports(all_clamped));
    fem::ModalSettings modal;
    modal.n_modes             = 10;
    modal.tolerance           = request.settings.eigen_tolerance;
    const auto clamped_modes  = clamped.solve_modes(modal);
    if (root)
      out << "full model: " << model.n_dofs() << " DoFs; lowest free mode " << full.free_frequencies_hz.front()
          << " Hz (modal solve " << full.modal_seconds << " s), lowest clamped-boundary mode "
          << clamped_modes.frequencies_hz.front() << " Hz\n";

    std::filesystem::create_directories(directory);
    const std::string csv_path = (std::filesystem::path(directory) / "reduction_study.csv").string();
    std::ofstream     csv;
    if (root)
      {
        csv.open(csv_path);
        csv << "fixed_interface_modes,interface_modes,reduced_size,reduction_s,free_error,clamped_error,"
               "static_displacement_error,static_stress_error,full_static_s,reduced_static_s,balls_displacement_error,"
               "balls_stress_error\n";
        out << "     m   n_cc   size   time [s]   free err   clamped err   squeeze u_r err   squeeze stress err"
               "   balls u_r err   balls stress err\n";
      }
    for (const unsigned int m : request.study_fixed_interface)
      for (const unsigned int n_cc : request.study_interface)
        {
          reduction::ReductionSettings settings      = request.settings;
          settings.n_fixed_interface_modes           = m;
          settings.n_characteristic_constraint_modes = n_cc;
          if (m == 0 && settings.interface_shift_hz == 0.0)
            settings.interface_shift_hz = clamped_modes.frequencies_hz.front() / 50.0;
          settings.progress = nullptr;
          reduction::CraigBampton cb(model, settings);
          reduction::ReducedMatrices reduced;
          try
            {
              reduced = cb.run();
            }
          catch (const std::invalid_argument &error)
            {
              throw InputError(options.config_file, "Reduction/Study characteristic constraint modes", error.what());
            }
          const Accuracy a = measure(cb, reduced, reduction::reduced_frequencies_hz(reduced), full, model, map.get(),
                                     sampler.get());
          double clamped_error = m < 10 ? 1.0 : 0.0;
          for (unsigned int k = 0; k < std::min(m, 10u); ++k)
            clamped_error = std::max(clamped_error, std::abs(reduced.fixed_interface_frequencies_hz[k] /
                                                               clamped_modes.frequencies_hz[k] - 1.0));
          if (root)
            {
              csv << m << ',' << n_cc << ',' << reduced.size() << ',' << cb.timings().total << ','
                  << a.frequency_error << ',' << clamped_error << ',' << a.static_displacement << ','
                  << a.static_stress << ',' << full.static_seconds << ',' << a.reduced_static_seconds << ','
                  << a.balls_displacement << ',' << a.balls_stress << '\n';
              out << std::setw(6) << m << std::setw(7) << n_cc << std::setw(7) << reduced.size() << std::fixed
                  << std::setprecision(2) << std::setw(11) << cb.timings().total << std::scientific
                  << std::setprecision(2) << std::setw(11) << a.frequency_error << std::setw(14) << clamped_error
                  << std::setw(18) << a.static_displacement << std::setw(21) << a.static_stress << std::setw(16)
                  << a.balls_displacement << std::setw(19) << a.balls_stress << "\n"
                  << std::defaultfloat;
            }
        }
    if (!root)
      return {};
    return {csv_path};
  }
} // namespace fretsim::models
