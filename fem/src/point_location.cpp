#include "point_location.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/grid_tools_cache.h>

#include <algorithm>
#include <cmath>

namespace fretsim::fem
{
  std::vector<LocatedPoint> locate_points(const ElasticModel::Impl &model, const std::vector<dealii::Point<3>> &points,
                                          const std::optional<BoundaryId> on_boundary,
                                          std::vector<std::size_t> &missing)
  {
    const auto                 &tria    = model.mesh->impl().triangulation;
    const unsigned int          me      = dealii::Utilities::MPI::this_mpi_process(model.communicator());
    const unsigned int          n_ranks = dealii::Utilities::MPI::n_mpi_processes(model.communicator());
    dealii::GridTools::Cache<3> cache(tria, model.mapping);

    std::vector<LocatedPoint> found;
    std::vector<unsigned int> owner(points.size(), n_ranks);
    auto                      hint = tria.begin_active();
    for (std::size_t k = 0; k < points.size(); ++k)
      {
        const auto located = dealii::GridTools::find_active_cell_around_point(cache, points[k], hint, {}, 0.1);
        if (located.first == tria.end() || !located.first->is_locally_owned())
          continue;
        hint                       = located.first;
        dealii::Point<3> reference = located.second;
        for (unsigned int d = 0; d < 3; ++d)
          reference[d] = std::clamp(reference[d], 0.0, 1.0);
        if (on_boundary)
          {
            // Within a quarter of the cell from the face (a Q1 chord across a
            // coarse groove cell runs up to ~0.15 of the wall cell inside the
            // exact arc): a point deeper in a cell that merely touches the
            // boundary is not on it.
            bool on_face = false;
            for (unsigned int f = 0; f < located.first->n_faces(); ++f)
              if (located.first->face(f)->at_boundary() &&
                  located.first->face(f)->boundary_id() == static_cast<unsigned int>(*on_boundary) &&
                  std::abs(reference[f / 2] - f % 2) <= 0.25)
                {
                  reference[f / 2] = f % 2;
                  on_face          = true;
                }
            if (!on_face)
              continue;
          }
        found.push_back({k,
                         dealii::DoFHandler<3>::active_cell_iterator(&tria, located.first->level(),
                                                                     located.first->index(), &model.dof_handler),
                         reference});
        owner[k] = me;
      }

    dealii::Utilities::MPI::min(owner, model.communicator(), owner);
    missing.clear();
    for (std::size_t k = 0; k < points.size(); ++k)
      if (owner[k] == n_ranks)
        missing.push_back(k);
    std::vector<LocatedPoint> mine;
    for (auto &p : found)
      if (owner[p.index] == me)
        mine.push_back(std::move(p));
    return mine;
  }
} // namespace fretsim::fem
