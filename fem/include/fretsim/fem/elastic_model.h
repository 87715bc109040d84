#pragma once
// Linear elasticity of ring and housing (docs/theory.md §3): FE_Q of degree 1 or 2
// per displacement component on a distributed mesh, with a mapping of the same
// degree so curved surfaces converge at the element's rate; stiffness K and
// mass M as PETSc matrices; static solutions and eigenmodes. SI units.
//
// Call order: construct (DoFs, constraints and K are set up), then any number
// of solve_static() / solve_modes() calls. All calls are collective over the
// mesh's ranks. No deal.II, PETSc or MPI type appears here; reduction/ gets
// the PETSc matrices through the forward-declared handles below (as MFEM does
// for SLEPc), and only its sources include PETSc.
#include <fretsim/fem/mesh.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

struct _p_Mat; // PETSc's Mat is a pointer to this
struct _p_Vec; // PETSc's Vec

namespace fretsim::fem
{
  /// Isotropic linear elastic material.
  struct Material
  {
    double youngs_modulus = 0.0; ///< E [Pa]
    double poisson_ratio  = 0.0; ///< ν [-]
    double density        = 0.0; ///< ρ [kg/m³]
  };

  /// Zero displacement of the chosen Cartesian components on a boundary (a
  /// clamp, or a symmetry plane normal to x, y or z).
  struct Support
  {
    BoundaryId boundary;
    bool       fix_x = true;
    bool       fix_y = true;
    bool       fix_z = true;
  };

  /// Uniform pressure on a boundary [Pa]; positive pushes into the body
  /// (traction t = -p n).
  struct PressureLoad
  {
    BoundaryId boundary;
    double     pressure = 0.0;
  };

  /// In-plane isotropic expansion eigenstrain ε* = e (e_x⊗e_x + e_y⊗e_y) of
  /// one body. A ring bonded in a housing with e = δ/R is, in linear theory,
  /// exactly the ring with radial interference δ at the interface radius R
  /// pressed into the housing: the free ring would expand by u = e·(x, y, 0)
  /// without stress, so the bond imposes the displacement jump δ e_r at R.
  /// Displacements reported for that body include the free expansion.
  struct InPlaneExpansion
  {
    MaterialId body;
    double     strain = 0.0; ///< e [-]
  };

  class SurfaceGridMap;
  struct GridTractions;

  /// Tractions on a contact surface grid, applied as f = Hᵀ (A t) through the
  /// grid's map (surface_grid_map.h); the map and tractions must outlive the solve.
  struct GridTractionLoad
  {
    const SurfaceGridMap *map       = nullptr;
    const GridTractions  *tractions = nullptr;
  };

  class SurfacePointMap;

  /// Forces [N] at the points of a SurfacePointMap (one per point, Cartesian),
  /// applied as f = Hᵀ F (surface_point_map.h); the map must outlive the solve.
  struct PointForceLoad
  {
    const SurfacePointMap             *map = nullptr;
    std::vector<std::array<double, 3>> forces;
  };

  /// A ball pressing on the raceway (surface_point_map.h for the discretisation):
  /// Hertz pressure p = p₀ √(1 - (ξ/a)² - (η/b)²), p₀ = 3Q/(2πab), on an
  /// elliptical patch centred at the contact point, ξ along the circumference
  /// and η along the groove arc (axially on a plain bore), acting along the
  /// contact normal (from the groove arc centre through the contact point):
  /// the resultant on the ring is Q along that line.
  struct RacewayBallLoad
  {
    RingGeometry ring;                            ///< the groove (or plain bore) the ball presses on
    double       angle                     = 0.0; ///< θ of the ball centre [rad]
    double       contact_angle             = 0.0; ///< α, from the mid-plane towards +z (0 on a plain bore) [rad]
    double       force                     = 0.0; ///< resultant Q [N]
    double       semi_axis_circumferential = 0.0; ///< a [m]
    double       semi_axis_transverse      = 0.0; ///< b, along the groove arc [m]
    unsigned int quadrature_rings          = 4;   ///< annuli of the patch quadrature
    unsigned int quadrature_sectors        = 16;  ///< points per annulus (even: a symmetric rule)
  };

  struct StaticLoad
  {
    std::vector<PressureLoad>     pressures;
    std::vector<InPlaneExpansion> expansions;
    std::vector<GridTractionLoad> grid_tractions;
    std::vector<PointForceLoad>   point_forces;
    std::vector<RacewayBallLoad>  ball_loads;
  };

  enum class LinearSolver
  {
    direct, ///< MUMPS Cholesky: exact, for small and medium models
    cg_amg, ///< PETSc CG preconditioned with hypre BoomerAMG (scalar: blind to rigid rotations)
    /// PETSc CG with smoothed-aggregation GAMG given the six rigid-body
    /// modes as near-null space: the coarse spaces then hold the rotations
    /// that scalar AMG must relearn from the smoother (the fast iterative choice).
    cg_gamg,
  };

  struct SolverSettings
  {
    LinearSolver type               = LinearSolver::direct;
    double       relative_tolerance = 1e-10; ///< CG: ‖B r‖ ≤ tol ‖B f‖ (B = the AMG)
    unsigned int max_iterations     = 5000;
  };

  /// Wall-clock seconds of the stages so far, and the last iteration count.
  struct Timings
  {
    double       setup_dofs         = 0.0;
    double       assemble_stiffness = 0.0;
    double       assemble_mass      = 0.0;
    double       assemble_load      = 0.0;
    double       solve              = 0.0;
    unsigned int iterations         = 0;
  };

