#pragma once
// The ring/housing FE model that a "ring_housing" configuration describes
// (docs/theory.md §3): its parameter table (mesh, material, and the sections of
// the commands that work on it: `fe`, `reduce`), and the mesh and materials
// read from it. Shared by `fretsim mesh`, `fretsim fe`, `fretsim reduce` and
// the scenes that build their reduced models.
#include <fretsim/support/parameters.h>

#include <fretsim/fem/elastic_model.h>
#include <fretsim/fem/mesh.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::models
{
  using app::InputError;
  using app::ParameterSpec;
  using app::SceneParameters;

  /// The scene name of ring/housing FE configurations.
  inline const std::string ring_housing_scene = "ring_housing";

  /// Every parameter of a ring_housing configuration: Mesh, Ring, Housing,
  /// Divisions, Material, Housing material, and the sections of `fe` and `reduce`.
  std::vector<ParameterSpec> ring_housing_parameter_specs();
  /// The `fe` command's section of that table (FE run/...).
  inline const std::string fe_run_section = "FE run/";
  std::vector<ParameterSpec> fe_run_parameter_specs();

  /// The names of the FE boundary ids, as a selection pattern (a|b|c).
  std::string boundary_names();
  /// The boundary id of a name; none for an unknown name.
  std::optional<fem::BoundaryId> boundary_named(const std::string &name);

  /// Reads a ring_housing configuration and applies --set overrides; throws
  /// InputError (file, parameter, expectation) before anything is built.
  SceneParameters read_ring_housing_parameters(const std::string &config_file,
                                               const std::vector<std::pair<std::string, std::string>> &overrides);

  /// Command-line options of the commands that work on a ring_housing configuration.
  struct RingHousingCommandOptions
  {
    std::string config_file;
    std::string output; ///< output directory or file; empty: the command's default under results/
    std::vector<std::pair<std::string, std::string>> overrides; ///< --set Section/Name=value
    bool        progress = true;  ///< progress display on the terminal
    bool        plots    = true;  ///< PNG figures where the command makes them
  };

  /// What the configuration asks for, read and cross-checked.
  struct RingHousingRequest
  {
    std::string          bodies;    ///< ring | housing | ring_in_housing
    std::string          gmsh_file; ///< empty: parametric
    fem::RingGeometry    ring;
    fem::HousingGeometry housing;
    fem::MeshDivisions   divisions;
    unsigned int         refinements = 0;
    unsigned int         degree      = 2;
    std::map<fem::MaterialId, fem::Material> materials; ///< ring and housing
  };

  /// Cross-checks the geometry (InputError naming the parameter).
  RingHousingRequest read_ring_housing_request(const SceneParameters &parameters);

  /// Builds or reads the mesh (needs MPI/PETSc running: fem::ParallelEnvironment).
  /// A Gmsh file that cannot be used is an InputError naming Mesh/Mesh file.
  /// Global refinements are applied.
  fem::Mesh build_ring_housing_mesh(const RingHousingRequest &request, const std::string &config_file);
} // namespace fretsim::models
