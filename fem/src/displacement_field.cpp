// Queries on a displacement solution: energies, surface means in cylindrical
// components, L2 errors, output.
#include "model_impl.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include <filesystem>

namespace fretsim::fem
{
  DisplacementField::DisplacementField(std::unique_ptr<Impl> impl)
    : pimpl(std::move(impl))
  {}
  DisplacementField::~DisplacementField()                                = default;
  DisplacementField::DisplacementField(DisplacementField &&) noexcept        = default;
  DisplacementField &DisplacementField::operator=(DisplacementField &&) noexcept = default;

  namespace
  {
    dealii::PETScWrappers::MPI::Vector owned_copy(const DisplacementField::Impl &field)
    {
      dealii::PETScWrappers::MPI::Vector u(field.model->owned_dofs, field.model->communicator());
      u = field.displacement;
      return u;
    }

    double expansion_of(const DisplacementField::Impl &field, const unsigned int material_id)
    {
      double e = 0.0;
      for (const InPlaneExpansion &x : field.expansions)
        if (static_cast<unsigned int>(x.body) == material_id)
          e += x.strain;
      return e;
    }

    /// Accumulates area-weighted cylindrical components at face quadrature points.
    class CylindricalAccumulator
    {
    public:
      void add(const dealii::Point<3> &x, const dealii::Tensor<1, 3> &u, const dealii::SymmetricTensor<2, 3> &s,
               const double weight)
      {
        const double               r = std::hypot(x[0], x[1]);
        const dealii::Tensor<1, 3> er({x[0] / r, x[1] / r, 0.0}), et({-x[1] / r, x[0] / r, 0.0}), ez({0.0, 0.0, 1.0});
        const double values[10] = {1.0,         u * er,      u * et,      u * ez,      er * (s * er),
                                   et * (s * et), ez * (s * ez), er * (s * et), er * (s * ez), et * (s * ez)};
        for (unsigned int k = 0; k < 10; ++k)
          sums[k] += weight * values[k];
      }

      CylindricalAverage result(const MPI_Comm comm) const
      {
        std::array<double, 10> total;
        dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(sums.data(), sums.size()), comm,
                                    dealii::ArrayView<double>(total.data(), total.size()));
        CylindricalAverage a;
        a.area = total[0];
        if (a.area <= 0.0)
          return a;
        double *mean[9] = {&a.u_r, &a.u_theta, &a.u_z, &a.s_rr, &a.s_tt, &a.s_zz, &a.s_rt, &a.s_rz, &a.s_tz};
        for (unsigned int k = 0; k < 9; ++k)
          *mean[k] = total[k + 1] / a.area;
        return a;
      }

    private:
      std::array<double, 10> sums{};
    };