  /// Area-weighted means over a surface, in cylindrical components about the
  /// z axis (r, θ, z): displacement [m] and stress [Pa].
  struct CylindricalAverage
  {
    double area = 0.0; ///< [m²]
    double u_r = 0.0, u_theta = 0.0, u_z = 0.0;
    double s_rr = 0.0, s_tt = 0.0, s_zz = 0.0, s_rt = 0.0, s_rz = 0.0, s_tz = 0.0;
  };

  using Point3  = std::array<double, 3>;
  using Vector3 = std::array<double, 3>;

  /// A displacement solution (static state or mode shape) on the model's mesh.
  /// Keeps the model's discretisation alive.
  class DisplacementField
  {
  public:
    ~DisplacementField();
    DisplacementField(DisplacementField &&) noexcept;
    DisplacementField &operator=(DisplacementField &&) noexcept;

    /// ½ uᵀ K u [J] (the field's elastic energy when there is no eigenstrain).
    double strain_energy() const;
    /// Mean displacement and stress over a boundary, stresses taken from the
    /// cells at the faces' quadrature points.
    CylindricalAverage average_on_boundary(BoundaryId boundary) const;
    /// The same over the interface between two bodies, stresses evaluated in
    /// the cells of `evaluated_in` (the traction is continuous across, the
    /// other stress components need not be).
    CylindricalAverage average_on_interface(MaterialId evaluated_in, MaterialId neighbour) const;
    /// ‖u - u_exact‖ in L2 over the body [m·m^(3/2)], with a Gauss rule of
    /// degree+2 points per direction.
    double l2_error(const std::function<Vector3(const Point3 &)> &exact) const;
    /// Share of uᵀ M u in the x, y and z components (needs the mass matrix;
    /// tells in-plane modes (z share ≈ 0) from out-of-plane ones).
    Vector3 mass_fractions() const;
    /// ParaView output: `<directory>/<name>.pvtu` with its pieces (displacement).
    void write_vtu(const std::string &directory, const std::string &name) const;

    struct Impl;
    const Impl &impl() const { return *pimpl; }
    explicit DisplacementField(std::unique_ptr<Impl> impl);

  private:
    std::unique_ptr<Impl> pimpl;
  };

  struct ModalSettings
  {
    unsigned int n_modes = 10; ///< elastic modes wanted (rigid-body modes come on top)
    /// Shift-and-invert target σ = -(2π f_shift)²: negative, so that K - σM is
    /// positive definite even for a free body, and small, so that the modes
    /// nearest to it are the lowest ones [Hz].
    double shift_hz = 10.0;
    /// Modes below this frequency are rigid-body modes (round-off makes their
    /// eigenvalues tiny instead of zero) [Hz].
    double rigid_body_cutoff_hz = 1.0;
    double tolerance            = 1e-10; ///< relative eigen-residual
  };

  struct ModalSolution
  {
    std::vector<double>            frequencies_hz;       ///< elastic modes, ascending
    std::vector<DisplacementField> shapes;               ///< mass-normalised: φᵀ M φ = 1
    unsigned int                   n_rigid_body_modes = 0; ///< found below the cutoff
    double                         seconds            = 0.0;
  };

  class ElasticModel
  {
  public:
    /// `materials` must cover every material id of the mesh; `degree` is 1 or 2.
    /// Supports act as zero-displacement constraints in K, M and every solve.
    ElasticModel(std::shared_ptr<const Mesh> mesh, const std::map<MaterialId, Material> &materials,
                 unsigned int degree, const std::vector<Support> &supports = {});
    ~ElasticModel();
    ElasticModel(ElasticModel &&) noexcept;
    ElasticModel &operator=(ElasticModel &&) noexcept;

    unsigned long  n_dofs() const;
    unsigned int   degree() const;
    const Timings &timings() const;

    /// Assembles the load, solves K u = f and applies the constraints.
    DisplacementField solve_static(const StaticLoad &load, const SolverSettings &settings = {});

    /// Lowest eigenmodes of K φ = ω² M φ by SLEPc Krylov–Schur with
    /// shift-and-invert (MUMPS inside). Constrained DoFs have a zero row and
    /// column in M and a unit-scale diagonal in K, i.e. infinite eigenvalues,
    /// so they never show up among the lowest modes (the problem deal.II's step-36 describes).
    ModalSolution solve_modes(const ModalSettings &settings = {});

    /// The assembled PETSc matrices (owned by the model), for reduction/.
    /// The mass matrix is assembled on first use.
    _p_Mat *petsc_stiffness();
    _p_Mat *petsc_mass();
    /// Global indices (PETSc numbering) of the DoFs owned by this rank that
    /// lie on any of `boundaries`, ascending. Collective.
    std::vector<long> owned_boundary_dofs(const std::vector<BoundaryId> &boundaries) const;
    /// The load vector f of `load` (through the constraints) into `f`, a
    /// vector laid out like the matrices' columns. Collective.
    void assemble_load_vector(const StaticLoad &load, _p_Vec *f) const;
    /// A displacement field from a vector laid out like the matrices' columns
    /// (copied, constraints applied): e.g. a reduced basis vector. Collective.
    DisplacementField field_from_vector(_p_Vec *u) const;

    struct Impl;
    Impl       &impl() { return *pimpl; }
    const Impl &impl() const { return *pimpl; }
    /// Shared ownership of the discretisation, for objects that outlive the model.
    std::shared_ptr<const Impl> shared_impl() const { return pimpl; }

  private:
    std::shared_ptr<Impl> pimpl;
  };
} // namespace fretsim::fem
