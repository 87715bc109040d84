#pragma once
// Forces and displacements at points of a mesh boundary (docs/theory.md §3/§4):
// ball loads on the raceway groove, where a contact surface grid on a
// cylinder (SurfaceGridMap) cannot go. Each point is located once in the
// surface cell that holds it, and the cell's shape functions there form H:
//
//   interpolate():  u_p = H u        (consistent: Cartesian displacement at
//                                     each point)
//   nodal forces:   f = Hᵀ F         (conservative: the same operator
//                                     transposed, F a Cartesian force per point)
//
// so that Σ_p F_p · u_p = fᵀ u for every field, and f carries Σ_p F_p exactly
// (the shape functions sum to one). Points given on the exact geometry are
// moved onto the discrete surface (the mapped cells approximate a curved
// boundary by a sagitta of O(h^(p+1))): points() tells where the map acts.
//
// A ball's Hertz patch (RacewayBallLoad in elastic_model.h) is discretised by
// raceway_patch_forces() and applied through such a map; reduction/ can build
// "modal coordinates → raceway displacement at the balls" from interpolate().
#include <fretsim/fem/elastic_model.h>

#include <memory>
#include <vector>

namespace fretsim::fem
{
  class SurfacePointMap
  {
  public:
    /// Locates every point on the boundary `surface`: up to a tenth of a cell
    /// outside it, or a quarter of a cell inside (where the exact geometry
    /// lies from the chords of a coarse Q1 mesh). Throws std::invalid_argument naming the first point that is
    /// not on that boundary. Collective.
    SurfacePointMap(const ElasticModel &model, const std::vector<Point3> &points, BoundaryId surface);
    ~SurfacePointMap();
    SurfacePointMap(SurfacePointMap &&) noexcept;
    SurfacePointMap &operator=(SurfacePointMap &&) noexcept;

    std::size_t n_points() const;
    /// Where the map acts: the given points on the discrete surface [m]; the
    /// same on every rank.
    const std::vector<Point3> &points() const;

    /// u_p = H u, Cartesian [m], the same on every rank. Collective.
    std::vector<Vector3> interpolate(const DisplacementField &u) const;
    /// Σ over DoFs of f = Hᵀ F per Cartesian component [N], before any
    /// support drops a part: equal to Σ_p F_p (conservation). Collective.
    Vector3 nodal_force_sum(const std::vector<Vector3> &forces) const;

    struct Impl;
    const Impl &impl() const { return *pimpl; }
    explicit SurfacePointMap(std::unique_ptr<Impl> impl);

  private:
    std::unique_ptr<Impl> pimpl;
  };

  /// The contact point of a ball at θ = `angle` with contact angle α on the
  /// exact raceway: the groove arc (centre at radius groove_bottom_radius -
  /// groove_radius in the mid-plane) at α from its bottom, or the plain bore
  /// at z = 0 [m].
  Point3 raceway_contact_point(const RingGeometry &ring, double angle, double contact_angle);
  /// The contact normal there, pointing into the ring (the direction of the
  /// ball's force on it): (cos α e_r(θ) + sin α e_z).
  Vector3 raceway_contact_normal(double angle, double contact_angle);

  /// A ball load discretised on the exact raceway surface: quadrature points
  /// of the elliptical patch and the force at each [N].
  struct PatchForces
  {
    std::vector<Point3>  points;
    std::vector<Vector3> forces;
  };

  /// The quadrature: `quadrature_rings` annuli of equal width in the
  /// normalised radius ρ = √((ξ/a)² + (η/b)²), each with its exact share
  /// ∫√(1-ρ²)ρ dρ of the Hertz load placed at the annulus' load centroid, times
  /// `quadrature_sectors` equal angles; the shares sum to `force` exactly.
  /// Every point force acts along the contact normal: the patch is small
  /// against the radii (the local normals turn by at most b/r_g across it,
  /// and pressure along them would tilt the resultant off the ball's load
  /// line through the circumferential curvature); likewise the patch's area
  /// element is taken flat (dξ dη), as Hertz theory does. Throws
  /// std::invalid_argument if the patch leaves the groove, or for a contact
  /// angle on a plain bore.
  PatchForces raceway_patch_forces(const RacewayBallLoad &ball);
} // namespace fretsim::fem
