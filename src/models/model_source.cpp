#include <fretsim/models/model_source.h>

#include <fretsim/models/reduction.h>

#include <fretsim/contact/material.h>
#include <fretsim/coupling/bearing.h>
#include <fretsim/fem/parallel_environment.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <tuple>

namespace fretsim::models
{
  namespace
  {
    /// The configuration named by `config_parameter` (relative to the
    /// scene's file) and its model file (`file_parameter`; empty: results/
    /// <configuration name>-model.h5, where `fretsim reduce` writes it).
    ModelSource model_source(const app::SceneParameters &par, const std::string &config_parameter,
                             const std::string &file_parameter)
    {
      namespace fs = std::filesystem;
      ModelSource source;
      source.config = (fs::path(par.file()).parent_path() / par.get(config_parameter)).lexically_normal().string();
      std::error_code error; // a name too long for the file system is a missing file, not a crash
      if (!fs::is_regular_file(source.config, error))
        par.reject(config_parameter, "no file '" + source.config + "'" + (error ? " (" + error.message() + ")" : ""));
      source.file = par.get(file_parameter);
      if (source.file.empty())
        source.file = (fs::path("results") / (fs::path(source.config).stem().string() + "-model.h5")).string();
      source.file_parameter = file_parameter;
      return source;
    }

    /// The basis sizes the scene sets over the configuration's (`fixed`: m,
    /// `modes`: n_cc; 0 keeps the configuration's) as reduction overrides;
    /// returns the tag they add to the model file's name, "-m<m>-ncc<n_cc>".
    std::string basis_overrides(const app::SceneParameters &par, const char *fixed, const char *modes,
                                ModelSource &source)
    {
      std::string suffix;
      for (const auto &[parameter, reduction, tag] :
           {std::tuple<const char *, const char *, const char *>{fixed, "Reduction/Fixed-interface modes", "-m"},
            {modes, "Reduction/Characteristic constraint modes", "-ncc"}})
        if (const long count = par.get_integer(parameter); count > 0)
          {
            source.overrides.emplace_back(reduction, std::to_string(count));
            suffix += tag + std::to_string(count);
          }
      return suffix;
    }

    /// The model file named after its overrides' tag: model.h5 ->
    /// model-ncc40.h5, results/ring-model.h5 -> results/ring-ncc40-model.h5.
    void tag_file(const app::SceneParameters &par, const std::string &suffix, ModelSource &source)
    {
      namespace fs = std::filesystem;
      if (suffix.empty())
        return;
      const fs::path file          = source.file;
      std::string    stem          = file.stem().string();
      const bool     named_default = par.get(source.file_parameter).empty();
      stem = named_default ? stem.substr(0, stem.size() - std::string("-model").size()) + suffix + "-model" : stem + suffix;
      source.file = (file.parent_path() / (stem + file.extension().string())).string();
    }

