#pragma once
// `fretsim compare` on a run with a flexible housing: the housing's reduced
// model against its full FE at the run's interface tractions (the ring's
// part is compare_command.h's).
#include <fretsim/fem/mesh.h>

#include <memory>
#include <string>
#include <vector>

namespace fretsim::app
{
  /// The housing's full FE and reduced model, read and checked before
  /// anything is built or written (InputError naming the file and parameter).
  class HousingComparison
  {
  public:
    /// `source`: the scene file, for messages. `config`: the housing's
    /// ring_housing configuration (Model/Housing reduction configuration),
    /// `model_file` its reduced model (Model/Housing model file), whose
    /// interface grid must have `grid_cells` cells; its bore fits `ring`.
    HousingComparison(const std::string &source, const std::string &config, const std::string &model_file,
                      const fem::RingGeometry &ring, std::size_t grid_cells);
    ~HousingComparison();

    std::size_t coordinates() const; ///< the housing model's size n_h

    /// One instant: the interface tractions the run put on the ring (the
    /// housing carries them equal and opposite) and the run's own housing
    /// coordinates (n_h; empty: none).
    struct Instant
    {
      std::vector<double> pressure, shear_x, shear_y; ///< [cell] [Pa]
      std::vector<double> run_q;
    };
    struct Result
    {
      double full_max_u_r = 0.0;  ///< the full FE bore's largest |u_r| [m]
      double reduced_error = 0.0; ///< the reduced model solved statically: max |Δu_r| / full_max_u_r [-]
      /// The same with the model's residual flexibility of the pressure
      /// added (Interface/Housing residual flexibility); nan if the model
      /// file has none [-].
      double reduced_residual_error = 0.0;
      double run_error = 0.0;     ///< the run's own q_h (dynamic), the same measure [-]; nan without it
      /// The run's q_h against the reduced static solution, the same measure:
      /// the housing's inertia at the instant, and a check that the
      /// tractions reach the housing as the co-simulation passed them [-].
      double run_vs_reduced = 0.0;
      double full_seconds = 0.0, reduced_seconds = 0.0; ///< this instant's solves [s]
    };

    /// Builds the full FE housing (held as in its configuration; MPI must be
    /// running: fem::ParallelEnvironment) and compares at every instant.
    /// Collective.
    std::vector<Result> run(const std::vector<Instant> &instants);

    double setup_seconds() const;    ///< mesh and full FE set-up of run() [s]
    unsigned long full_dofs() const; ///< after run()

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace fretsim::app
