#pragma once
// The outer ring's own full-FE stresses below its interface: the stresses
// on the depth layers under every grid cell from the interface tractions and
// the balls' raceway loads, by superposing the ring's influence tables
// (interface_influence.h). Unlike a half-space's, they hold the ring's
// structural stress — its bending between the balls — which is most of the
// ring's stress cycle at the seat (docs/fe_reference.md).
#include <fretsim/fem/mesh.h>
#include <fretsim/models/interface_influence.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fretsim::reduction
{
  struct ReducedModel;
} // namespace fretsim::reduction

namespace fretsim::models
{
  struct RingHousingRequest;

  class RingStressTable
  {
  public:
    /// Tables with stresses and a ball table; throws std::invalid_argument otherwise.
    explicit RingStressTable(InterfaceInfluence tables);
    ~RingStressTable();
    RingStressTable(RingStressTable &&) noexcept;
    RingStressTable(const RingStressTable &)            = delete;
    RingStressTable &operator=(const RingStressTable &) = delete;

    /// The stresses [layer][6][ny][nx] in the tables' contact frame (xx
    /// circumferential, yy axial, zz radial, yz, xz, xy; tension positive)
    /// [Pa] under balls at `ball_angles` [rad] with loads `ball_loads` [N]
    /// and tractions on the ring (pushing in, along +θ, along +z) [Pa].
    void evaluate(const std::vector<double> &ball_angles, const std::vector<double> &ball_loads,
                  const std::vector<double> &pressure, const std::vector<double> &shear_x,
                  const std::vector<double> &shear_y, std::vector<double> &stress) const;

    const InterfaceInfluence &tables() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };

  /// The ring's tables on a mesh of `divisions` of the ring in `ring` (its
  /// configuration `config_file`), loaded on `model`'s interface grid and by
  /// a ball with `model`'s raceway footprint, stresses on `depths`.
  /// Collective under MPI; the same tables on every rank.
  InterfaceInfluence ring_influence(const RingHousingRequest &ring, const std::string &config_file,
                                    const reduction::ReducedModel &model, const fem::MeshDivisions &divisions,
                                    const std::vector<double> &depths, int points_per_side);

  /// What a scene's ring stress tables are made from, and the input hash
  /// their file carries.
  struct RingStressSource
  {
    std::string         config;       ///< the ring's reduction configuration
    /// The raceway footprints set over it (ModelSource::footprint_overrides).
    std::vector<std::pair<std::string, std::string>> footprint_overrides;
    std::string         file;         ///< where the tables are kept
    fem::MeshDivisions  divisions;
    std::vector<double> depths;       ///< [m]
    int                 points_per_side = 3;
    std::string         expected_hash;
  };

  /// The source's input hash from its configuration and footprints, mesh,
  /// depths and points.
  std::string ring_stress_hash(const RingStressSource &source);

  /// Writes stress tables (without their displacement tables) atomically;
  /// reads them back, throwing std::runtime_error for a missing, unreadable
  /// or stale file (another input hash).
  void write_ring_stress_file(const std::string &path, const InterfaceInfluence &tables, const std::string &hash);
  InterfaceInfluence read_ring_stress_file(const std::string &path, const std::string &expected_hash);
} // namespace fretsim::models