    /// The ring's raceway footprints as reduction parameters: with
    /// Model/Ball footprint = load following, the Hertz ellipses of a ball on
    /// the outer raceway (Bearing/..., the ring's groove and material) at
    /// Model/Ball footprints loads up to the one whose peak pressure reaches
    /// ISO 76's static limit; fixed (or a ring without a groove, which the
    /// scene refuses): none, the configuration's own.
    std::vector<std::pair<std::string, std::string>> footprint_overrides(const app::SceneParameters &par,
                                                                         const std::string &config)
    {
      if (par.get("Model/Ball footprint") == "fixed")
        return {};
      const RingHousingRequest body = read_ring_housing_request(read_ring_housing_parameters(config, {}));
      if (!body.ring.has_groove())
        return {};
      coupling::BearingGeometry bearing;
      bearing.ball_diameter           = par.get_double("Bearing/Ball diameter");
      bearing.pitch_diameter          = 2.0 * body.ring.groove_bottom_radius - bearing.ball_diameter;
      bearing.outer_groove_conformity = body.ring.groove_radius / bearing.ball_diameter;
      bearing.inner_groove_conformity = par.get_double("Bearing/Inner groove conformity");
      const fem::Material &ring       = body.materials.at(fem::MaterialId::ring);
      const double         modulus =
        contact::MaterialPair{{ring.youngs_modulus, ring.poisson_ratio},
                              {par.get_double("Bearing/Young's modulus"), par.get_double("Bearing/Poisson ratio")}}
          .contact_modulus();
      coupling::OuterContactEllipse ellipse;
      try
        {
          ellipse = coupling::outer_contact_ellipse(bearing, modulus);
        }
      catch (const std::invalid_argument &error)
        {
          par.reject("Bearing/Ball diameter", error.what());
        }
      const long count = par.get_integer("Model/Ball footprints");
      if (count % 2 == 0)
        par.reject("Model/Ball footprints", "expected an odd number (the rows are interpolated over pieces of three), "
                                            "got " + std::to_string(count));
      const auto loads =
        ellipse.footprint_loads(coupling::static_limit_peak_pressure, static_cast<unsigned int>(count));
      std::ostringstream load_list, a_list, b_list;
      for (auto *list : {&load_list, &a_list, &b_list})
        *list << std::setprecision(17);
      for (std::size_t f = 0; f < loads.size(); ++f)
        {
          const double      scale     = std::cbrt(loads[f]);
          const char *const separator = f == 0 ? "" : ", ";
          load_list << separator << loads[f];
          a_list << separator << scale * ellipse.semi_axis_rolling_per_newton_cube_root;
          b_list << separator << scale * ellipse.semi_axis_transverse_per_newton_cube_root;
        }
      return {{"Reduction/Ball footprint loads", load_list.str()},
              {"Reduction/Ball footprint circumferential semi-axis", a_list.str()},
              {"Reduction/Ball footprint transverse semi-axis", b_list.str()}};
    }
  } // namespace

  ModelSource ring_model_source(const app::SceneParameters &par)
  {
    ModelSource source = model_source(par, "Model/Reduction configuration", "Model/Model file");
    // The basis sizes over the configuration's: a study of D_max against the
    // ring's basis is one `--set` per run, each model in its own file.
    std::string suffix = basis_overrides(par, "Model/Fixed-interface modes", "Model/Characteristic constraint modes",
                                         source);
    source.footprint_overrides = footprint_overrides(par, source.config);
    if (!source.footprint_overrides.empty())
      {
        source.overrides.insert(source.overrides.end(), source.footprint_overrides.begin(),
                                source.footprint_overrides.end());
        source.footprint_tag = "-hertz";
        suffix += source.footprint_tag;
      }
    tag_file(par, suffix, source);
    source.expected_hash = reduce_input_hash(source.config, source.overrides);
    return source;
  }

  ModelSource housing_model_source(const app::SceneParameters &par)
  {
    ModelSource source = model_source(par, "Model/Housing reduction configuration", "Model/Housing model file");
    tag_file(par,
             basis_overrides(par, "Model/Housing fixed-interface modes", "Model/Housing characteristic constraint modes",
                             source),
             source);
    source.expected_hash = reduce_input_hash(source.config, source.overrides);
    return source;
  }

  RingStressSource ring_stress_source(const app::SceneParameters &par, const ModelSource &ring,
                                      const std::vector<double> &depths)
  {
    namespace fs             = std::filesystem;
    const std::string mesh   = par.get("Stresses/Ring mesh");
    const auto        counts = app::parse_cell_counts(mesh, 4);
    if (counts.empty() || counts[0] < 3)
      par.reject("Stresses/Ring mesh", "expected 'around x radial x axial x axial land' cells (whole numbers >= 1, "
                                       "at least 3 around), got '" + mesh + "'");
    RingStressSource source;
    source.config                    = ring.config;
    source.footprint_overrides       = ring.footprint_overrides;
    source.divisions.circumferential = static_cast<unsigned int>(counts[0]);
    source.divisions.radial_ring     = static_cast<unsigned int>(counts[1]);
    source.divisions.axial           = static_cast<unsigned int>(counts[2]);
    source.divisions.axial_land      = static_cast<unsigned int>(counts[3]);
    source.divisions.radial_grading  = par.get_double("Stresses/Ring mesh radial grading");
    source.depths                    = depths;
    source.file = (fs::path(ring.file).parent_path() /
                   (fs::path(ring.config).stem().string() + ring.footprint_tag + "-stress-tables.h5"))
                    .string();
    source.expected_hash = ring_stress_hash(source);
    return source;
  }