    template <typename FaceSelector>
    CylindricalAverage face_average(const DisplacementField::Impl &field, const FaceSelector &selected)
    {
      const auto                      &model = *field.model;
      const dealii::QGauss<2>          quadrature(model.degree + 1);
      dealii::FEFaceValues<3>          fe_face_values(model.mapping, model.fe, quadrature,
                                                      dealii::update_values | dealii::update_gradients |
                                                        dealii::update_quadrature_points | dealii::update_JxW_values);
      const dealii::FEValuesExtractors::Vector    displacement(0);
      std::vector<dealii::Tensor<1, 3>>           u(quadrature.size());
      std::vector<dealii::SymmetricTensor<2, 3>>  strain(quadrature.size());
      CylindricalAccumulator                      sum;
      for (const auto &cell : model.dof_handler.active_cell_iterators())
        {
          if (!cell->is_locally_owned())
            continue;
          for (unsigned int f = 0; f < cell->n_faces(); ++f)
            {
              if (!selected(cell, f))
                continue;
              fe_face_values.reinit(cell, f);
              fe_face_values[displacement].get_function_values(field.displacement, u);
              fe_face_values[displacement].get_function_symmetric_gradients(field.displacement, strain);
              const Lame  &m = model.material(cell->material_id());
              const double e = expansion_of(field, cell->material_id());
              for (unsigned int q = 0; q < quadrature.size(); ++q)
                sum.add(fe_face_values.quadrature_point(q), u[q], stress(m, strain[q], e), fe_face_values.JxW(q));
            }
        }
      return sum.result(model.communicator());
    }
  } // namespace

  double DisplacementField::strain_energy() const
  {
    return 0.5 * pimpl->model->stiffness.matrix_norm_square(owned_copy(*pimpl));
  }

  CylindricalAverage DisplacementField::average_on_boundary(const BoundaryId boundary) const
  {
    const unsigned int id = static_cast<unsigned int>(boundary);
    return face_average(*pimpl, [id](const auto &cell, unsigned int f) {
      return cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == id;
    });
  }

  CylindricalAverage DisplacementField::average_on_interface(const MaterialId evaluated_in,
                                                             const MaterialId neighbour) const
  {
    const unsigned int inside = static_cast<unsigned int>(evaluated_in), outside = static_cast<unsigned int>(neighbour);
    return face_average(*pimpl, [inside, outside](const auto &cell, unsigned int f) {
      return cell->material_id() == inside && !cell->face(f)->at_boundary() &&
             cell->neighbor(f)->material_id() == outside;
    });
  }

  double DisplacementField::l2_error(const std::function<Vector3(const Point3 &)> &exact) const
  {
    const auto                              &model = *pimpl->model;
    const dealii::QGauss<3>                  quadrature(model.degree + 2);
    dealii::FEValues<3>                      fe_values(model.mapping, model.fe, quadrature,
                                                       dealii::update_values | dealii::update_quadrature_points |
                                                         dealii::update_JxW_values);
    const dealii::FEValuesExtractors::Vector displacement(0);
    std::vector<dealii::Tensor<1, 3>>        u(quadrature.size());
    double                                   sum = 0.0;
    for (const auto &cell : model.dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        fe_values[displacement].get_function_values(pimpl->displacement, u);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const dealii::Point<3> &x  = fe_values.quadrature_point(q);
            const Vector3           ue = exact({x[0], x[1], x[2]});
            for (unsigned int c = 0; c < 3; ++c)
              sum += (u[q][c] - ue[c]) * (u[q][c] - ue[c]) * fe_values.JxW(q);
          }
      }
    return std::sqrt(dealii::Utilities::MPI::sum(sum, model.communicator()));
  }

  Vector3 DisplacementField::mass_fractions() const
  {
    // M couples only equal components, so uᵀMu splits into Σ_c Σ_{i∈c} u_i (Mu)_i.
    auto &model = const_cast<ElasticModel::Impl &>(*pimpl->model);
    model.assemble_mass();
    const auto                         u = owned_copy(*pimpl);
    dealii::PETScWrappers::MPI::Vector mu(model.owned_dofs, model.communicator());
    model.mass.vmult(mu, u);

    std::vector<int> component(model.owned_dofs.n_elements(), -1);
    std::vector<dealii::types::global_dof_index> dof_indices(model.fe.n_dofs_per_cell());
    for (const auto &cell : model.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dof_indices);
          for (unsigned int i = 0; i < dof_indices.size(); ++i)
            if (model.owned_dofs.is_element(dof_indices[i]))
              component[model.owned_dofs.index_within_set(dof_indices[i])] =
                model.fe.system_to_component_index(i).first;
        }
    std::array<double, 3> sums{};
    unsigned int          k = 0;
    for (const auto i : model.owned_dofs)
      {
        if (component[k] >= 0)
          sums[component[k]] += u[i] * mu[i];
        ++k;
      }
    std::array<double, 3> total;
    dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(sums.data(), 3), model.communicator(),
                                dealii::ArrayView<double>(total.data(), 3));
    const double all = total[0] + total[1] + total[2];
    return {total[0] / all, total[1] / all, total[2] / all};
  }

  void DisplacementField::write_vtu(const std::string &directory, const std::string &name) const
  {
    const auto &model = *pimpl->model;
    if (dealii::Utilities::MPI::this_mpi_process(model.communicator()) == 0)
      std::filesystem::create_directories(directory);
    MPI_Barrier(model.communicator());
    dealii::DataOut<3> data_out;
    data_out.attach_dof_handler(model.dof_handler);
    data_out.add_data_vector(pimpl->displacement, std::vector<std::string>(3, "displacement"),
                             dealii::DataOut<3>::type_dof_data,
                             std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>(
                               3, dealii::DataComponentInterpretation::component_is_part_of_vector));
    data_out.build_patches(model.mapping, model.degree, dealii::DataOut<3>::curved_inner_cells);
    data_out.write_vtu_with_pvtu_record(directory + "/", name, 0, model.communicator(), 0, 0);
  }
} // namespace fretsim::fem
