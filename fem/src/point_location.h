#pragma once
// Finding the cells that hold given points, through the model's mapping (so on
// the curved geometry), each point answered by exactly one rank. Shared by the
// operators that act at points: StressSampler, SurfaceGridMap, SurfacePointMap.
#include "model_impl.h"

#include <optional>
#include <vector>

namespace fretsim::fem
{
  struct LocatedPoint
  {
    std::size_t                                 index; ///< position in the list searched
    dealii::DoFHandler<3>::active_cell_iterator cell;  ///< locally owned
    dealii::Point<3>                            reference; ///< in the unit cell [0, 1]³
  };

  /// Locates `points` in this rank's owned cells. The mapped surface only
  /// approximates a curved boundary (by chords for degree 1: a sagitta of a
  /// few % of a cell), so points up to a tenth of a cell outside are accepted
  /// and moved onto the cell; with `on_boundary`, onto the cell's face on that
  /// boundary (only from within a quarter of the cell: a point deeper inside
  /// is not on the boundary). A point on a face between two ranks' cells goes to the lower
  /// rank. Returns this rank's points; `missing` gets the indices no rank
  /// found (the same on every rank). Collective.
  std::vector<LocatedPoint> locate_points(const ElasticModel::Impl &model, const std::vector<dealii::Point<3>> &points,
                                          std::optional<BoundaryId> on_boundary, std::vector<std::size_t> &missing);
} // namespace fretsim::fem