  namespace
  {
    /// Rank 0 under MPI, or the only process: the one that reports.
    bool first_rank() { return !fem::ParallelEnvironment::active() || fem::ParallelEnvironment::rank() == 0; }
  } // namespace

  ModelLoader::ModelLoader(bool build_if_missing, bool progress)
    : build_if_missing(build_if_missing)
    , progress(progress)
  {}

  ModelLoader::~ModelLoader() = default;

  reduction::ReducedModel ModelLoader::load(const ModelSource &source, const app::SceneParameters &scene)
  {
    try
      {
        return reduction::read_model_file(source.file, source.expected_hash);
      }
    catch (const reduction::ModelFileError &error)
      {
        if (!build_if_missing)
          scene.reject(source.file_parameter, error.what());
        if (first_rank())
          {
            std::cerr << "bearing_housing: " << error.what() << "\n  building it with `fretsim reduce "
                      << source.config << " -o " << source.file;
            for (const auto &[name, value] : source.overrides)
              std::cerr << " --set '" << name << "=" << value << "'";
            std::cerr << "` (about 2 minutes for the 6208 ring or housing)\n";
          }
        RingHousingCommandOptions reduce;
        reduce.config_file = source.config;
        reduce.output      = source.file;
        reduce.overrides   = source.overrides;
        reduce.overrides.emplace_back("Reduction/Compare with full FE", "false");
        reduce.progress    = progress;
        reduce.plots       = false;
        if (!fem::ParallelEnvironment::active())
          mpi = std::make_unique<fem::ParallelEnvironment>();
        write_reduced_model(reduce, std::cerr);
        fem::ParallelEnvironment::barrier(); // rank 0 wrote the file the others read next
        built_any = true;
        return reduction::read_model_file(source.file, source.expected_hash);
      }
  }

  InterfaceInfluence ModelLoader::load_ring_stress(const RingStressSource &source, const reduction::ReducedModel &ring,
                                                 const app::SceneParameters &scene)
  {
    try
      {
        InterfaceInfluence tables = read_ring_stress_file(source.file, source.expected_hash);
        if (tables.grid.nx != ring.interface_grid.grid.nx || tables.grid.ny != ring.interface_grid.grid.ny)
          throw std::runtime_error("ring stress tables '" + source.file + "' are on another grid than the ring's model");
        return tables;
      }
    catch (const std::runtime_error &error)
      {
        if (!build_if_missing)
          scene.reject("Stresses/Ring mesh", std::string(error.what()) + "; allow Model/Build if missing to build them");
      }
    const auto &d = source.divisions;
    if (first_rank())
      std::cerr << "bearing_housing: building the ring's full-FE stress tables " << source.file << " (mesh "
                << d.circumferential << "x" << d.radial_ring << "x" << d.axial << "x" << d.axial_land
                << "; about 2 minutes for the 6208 ring)\n";
    if (!fem::ParallelEnvironment::active())
      mpi = std::make_unique<fem::ParallelEnvironment>();
    const RingHousingRequest request = read_ring_housing_request(read_ring_housing_parameters(source.config, {}));
    InterfaceInfluence tables =
      ring_influence(request, source.config, ring, source.divisions, source.depths, source.points_per_side);
    tables.displacement.clear(); // the stresses are what a run needs
    tables.ball_displacement.clear();
    if (fem::ParallelEnvironment::rank() == 0)
      {
        if (const auto parent = std::filesystem::path(source.file).parent_path(); !parent.empty())
          std::filesystem::create_directories(parent);
        write_ring_stress_file(source.file, tables, source.expected_hash);
      }
    fem::ParallelEnvironment::barrier(); // the file is there before any rank's run reads it
    built_any = true;
    return tables;
  }

  void ModelLoader::finish()
  {
    mpi.reset();
  }
} // namespace fretsim::models
