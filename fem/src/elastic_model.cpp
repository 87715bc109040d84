// ElasticModel: DoFs, constraints, and the assembly of K and M.
#include "model_impl.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <petscmat.h>
#include <petscvec.h>

#include <array>
#include <set>

namespace fretsim::fem
{
  using Clock = std::chrono::steady_clock;

  dealii::SymmetricTensor<2, 3> stress(const Lame &m, const dealii::SymmetricTensor<2, 3> &strain,
                                       const double in_plane_eigenstrain)
  {
    dealii::SymmetricTensor<2, 3> elastic = strain;
    elastic[0][0] -= in_plane_eigenstrain;
    elastic[1][1] -= in_plane_eigenstrain;
    return m.lambda * dealii::trace(elastic) * dealii::unit_symmetric_tensor<3>() + 2.0 * m.mu * elastic;
  }

  ElasticModel::Impl::Impl(std::shared_ptr<const Mesh> mesh_in, const std::map<MaterialId, Material> &materials,
                           const unsigned int degree_in, const std::vector<Support> &supports)
    : mesh(std::move(mesh_in))
    , degree(degree_in)
    , fe(dealii::FE_Q<3>(degree_in), 3)
    // A mapping of the element's degree on the exact manifold: with a lower
    // one the geometry error would cap the convergence rate on curved faces.
    , mapping(degree_in)
    , dof_handler(mesh->impl().triangulation)
  {
    if (degree != 1 && degree != 2)
      throw std::invalid_argument("fem::ElasticModel: element degree must be 1 or 2, not " + std::to_string(degree));
    for (const auto &[id, m] : materials)
      {
        if (!(m.youngs_modulus > 0.0 && m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5 && m.density > 0.0))
          throw std::invalid_argument("fem::ElasticModel: material " + to_string(id) +
                                      " needs E > 0, -1 < ν < 0.5 and ρ > 0");
        const double E = m.youngs_modulus, nu = m.poisson_ratio;
        lame[static_cast<unsigned int>(id)] = {E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu)), m.density};
      }
    for (const auto &[id, cells] : mesh->summary(1).material_cells)
      if (lame.count(id) == 0 && cells > 0)
        throw std::invalid_argument("fem::ElasticModel: no material given for material id " + std::to_string(id));
    setup_dofs(supports);
    assemble_stiffness();
  }

  const Lame &ElasticModel::Impl::material(const unsigned int material_id) const { return lame.at(material_id); }

  namespace
  {
    /// True when every node's three displacement components carry
    /// consecutive global indices 3k, 3k+1, 3k+2 (deal.II numbers the DoFs of
    /// an FESystem object by object, all components together).
    bool dofs_come_in_node_triples(const ElasticModel::Impl &model)
    {
      const unsigned int                           n = model.fe.n_dofs_per_cell();
      std::vector<dealii::types::global_dof_index> dof_indices(n);
      bool triples = model.owned_dofs.size() > 0 && model.owned_dofs.n_elements() % 3 == 0;
      for (const auto &cell : model.dof_handler.active_cell_iterators())
        {
          if (!triples)
            break;
          if (!cell->is_locally_owned())
            continue;
          cell->get_dof_indices(dof_indices);
          for (unsigned int i = 0; i < n && triples; ++i)
            {
              const unsigned int c     = model.fe.system_to_component_index(i).first;
              const auto         first = dof_indices[i] - c;
              // Component c of a support point sits c places after its x.
              triples = first % 3 == 0 && i >= c && dof_indices[i - c] == first &&
                        model.fe.system_to_component_index(i - c).first == 0;
            }
        }
      return dealii::Utilities::MPI::min(triples ? 1 : 0, model.communicator()) == 1;
    }

    /// A PETSc matrix with the sparsity of the model's DoF couplings through
    /// its constraints (the pattern of K and of M).
    void reinit_with_dof_couplings(const ElasticModel::Impl &model, dealii::PETScWrappers::MPI::SparseMatrix &matrix)
    {
      dealii::DynamicSparsityPattern dsp(model.relevant_dofs);
      dealii::DoFTools::make_sparsity_pattern(model.dof_handler, dsp, model.constraints, false);
      dealii::SparsityTools::distribute_sparsity_pattern(dsp, model.owned_dofs, model.communicator(),
                                                         model.relevant_dofs);
      matrix.reinit(model.owned_dofs, model.owned_dofs, dsp, model.communicator());
      // Block size 3 tells PETSc's GAMG the DoFs per node: with 1 (deal.II's
      // default) it aggregates the scalar graph, 9× the edges of the nodal
      // one, with six near-null vectors per scalar "node" — a far costlier
      // setup for no better hierarchy.
      if (dofs_come_in_node_triples(model))
        if (MatSetBlockSize(static_cast<Mat>(matrix), 3) != 0)
          throw std::runtime_error("fem::ElasticModel: PETSc failed in MatSetBlockSize");
    }

    /// Shape data of the scalar base element FE_Q(p) at the quadrature points
    /// of one cell, and where its functions sit in the vector element: the
    /// vector shape function of base function a and component c is
    /// N_a e_c, so every cell matrix is made of 3×3 blocks per pair (a, b)
    /// computed from the scalar N_a alone (a third of the shape functions
    /// FEValues would evaluate on the FESystem, a ninth of the products).
    struct ScalarBase
    {
      explicit ScalarBase(const dealii::FESystem<3> &fe)
        : n(fe.base_element(0).n_dofs_per_cell())
        , system_index(n)
      {
        for (unsigned int a = 0; a < n; ++a)
          for (unsigned int c = 0; c < 3; ++c)
            system_index[a][c] = fe.component_to_system_index(c, a);
      }
      unsigned int                            n;
      std::vector<std::array<unsigned int, 3>> system_index;
    };
  } // namespace

  void ElasticModel::Impl::setup_dofs(const std::vector<Support> &supports)
  {
    const auto start = Clock::now();
    dof_handler.distribute_dofs(fe);
    owned_dofs = dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_dofs);

    constraints.clear();
    constraints.reinit(relevant_dofs);
    dealii::DoFTools::make_hanging_node_constraints(dof_handler, constraints);
    for (const Support &support : supports)
      dealii::VectorTools::interpolate_boundary_values(
        mapping, dof_handler, static_cast<unsigned int>(support.boundary), dealii::Functions::ZeroFunction<3>(3),
        constraints, dealii::ComponentMask({support.fix_x, support.fix_y, support.fix_z}));
    constraints.close();

    // M gets its pattern when it is first assembled: a static solve never
    // needs it, and at 1M DoFs it would hold gigabytes.
    reinit_with_dof_couplings(*this, stiffness);
    timings.setup_dofs = seconds_since(start);
  }

  void ElasticModel::Impl::assemble_stiffness()
  {
    const auto              start = Clock::now();
    const dealii::QGauss<3> quadrature(degree + 1);
    const ScalarBase        base(fe);
    // Gradients only: the mapping then computes Jacobians but no
    // quadrature points, normals or Hessians.
    dealii::FEValues<3>        fe_values(mapping, fe.base_element(0), quadrature,
                                         dealii::update_gradients | dealii::update_JxW_values);
    const unsigned int         n_q = quadrature.size(), nb = base.n;
    dealii::FullMatrix<double> cell_matrix(fe.n_dofs_per_cell(), fe.n_dofs_per_cell());
    std::vector<dealii::types::global_dof_index> dof_indices(fe.n_dofs_per_cell());
    // ∇N_a at every point, [a][q][component], and the same times JxW.
    std::vector<double> grad(nb * n_q * 3), weighted_grad(nb * n_q * 3);

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        const Lame &m = material(cell->material_id());
        for (unsigned int a = 0; a < nb; ++a)
          for (unsigned int q = 0; q < n_q; ++q)
            {
              const dealii::Tensor<1, 3> &g   = fe_values.shape_grad(a, q);
              const double                jxw = fe_values.JxW(q);
              for (unsigned int c = 0; c < 3; ++c)
                {
                  grad[(a * n_q + q) * 3 + c]          = g[c];
                  weighted_grad[(a * n_q + q) * 3 + c] = g[c] * jxw;
                }
            }
        // With S_ab = ∫ ∇N_a ⊗ ∇N_b, the block of φ = N_a e_c, N_b e_d is
        //   a(N_b e_d, N_a e_c) = λ S_ab[c][d] + μ S_ab[d][c] + μ δ_cd tr S_ab.
        for (unsigned int a = 0; a < nb; ++a)
          for (unsigned int b = 0; b <= a; ++b)
            {
              double       S[3][3] = {};
              const double *ga = &weighted_grad[a * n_q * 3], *gb = &grad[b * n_q * 3];
              for (unsigned int q = 0; q < n_q; ++q, ga += 3, gb += 3)
                for (unsigned int c = 0; c < 3; ++c)
                  for (unsigned int d = 0; d < 3; ++d)
                    S[c][d] += ga[c] * gb[d];
              const double trace = S[0][0] + S[1][1] + S[2][2];
              for (unsigned int c = 0; c < 3; ++c)
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    const double value = m.lambda * S[c][d] + m.mu * S[d][c] + (c == d ? m.mu * trace : 0.0);
                    const unsigned int i = base.system_index[a][c], j = base.system_index[b][d];
                    cell_matrix(i, j) = value;
                    cell_matrix(j, i) = value;
                  }
            }
        cell->get_dof_indices(dof_indices);
        constraints.distribute_local_to_global(cell_matrix, dof_indices, stiffness);
      }
    stiffness.compress(dealii::VectorOperation::add);
    timings.assemble_stiffness = seconds_since(start);
  }

  void ElasticModel::Impl::assemble_mass()
  {
    if (mass_assembled)
      return;
    const auto start = Clock::now();
    // K's pattern (and block size), copied rather than built again.
    mass.reinit(stiffness);
    const dealii::QGauss<3> quadrature(degree + 1);
    const ScalarBase        base(fe);
    // N_a at the points depends on the reference cell only; the mapping
    // enters through JxW.
    dealii::FEValues<3>        fe_values(mapping, fe.base_element(0), quadrature,
                                         dealii::update_values | dealii::update_JxW_values);
    const unsigned int         n_q = quadrature.size(), nb = base.n;
    dealii::FullMatrix<double> cell_matrix(fe.n_dofs_per_cell(), fe.n_dofs_per_cell());
    std::vector<dealii::types::global_dof_index> dof_indices(fe.n_dofs_per_cell());

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        const double rho = material(cell->material_id()).rho;
        // M couples equal components only: ρ ∫ N_a N_b in the three diagonal
        // positions of each 3×3 block, zero elsewhere.
        cell_matrix = 0.0;
        for (unsigned int a = 0; a < nb; ++a)
          for (unsigned int b = 0; b <= a; ++b)
            {
              double value = 0.0;
              for (unsigned int q = 0; q < n_q; ++q)
                value += fe_values.shape_value(a, q) * fe_values.shape_value(b, q) * fe_values.JxW(q);
              value *= rho;
              for (unsigned int c = 0; c < 3; ++c)
                {
                  const unsigned int i = base.system_index[a][c], j = base.system_index[b][c];
                  cell_matrix(i, j) = value;
                  cell_matrix(j, i) = value;
                }
            }
        cell->get_dof_indices(dof_indices);
        constraints.distribute_local_to_global(cell_matrix, dof_indices, mass);
      }
    mass.compress(dealii::VectorOperation::add);

    // distribute_local_to_global gave each constrained row a diagonal entry so
    // that K stays invertible; in M it would turn every constrained DoF into a
    // spurious eigenvalue K_ii/M_ii (step-36). A zero there makes it infinite.
    std::vector<dealii::types::global_dof_index> constrained;
    for (const auto i : owned_dofs)
      if (constraints.is_constrained(i))
        constrained.push_back(i);
    mass.clear_rows(constrained, 0.0);
    mass_assembled      = true;
    timings.assemble_mass = seconds_since(start);
  }

  dealii::PETScWrappers::MPI::Vector ElasticModel::Impl::ghosted(dealii::PETScWrappers::MPI::Vector owned) const
  {
    constraints.distribute(owned);
    dealii::PETScWrappers::MPI::Vector result(owned_dofs, relevant_dofs, communicator());
    result = owned;
    return result;
  }

  ElasticModel::ElasticModel(std::shared_ptr<const Mesh> mesh, const std::map<MaterialId, Material> &materials,
                             const unsigned int degree, const std::vector<Support> &supports)
    : pimpl(std::make_shared<Impl>(std::move(mesh), materials, degree, supports))
  {}
  ElasticModel::~ElasticModel()                               = default;
  ElasticModel::ElasticModel(ElasticModel &&) noexcept        = default;
  ElasticModel &ElasticModel::operator=(ElasticModel &&) noexcept = default;

  unsigned long  ElasticModel::n_dofs() const { return pimpl->dof_handler.n_dofs(); }
  unsigned int   ElasticModel::degree() const { return pimpl->degree; }
  const Timings &ElasticModel::timings() const { return pimpl->timings; }

  _p_Mat *ElasticModel::petsc_stiffness() { return static_cast<Mat>(pimpl->stiffness); }
  _p_Mat *ElasticModel::petsc_mass()
  {
    pimpl->assemble_mass();
    return static_cast<Mat>(pimpl->mass);
  }

  std::vector<long> ElasticModel::owned_boundary_dofs(const std::vector<BoundaryId> &boundaries) const
  {
    std::set<dealii::types::boundary_id> ids;
    for (const BoundaryId b : boundaries)
      ids.insert(static_cast<dealii::types::boundary_id>(b));
    const dealii::IndexSet on_boundary = dealii::DoFTools::extract_boundary_dofs(pimpl->dof_handler,
                                                                               dealii::ComponentMask(), ids);
    std::vector<long> result;
    for (const auto i : on_boundary)
      if (pimpl->owned_dofs.is_element(i))
        result.push_back(static_cast<long>(i));
    return result;
  }

  void ElasticModel::assemble_load_vector(const StaticLoad &load, _p_Vec *f) const
  {
    const auto rhs = assemble_load(*pimpl, load);
    VecCopy(static_cast<const Vec &>(rhs), f);
  }

  DisplacementField ElasticModel::field_from_vector(_p_Vec *u) const
  {
    dealii::PETScWrappers::MPI::Vector owned(pimpl->owned_dofs, pimpl->communicator());
    VecCopy(u, static_cast<const Vec &>(owned));
    auto field          = std::make_unique<DisplacementField::Impl>();
    field->model        = pimpl;
    field->displacement = pimpl->ghosted(std::move(owned));
    return DisplacementField(std::move(field));
  }
} // namespace fretsim::fem
