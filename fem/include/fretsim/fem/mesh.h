#pragma once
// Meshes of the bearing outer ring and its housing (docs/theory.md §3): 3-D
// hexahedra, built parametrically or read from Gmsh, distributed over the MPI
// ranks. deal.II types stay in the sources (Mesh::Impl). SI units: lengths in m.
//
// Geometry convention: the bearing axis is the z axis, z = 0 is the ring's
// mid-plane; θ is measured from the x axis towards the y axis.
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fretsim::fem
{
  /// Boundary ids of every ring/housing mesh. They are also the Gmsh physical
  /// surface tags expected in meshes/*.msh. Id 0 is never used: a boundary face
  /// without a tag is an error.
  enum class BoundaryId : unsigned int
  {
    raceway       = 1, ///< raceway groove; the whole bore of a ring without groove
    ring_lands    = 2, ///< cylindrical bore beside the groove (the shoulders)
    ring_outer    = 3, ///< ring outer surface (a boundary when the housing is not meshed)
    housing_bore  = 4, ///< housing bore (a boundary when the ring is not meshed)
    housing_outer = 5, ///< housing outer surface
    side_faces    = 6, ///< the axial end faces z = ±width/2 of ring and housing
    sector_start  = 7, ///< cut face θ = 0 (the plane y = 0) of a sector model
    sector_end    = 8, ///< cut face θ = sector angle of a sector model
  };
  constexpr unsigned int max_boundary_id = 8;

  /// Material ids: which body a cell belongs to (Gmsh physical volume tags).
  enum class MaterialId : unsigned int
  {
    ring    = 1,
    housing = 2,
  };

  /// "raceway", "ring_lands", ... (for messages and output).
  std::string to_string(BoundaryId id);
  std::string to_string(MaterialId id);

  /// Outer ring of a ball bearing; axially symmetric about z = 0.
  struct RingGeometry
  {
    double bore_radius  = 0.0; ///< bore of a plain ring, or the land (shoulder) radius [m]
    double outer_radius = 0.0; ///< [m]
    double width        = 0.0; ///< axial width B [m]
    /// Radius of the raceway groove's circular arc in the axial cross-section;
    /// 0 for a plain cylindrical bore [m].
    double groove_radius = 0.0;
    /// Distance of the groove bottom from the axis (half the outer raceway
    /// diameter) [m]; used when groove_radius > 0.
    double groove_bottom_radius = 0.0;

    bool has_groove() const { return groove_radius > 0.0; }
    /// Axial half-width of the groove, where the arc meets the lands [m].
    double groove_half_width() const;
  };

  /// Ring-shaped housing around the ring: bore = ring outer radius, same width.
  struct HousingGeometry
  {
    double bore_radius  = 0.0; ///< [m]
    double outer_radius = 0.0; ///< [m]
    double width        = 0.0; ///< [m]
  };

  /// Cell counts of a parametric mesh (before any global refinement).
  struct MeshDivisions
  {
    unsigned int circumferential = 32; ///< cells around the meshed sector
    unsigned int radial_ring     = 2;  ///< cells through the ring wall
    unsigned int radial_housing  = 2;  ///< cells through the housing wall
    unsigned int axial           = 4;  ///< cells across the width, or across the groove
    unsigned int axial_land      = 2;  ///< cells across each land of a grooved ring
    /// Radial cell sizes in geometric progression, the thickest this many times
    /// the thinnest; the thinnest at the ring's outer surface and at the
    /// housing's bore, where the contact's stresses vary fastest. 1: uniform.
    double radial_grading = 1.0;
    /// Meshed sector θ ∈ [0, sector_angle]; 2π (the default) is the full ring.
    /// A sector gets the cut faces sector_start / sector_end.
    double sector_angle = 6.283185307179586;
  };

  /// Which MPI ranks share a mesh (and everything built on it).
  enum class Ranks
  {
    all,      ///< distributed over MPI_COMM_WORLD
    this_one, ///< this rank alone (MPI_COMM_SELF): e.g. a serial reference inside an MPI run
  };

  /// A mesh file that cannot be used (unreadable, inverted cells, untagged or
  /// missing boundaries). what() names the file and the problem.
  class MeshError : public std::runtime_error
  {
  public:
    MeshError(const std::string &file, const std::string &problem);
  };

  /// What a mesh holds, summed over all ranks.
  struct MeshSummary
  {
    unsigned long n_cells = 0;                          ///< active cells
    unsigned int  n_ranks = 1;
    double        volume  = 0.0;                        ///< [m³]
    std::map<unsigned int, unsigned long> boundary_faces; ///< id → number of faces
    std::map<unsigned int, double>        boundary_area;  ///< id → area [m²]
    std::map<unsigned int, unsigned long> material_cells; ///< material id → cells
    std::map<unsigned int, double>        material_volume;///< material id → volume [m³]
    std::string description;                           ///< how the mesh was made
  };

  /// A distributed hexahedral mesh with exact curved geometry where it is
  /// known: parametric meshes carry a chart of the ring cross-section (so
  /// refinement and a higher-order mapping follow the cylinders and the groove
  /// arc); Gmsh meshes get cylinders about the z axis.
  class Mesh
  {
  public:
    /// The outer ring alone (plain bore or raceway groove).
    static Mesh ring(const RingGeometry &ring, const MeshDivisions &divisions, Ranks ranks = Ranks::all);
    /// The housing alone.
    static Mesh housing(const HousingGeometry &housing, const MeshDivisions &divisions,
                        Ranks ranks = Ranks::all);
    /// Ring and housing in one conforming mesh, bonded at the ring outer
    /// surface = housing bore (which then are interior faces).
    static Mesh ring_in_housing(const RingGeometry &ring, const HousingGeometry &housing,
                                const MeshDivisions &divisions, Ranks ranks = Ranks::all);
    /// A Gmsh .msh file (format 2 or 4): physical surfaces carry BoundaryId
    /// values, physical volumes MaterialId values. Throws MeshError if the file
    /// cannot be read, has inverted cells, boundary faces without a known id,
    /// or lacks one of `required`.
    static Mesh from_gmsh(const std::string &path, const std::vector<BoundaryId> &required,
                          Ranks ranks = Ranks::all);

    ~Mesh();
    Mesh(Mesh &&) noexcept;
    Mesh &operator=(Mesh &&) noexcept;

    /// Splits every cell into 8, placing new points on the exact geometry.
    void refine_globally(unsigned int times = 1);

    /// Collective over the mesh's ranks. Volumes and areas are integrated
    /// with a mapping of `mapping_degree` (1: the straight-edged cells as their
    /// vertices give them; 3: the exact curved geometry to ~1e-8).
    MeshSummary summary(unsigned int mapping_degree = 3) const;

    /// Number of DoFs of a displacement field with FE_Q of `degree` per
    /// component on this mesh (no matrices are built). Collective.
    unsigned long n_dofs(unsigned int degree) const;

    /// Writes `<directory>/<name>.vtu` (cells: material id, owner rank) and
    /// `<directory>/<name>_boundary.vtu` (boundary faces: boundary id) for
    /// ParaView. Collective; rank 0 writes.
    void write_vtu(const std::string &directory, const std::string &name) const;

    /// Number of MPI ranks sharing the mesh, and this rank's index.
    unsigned int n_ranks() const;
    unsigned int rank() const;

    /// The deal.II side, for the other fem sources only (fem/src/mesh_impl.h).
    struct Impl;
    Impl       &impl() { return *pimpl; }
    const Impl &impl() const { return *pimpl; }

  private:
    explicit Mesh(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> pimpl;
  };
} // namespace fretsim::fem
