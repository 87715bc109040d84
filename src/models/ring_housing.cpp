#include <fretsim/models/ring_housing.h>

#include <fretsim/models/reduction.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace fretsim::models
{
  namespace
  {
    using fem::BoundaryId;

    /// Boundaries a Gmsh file must carry for the bodies it claims to hold: the
    /// loaded surface, the supported one and the side faces.
    std::vector<BoundaryId> required_boundaries(const std::string &bodies)
    {
      if (bodies == "ring")
        return {BoundaryId::raceway, BoundaryId::ring_outer, BoundaryId::side_faces};
      if (bodies == "housing")
        return {BoundaryId::housing_bore, BoundaryId::housing_outer, BoundaryId::side_faces};
      return {BoundaryId::raceway, BoundaryId::housing_outer, BoundaryId::side_faces};
    }

    RingHousingRequest read_request(const SceneParameters &p)
    {
      RingHousingRequest r;
      r.bodies      = p.get("Mesh/Bodies");
      r.refinements = static_cast<unsigned int>(p.get_integer("Mesh/Global refinements"));
      r.degree      = static_cast<unsigned int>(p.get_integer("Mesh/Element degree"));
      if (p.get("Mesh/Source") == "gmsh")
        {
          const std::string file = p.get("Mesh/Mesh file");
          if (file.empty())
            p.reject("Mesh/Mesh file", "is empty; a Gmsh .msh file is needed when Mesh/Source = gmsh");
          // Relative to the configuration, so that a scene and its mesh move together.
          const std::filesystem::path path(file);
          r.gmsh_file = (path.is_absolute() ? path : std::filesystem::path(p.file()).parent_path() / path)
                          .lexically_normal()
                          .string();
          return r;
        }

      r.ring.bore_radius          = p.get_double("Ring/Bore radius");
      r.ring.outer_radius         = p.get_double("Ring/Outer radius");
      r.ring.width                = p.get_double("Ring/Width");
      r.ring.groove_radius        = p.get_double("Ring/Groove radius");
      r.ring.groove_bottom_radius = p.get_double("Ring/Groove bottom radius");
      r.housing.bore_radius       = r.ring.outer_radius;
      r.housing.outer_radius      = p.get_double("Housing/Outer radius");
      r.housing.width             = r.ring.width;
      r.divisions.circumferential = static_cast<unsigned int>(p.get_integer("Divisions/Circumferential"));
      r.divisions.radial_ring     = static_cast<unsigned int>(p.get_integer("Divisions/Radial ring"));
      r.divisions.radial_housing  = static_cast<unsigned int>(p.get_integer("Divisions/Radial housing"));
      r.divisions.axial           = static_cast<unsigned int>(p.get_integer("Divisions/Axial"));
      r.divisions.axial_land      = static_cast<unsigned int>(p.get_integer("Divisions/Axial land"));
      r.divisions.radial_grading  = p.get_double("Divisions/Radial grading");
      r.divisions.sector_angle    = p.get_double("Divisions/Sector angle");

      auto metres = [](double value) {
        std::ostringstream s;
        s << std::setprecision(6) << value << " m";
        return s.str();
      };
      const auto &g = r.ring;
      if (r.bodies != "housing")
        {
          if (!(g.outer_radius > g.bore_radius))
            p.reject("Ring/Outer radius", "must exceed Ring/Bore radius (" + metres(g.bore_radius) + ")");
          if (g.has_groove())
            {
              if (!(g.groove_bottom_radius > g.bore_radius && g.groove_bottom_radius < g.outer_radius))
                p.reject("Ring/Groove bottom radius", "must lie between Ring/Bore radius (" + metres(g.bore_radius) +
                                                        ") and Ring/Outer radius (" + metres(g.outer_radius) + ")");
              if (!(g.groove_bottom_radius - g.groove_radius < g.bore_radius))
                p.reject("Ring/Groove radius", "is too small: the groove arc (centre at " +
                                                 metres(g.groove_bottom_radius - g.groove_radius) +
                                                 " from the axis) does not reach the bore; expected > " +
                                                 metres(g.groove_bottom_radius - g.bore_radius));
              if (!(g.groove_half_width() < 0.5 * g.width))
                p.reject("Ring/Groove radius", "makes the groove (" + metres(2 * g.groove_half_width()) +
                                                 " wide at the bore) wider than Ring/Width (" + metres(g.width) + ")");
            }
        }
      if (r.bodies != "ring" && !(r.housing.outer_radius > r.housing.bore_radius))
        p.reject("Housing/Outer radius", "must exceed Ring/Outer radius (" + metres(r.housing.bore_radius) +
                                           "), the housing bore");
      return r;
    }

    fem::Mesh build_mesh(const RingHousingRequest &r, const std::string &config_file)
    {
      if (!r.gmsh_file.empty())
        {
          try
            {
              return fem::Mesh::from_gmsh(r.gmsh_file, required_boundaries(r.bodies));
            }
          catch (const fem::MeshError &error)
            {
              throw InputError(config_file, "Mesh/Mesh file", error.what());
            }
        }
      try
        {
          if (r.bodies == "ring")
            return fem::Mesh::ring(r.ring, r.divisions);
          if (r.bodies == "housing")
            return fem::Mesh::housing(r.housing, r.divisions);
          return fem::Mesh::ring_in_housing(r.ring, r.housing, r.divisions);
        }
      catch (const std::invalid_argument &error)
        {
          // The cross-checks above catch the geometry; what is left are the divisions.
          throw InputError(config_file, "Divisions", error.what());
        }
    }


    std::vector<ParameterSpec> material_specs(const std::string &section, const std::string &body)
    {
      using Spec = ParameterSpec;
      // Bearing steel (AISI 52100); the housing defaults to steel as well.
      return {Spec::positive(section + "/Young's modulus", "2.08e11", "Young's modulus E of the " + body + " [Pa]."),
              Spec::real_range(section + "/Poisson ratio", "0.3", "Poisson's ratio nu of the " + body + " [-].", 0.0,
                               0.5, false, true),
              Spec::positive(section + "/Density", "7850", "Density rho of the " + body + " [kg/m^3].")};
    }

    fem::Material read_material(const SceneParameters &p, const std::string &section)
    {
      return {p.get_double(section + "/Young's modulus"), p.get_double(section + "/Poisson ratio"),
              p.get_double(section + "/Density")};
    }

    std::vector<ParameterSpec> mesh_specs()
    {
    using Spec = ParameterSpec;
    std::vector<Spec> specs;
    // Defaults: the outer ring of a 6208 bearing in a steel housing, as in
    // meshes/bearing_6208_outer_ring.geo (the paper's §5 scene).
    specs.push_back(Spec::selection("Mesh/Source", "parametric",
                                    "parametric: built from the Ring, Housing and Divisions sections with exact "
                                    "cylinders and groove arc; gmsh: read from Mesh file [-].",
                                    "parametric|gmsh"));
    Spec file;
    file.path          = "Mesh/Mesh file";
    file.kind          = Spec::Kind::text;
    file.default_value = "";
    file.doc = "Gmsh .msh file (ASCII, hexahedra), relative to this configuration file; physical surfaces carry "
               "the boundary ids 1..8 (raceway, ring_lands, ring_outer, housing_bore, housing_outer, side_faces, "
               "sector_start, sector_end) and physical volumes 1 (ring) or 2 (housing) [-].";
    specs.push_back(file);
    specs.push_back(Spec::selection("Mesh/Bodies", "ring",
                                    "What is meshed: the outer ring alone, the housing alone, or both bonded at "
                                    "the ring outer surface [-].",
                                    "ring|housing|ring_in_housing"));
    specs.push_back(Spec::integer_range("Mesh/Global refinements", "0",
                                        "Times every cell is split into 8, new points on the exact geometry [-].", 0,
                                        4));
    specs.push_back(Spec::integer_range("Mesh/Element degree", "2",
                                        "Polynomial degree p of the FE_Q displacement elements (and of the "
                                        "mapping) [-].",
                                        1, 2));
    specs.push_back(Spec::positive("Ring/Bore radius", "0.0341",
                                   "Bore radius of a plain ring, or the land (shoulder) radius beside the "
                                   "raceway groove [m]."));
    specs.push_back(Spec::positive("Ring/Outer radius", "0.040", "Outer radius of the ring, D/2 [m]."));
    specs.push_back(Spec::positive("Ring/Width", "0.018", "Axial width B of ring and housing [m]."));
    specs.push_back(Spec::non_negative("Ring/Groove radius", "0.006731",
                                       "Radius of the raceway groove's circular arc in the axial cross-section, "
                                       "f_o D_w; 0 for a plain cylindrical bore [m]."));
    specs.push_back(Spec::positive("Ring/Groove bottom radius", "0.03635",
                                   "Distance of the groove bottom from the bearing axis, half the outer raceway "
                                   "diameter (used when Groove radius > 0) [m]."));
    specs.push_back(Spec::positive("Housing/Outer radius", "0.060",
                                   "Outer radius of the housing ring; its bore is the ring's outer radius [m]."));
    specs.push_back(Spec::integer_range("Divisions/Circumferential", "96",
                                        "Cells around the meshed sector [-].", 3, 4096));
    specs.push_back(Spec::integer_range("Divisions/Radial ring", "2", "Cells through the ring wall [-].", 1, 256));
    specs.push_back(
      Spec::integer_range("Divisions/Radial housing", "2", "Cells through the housing wall [-].", 1, 256));
    specs.push_back(Spec::integer_range("Divisions/Axial", "6",
                                        "Cells across the groove, or across the whole width of a plain ring "
                                        "[-].",
                                        1, 1024));
    specs.push_back(Spec::integer_range("Divisions/Axial land", "2",
                                        "Cells across each land beside the groove [-].", 1, 1024));
    specs.push_back(Spec::real_range("Divisions/Radial grading", "1",
                                     "Radial cells in geometric progression, the thickest this many times the "
                                     "thinnest, which lie at the ring's outer surface and the housing's bore (the "
                                     "interface); 1 is uniform [-].",
                                     1.0, 1000.0));
    specs.push_back(Spec::real_range("Divisions/Sector angle", "6.283185307179586",
                                     "Meshed sector 0 <= theta <= angle; 2 pi is the full ring, less gives the cut "
                                     "faces sector_start and sector_end [rad].",
                                     0.0, 6.283185307179586 * (1 + 1e-12), true, false));
    return specs;
      }
  } // namespace

  std::string boundary_names()
  {
    std::string names;
    for (unsigned int id = 1; id <= fem::max_boundary_id; ++id)
      names += (names.empty() ? "" : "|") + fem::to_string(static_cast<fem::BoundaryId>(id));
    return names;
  }

  std::optional<fem::BoundaryId> boundary_named(const std::string &name)
  {
    for (unsigned int id = 1; id <= fem::max_boundary_id; ++id)
      if (fem::to_string(static_cast<fem::BoundaryId>(id)) == name)
        return static_cast<fem::BoundaryId>(id);
    return std::nullopt;
  }

  std::vector<ParameterSpec> ring_housing_parameter_specs()
  {
    auto specs = mesh_specs();
    for (auto part : {material_specs("Material", "outer ring"), material_specs("Housing material", "housing"),
                      fe_run_parameter_specs(), reduce_parameter_specs()})
      specs.insert(specs.end(), part.begin(), part.end());
    return specs;
  }

  SceneParameters read_ring_housing_parameters(const std::string &config_file,
                                               const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    SceneParameters::scene_of_file(config_file, {ring_housing_scene});
    SceneParameters parameters(ring_housing_scene, ring_housing_parameter_specs());
    parameters.parse_file(config_file);
    for (const auto &[path, value] : overrides)
      parameters.set(path, value);
    return parameters;
  }

  RingHousingRequest read_ring_housing_request(const SceneParameters &parameters)
  {
    RingHousingRequest request = read_request(parameters);
    request.materials[fem::MaterialId::ring]    = read_material(parameters, "Material");
    request.materials[fem::MaterialId::housing] = read_material(parameters, "Housing material");
    return request;
  }

  fem::Mesh build_ring_housing_mesh(const RingHousingRequest &request, const std::string &config_file)
  {
    fem::Mesh mesh = build_mesh(request, config_file);
    mesh.refine_globally(request.refinements);
    return mesh;
  }
} // namespace fretsim::models
