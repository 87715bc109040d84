// ElasticModel: DoFs, constraints, and the assembly of K and M.
#include "model_impl.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <petscmat.h>
#include <petscvec.h>

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

    dealii::DynamicSparsityPattern dsp(relevant_dofs);
    dealii::DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
    dealii::SparsityTools::distribute_sparsity_pattern(dsp, owned_dofs, communicator(), relevant_dofs);
    stiffness.reinit(owned_dofs, owned_dofs, dsp, communicator());
    mass.reinit(owned_dofs, owned_dofs, dsp, communicator());
    timings.setup_dofs = seconds_since(start);
  }

  void ElasticModel::Impl::assemble_stiffness()
  {
    const auto                    start = Clock::now();
    const dealii::QGauss<3>       quadrature(degree + 1);
    dealii::FEValues<3>           fe_values(mapping, fe, quadrature,
                                            dealii::update_gradients | dealii::update_JxW_values);
    const unsigned int            n = fe.n_dofs_per_cell();
    dealii::FullMatrix<double>    cell_matrix(n, n);
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    std::vector<unsigned int>     component(n);
    for (unsigned int i = 0; i < n; ++i)
      component[i] = fe.system_to_component_index(i).first;

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        const Lame &m = material(cell->material_id());
        cell_matrix   = 0.0;
        // φ_i = N_i e_{c_i}: a(φ_j, φ_i) = λ ∂_{c_i}N_i ∂_{c_j}N_j
        //   + μ (∂_{c_j}N_i ∂_{c_i}N_j + δ_{c_i c_j} ∇N_i·∇N_j).
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const double jxw = fe_values.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              {
                const dealii::Tensor<1, 3> &gi = fe_values.shape_grad(i, q);
                const unsigned int          ci = component[i];
                for (unsigned int j = 0; j <= i; ++j)
                  {
                    const dealii::Tensor<1, 3> &gj = fe_values.shape_grad(j, q);
                    const unsigned int          cj = component[j];
                    double value = m.lambda * gi[ci] * gj[cj] + m.mu * gi[cj] * gj[ci];
                    if (ci == cj)
                      value += m.mu * (gi * gj);
                    cell_matrix(i, j) += value * jxw;
                  }
              }
          }
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i + 1; j < n; ++j)
            cell_matrix(i, j) = cell_matrix(j, i);
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
    const auto                 start = Clock::now();
    const dealii::QGauss<3>    quadrature(degree + 1);
    dealii::FEValues<3>        fe_values(mapping, fe, quadrature, dealii::update_values | dealii::update_JxW_values);
    const unsigned int         n = fe.n_dofs_per_cell();
    dealii::FullMatrix<double> cell_matrix(n, n);
    std::vector<dealii::types::global_dof_index> dof_indices(n);
    std::vector<unsigned int>  component(n);
    for (unsigned int i = 0; i < n; ++i)
      component[i] = fe.system_to_component_index(i).first;

    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        const double rho = material(cell->material_id()).rho;
        cell_matrix      = 0.0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const double w = rho * fe_values.JxW(q);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j <= i; ++j)
                if (component[i] == component[j])
                  cell_matrix(i, j) += fe_values.shape_value(i, q) * fe_values.shape_value(j, q) * w;
          }
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i + 1; j < n; ++j)
            cell_matrix(i, j) = cell_matrix(j, i);
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
