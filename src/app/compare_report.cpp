// `fretsim compare`'s report: the tables on the terminal and the CSV files
// and figure of the comparison.
#include "app/compare_stages.h"

#include <fretsim/scenes/figures.h>

#include <fretsim/fem/parallel_environment.h>
#include <fretsim/reduction/craig_bampton.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace fretsim::app::compare
{
  namespace
  {
    std::string sci(double value, int width = 10)
    {
      std::ostringstream s;
      if (std::isnan(value))
        s << std::setw(width) << "-";
      else
        s << std::setw(width) << std::scientific << std::setprecision(2) << value;
      return s.str();
    }

    std::string format_list(const std::vector<unsigned int> &values)
    {
      std::ostringstream s;
      for (std::size_t k = 0; k < values.size(); ++k)
        s << (k ? ", " : "") << values[k];
      return s.str();
    }

    /// The model, the full FE ring, the run and the notes on what is left out.
    void print_sources(std::ostream &out, const CompareInputs &in, const Plan &plan, const FullRingSetup &full)
    {
      const auto &matrices = plan.model.matrices;
      const auto &grid     = plan.grid();
      const auto &run      = plan.run;
      out << "model:        " << in.model_file << ": " << matrices.size() << " coordinates (" << matrices.n_constraint
          << " characteristic constraint + " << matrices.n_modal << " fixed-interface modes), interface grid "
          << grid.nx << " x " << grid.ny << ", " << plan.model.raceway.angles.size() << " ball positions, "
          << plan.raceway_points.size() << " raceway sample points\n"
          << "full FE:      " << full.dofs << " DoFs (FE_Q" << plan.body.degree << ", "
          << fem::ParallelEnvironment::n_ranks() << " rank(s)); mesh, K, M and the factorisation of K - sigma M "
          << "(sigma = -(2 pi " << reduction::ReductionSettings{}.static_shift_hz << " Hz)^2) in " << std::fixed
          << std::setprecision(2) << full.seconds << " s\n"
          << std::defaultfloat << "run:          " << in.results_file << ": " << run.n_snapshots << " snapshots, "
          << run.n_balls << " balls";
      if (run.ball_pass_frequency_hz > 0.0)
        out << ", ball pass " << run.ball_pass_frequency_hz << " Hz";
      if (!plan.run_on_layer)
        out << "; with " << run.other_problem();
      out << "; instants at snapshots";
      for (const auto &i : plan.instants)
        out << ' ' << i.snapshot;
      out << "\n";
      if (!full.residual->ball.empty())
        out << "residual:     R = K^-1 - T K_r^-1 T^T on the grid from " << full.residual->solves
            << " full and reduced solves (unit loads on the grid's first column, a unit ball) in " << std::fixed
            << std::setprecision(2) << full.residual->seconds << " s\n" << std::defaultfloat;
      if (run.other_model)
        out << "note:         the run used a model of " << run.n_coordinates << " coordinates, not this one's "
            << matrices.size() << ": its loads and pressures are compared, its own q is not\n";
      const Study &study = plan.study;
      if (!study.dropped_fixed.empty())
        out << "note:         m' = " << format_list(study.dropped_fixed) << " left out (the model has m = "
            << matrices.n_modal << ")\n";
      if (!study.dropped_constraint.empty())
        out << "note:         n_cc' = " << format_list(study.dropped_constraint) << " left out ("
            << (study.reduced_interface ? "between the six rigid-body motions and the model's n_cc = " +
                                            std::to_string(matrices.n_constraint)
                                        : std::string("the model keeps every boundary DoF: no interface modes to truncate"))
            << ")\n";
    }

    /// The pressure on the Winkler foundation, the model as used, and with
    /// its residual flexibility in series.
    void print_winkler(std::ostream &out, const CompareInputs &in, const Plan &plan, const RingResults &ring)
    {
      out << "\npressure on the Winkler foundation under the run's ball loads alone (k_n = " << in.normal_stiffness
          << " Pa/m, radial interference " << in.radial_interference
          << " m; static, full FE against the model; errors over the interface grid relative to the full field:\n"
          << " max-norm / max p and L2; 'run' = the run's own pressure at the instant, with tractions and dynamics;\n"
          << " solves = linear solves of the active-set iteration, the full one starting from the model's contact set;"
          << " full set-up " << std::fixed << std::setprecision(2) << ring.winkler_setup << std::defaultfloat << " s)\n"
          << "  inst  p_max full  model    run [MPa]  p err max   p err L2  contact full  model  solves full  model"
             "   full [s]  model [ms]  run vs full: max      L2  run vs model\n";
      for (const Row &r : ring.rows)
        if (r.whole_model)
          {
            const auto &w = r.winkler;
            out << std::setw(6) << r.instant << std::fixed << std::setprecision(2) << std::setw(11)
                << 1e-6 * w.full_peak << std::setw(7) << 1e-6 * w.reduced_peak << std::setw(12) << 1e-6 * r.max_pressure
                << ' ' << sci(w.error_max) << ' ' << sci(w.error_l2) << std::setprecision(4) << std::setw(14)
                << w.full_contact << std::setw(7) << w.reduced_contact << std::setprecision(0) << std::setw(13)
                << w.full_iterations << std::setw(7) << w.reduced_iterations << std::setprecision(3) << std::setw(11)
                << w.full_seconds << std::setw(12) << 1e3 * w.reduced_seconds << "       " << sci(w.run_error_max)
                << ' ' << sci(w.run_error_l2) << "    " << sci(w.run_vs_reduced_max) << "\n"
                << std::defaultfloat;
          }
      if (std::any_of(ring.rows.begin(), ring.rows.end(),
                      [](const Row &r) { return !std::isnan(r.winkler.residual_peak); }))
        {
          out << "the same with the model's residual flexibility in series (R = K^-1 - T K_r^-1 T^T, what the run "
                 "solves with Interface/Ring residual flexibility):\n"
                 "  inst  p_max full  model+R [MPa]  p err max   p err L2  contact model+R  Newton    [s]\n";
          for (const Row &r : ring.rows)
            if (r.whole_model)
              {
                const auto &w = r.winkler;
                out << std::setw(6) << r.instant << std::fixed << std::setprecision(2) << std::setw(11)
                    << 1e-6 * w.full_peak << std::setw(15) << 1e-6 * w.residual_peak << ' ' << sci(w.residual_error_max)
                    << ' ' << sci(w.residual_error_l2) << std::setprecision(4) << std::setw(17) << w.residual_contact
                    << std::setprecision(0) << std::setw(8) << w.residual_iterations << std::setprecision(2)
                    << std::setw(7) << w.residual_seconds << "\n"
                    << std::defaultfloat;
              }
        }
      for (const std::string &note : ring.winkler_notes)
        out << "note: Winkler solve failed at " << note << "\n";
      if (!plan.run_on_layer)
        out << "note: the run had " << plan.run.other_problem()
            << ": this check is of the model on the layer over the rigid housing alone, and the run's pressure is not "
               "compared with it (nan); the tables above and below use the run's own pressure and tractions on the "
               "ring\n";
    }

    /// The worst of the instants' rows of truncation (m', n_cc'): one line of the study.
    void print_truncation(std::ostream &out, const std::vector<Row> &rows, unsigned int m, unsigned int c)
    {
      Errors worst;
      double seconds = 0.0, winkler_max = not_measured, winkler_l2 = not_measured, winkler_seconds = 0.0;
      double worst_ratio = not_measured, most_solves = 0.0; // reduced / full peak farthest from 1
      std::size_t count = 0, size = 0;
      for (const Row &r : rows)
        if (r.fixed_interface == m && r.constraint == c)
          {
            const auto take = [](double &w, double v) { w = std::isnan(w) ? v : std::max(w, v); };
            take(worst.u_r, r.error.u_r);
            take(worst.u_theta, r.error.u_theta);
            take(worst.u_z, r.error.u_z);
            take(worst.grid_stress, r.error.grid_stress);
            take(worst.raceway_stress, r.error.raceway_stress);
            take(worst.raceway_stress_far, r.error.raceway_stress_far);
            take(worst.energy, r.error.energy);
            take(winkler_max, r.winkler.error_max);
            take(winkler_l2, r.winkler.error_l2);
            const double ratio = r.winkler.reduced_peak / r.winkler.full_peak;
            if (std::isnan(worst_ratio) || std::abs(ratio - 1.0) > std::abs(worst_ratio - 1.0))
              worst_ratio = ratio;
            most_solves = std::max(most_solves, std::isnan(r.winkler.reduced_iterations) ? 0.0 : r.winkler.reduced_iterations);
            winkler_seconds += std::isnan(r.winkler.reduced_seconds) ? 0.0 : r.winkler.reduced_seconds;
            seconds += r.reduced;
            size = r.size;
            ++count;
          }
      out << std::setw(7) << m << std::setw(7) << c << std::setw(7) << size << std::fixed << std::setprecision(3)
          << std::setw(14) << 1e3 * seconds / std::max<std::size_t>(count, 1) << ' ' << sci(worst.u_r) << "   "
          << sci(worst.u_theta) << ' ' << sci(worst.u_z) << "   " << sci(worst.grid_stress) << "   "
          << sci(worst.raceway_stress) << "  " << sci(worst.raceway_stress_far) << ' ' << sci(worst.energy)
          << "  |         " << sci(winkler_max) << ' ' << sci(winkler_l2) << std::fixed << std::setprecision(3)
          << std::setw(12) << worst_ratio << std::setprecision(0) << std::setw(8) << most_solves
          << std::setprecision(2) << std::setw(11) << 1e3 * winkler_seconds / std::max<std::size_t>(count, 1)
          << "\n"
          << std::defaultfloat;
    }

    /// The study: the worst instant per truncation.
    void print_study(std::ostream &out, const Plan &plan, const RingResults &ring)
    {
      out << "\nerror against the reduced model's size (worst of the " << plan.instants.size()
          << " instants; reduced time: mean per instant, load projection + factorisation + solve + recovery)\n"
          << "     m'  n_cc'   size  reduced [ms]    u_r err  u_theta err    u_z err  stress grid  stress race    race far"
             "     energy  | Winkler: p err max   p err L2  peak ratio  solves  time [ms]\n";
      for (const auto &[m, c] : plan.study.truncations)
        print_truncation(out, ring.rows, m, c);
    }

    /// The full-FE transients against the run.
    void print_transients(std::ostream &out, const CompareInputs &in, const Plan &plan, const RingResults &ring)
    {
      const RunFields &run = plan.run;
      for (const TransientTiming &transient : ring.transients)
        {
          out << std::setprecision(6);
          const double reduced_per_step = transient.reduced_per_step;
          const double steps_per_second = run.integrator_steps / run.time.back(); // of simulated time
          out << "\nfull-FE transient against the run ("
              << (transient.housing_meshed ? "ring and housing (" + in.full_transient_housing_config +
                                               ") meshed and joined by the layer"
                                           : std::string("the ring on the rigid Winkler foundation"))
              << ", Newmark, ball loads from the run, no bristle tractions"
              << (plan.run_on_layer || transient.housing_meshed ? "" : ", without " + run.other_problem())
              << ": a lower bound on a full-FE co-simulation's cost)\n"
              << "  " << transient.dofs << " DoFs; " << transient.steps << " steps of dt = " << transient.time_step
              << " s (the run's mean: " << static_cast<long long>(run.integrator_steps) << " steps in "
              << run.time.back() << " s) from t = " << transient.start_time << " s; " << transient.solves
              << " linear solves, " << transient.factorisations << " factorisations; static start " << std::fixed
              << std::setprecision(2) << transient.start_seconds << " s (from the run's contact set); one factorisation "
              << transient.mean_factorisation_seconds() << " s (mean of " << transient.factorisations_all
              << "); peak pressure " << 1e-6 * transient.peak_pressure << " MPa\n"
              << std::defaultfloat << "  full FE: " << transient.full_per_step() << " s per step; the run: "
              << reduced_per_step << " s per step (its whole run: integration, contact, stresses, Dang Van)\n"
              << "  full / reduced: " << std::fixed << std::setprecision(1)
              << transient.full_per_step() / reduced_per_step << std::defaultfloat;
          if (run.inner_ring_frequency_hz > 0.0)
            out << "; per inner-ring revolution at the run's steps: full " << std::fixed << std::setprecision(0)
                << transient.full_per_step() * steps_per_second / run.inner_ring_frequency_hz << " s, reduced "
                << std::setprecision(1) << reduced_per_step * steps_per_second / run.inner_ring_frequency_hz << " s"
                << std::defaultfloat;
          out << "\n";
        }
      for (const std::string &note : ring.transient_notes)
        out << "\nnote: a full-FE transient failed: " << note << "\n";
      if (ring.transients.empty() && ring.transient_notes.empty() && in.full_transient_steps > 0)
        out << "\nnote: no full-FE transient: the results file does not record the run's steps and time (a run made "
               "before they were written)\n";
    }

    /// The flexible housing against its reduced model, or why it is not compared.
    void print_housing(std::ostream &out, const CompareInputs &in, const Plan &plan,
                       const std::vector<HousingComparison::Result> &housing)
    {
      if (plan.housing)
        {
          out << "\nthe flexible housing (" << in.housing_reduction_config << ", " << plan.housing->coordinates()
              << " coordinates; full FE " << plan.housing->full_dofs() << " DoFs, set-up " << std::fixed
              << std::setprecision(2) << plan.housing->setup_seconds() << std::defaultfloat
              << " s) under the run's interface tractions, equal and opposite to the ring's; u_r on the bore grid,\n"
                 " max |error| / max |u_r full|: the reduced model solved statically (alone, and '+R' with its "
                 "residual flexibility of the pressure), and the run's own housing coordinates (with its dynamics)\n"
              << "  inst        t [s]  max u_r full [um]  reduced err         +R    run err  run vs reduced   full [s]  "
                 "reduced [ms]\n";
          for (std::size_t i = 0; i < housing.size(); ++i)
            {
              const auto &h = housing[i];
              out << std::setw(6) << i << std::setw(13) << std::setprecision(6) << plan.instants[i].time << std::fixed
                  << std::setprecision(4) << std::setw(19) << 1e6 * h.full_max_u_r << std::defaultfloat << "  "
                  << sci(h.reduced_error) << ' ' << sci(h.reduced_residual_error) << ' ' << sci(h.run_error) << "      "
                  << sci(h.run_vs_reduced) << std::fixed << std::setprecision(3) << std::setw(11) << h.full_seconds
                  << std::setw(14) << 1e3 * h.reduced_seconds << "\n"
                  << std::defaultfloat;
            }
        }
      if (plan.run.housing_coordinates > 0 && !plan.housing)
        out << "\nnote: the run had " << plan.run.other_problem()
            << ", but the scene names no Model/Housing reduction configuration: the housing is not compared\n";
    }

    /// compare_housing.csv: one line per instant.
    void write_housing_csv(const std::string &path, const Plan &plan,
                           const std::vector<HousingComparison::Result> &housing)
    {
      std::ofstream csv(path);
      csv << "instant,time_s,full_max_u_r_m,reduced_u_r_error,reduced_with_residual_u_r_error,run_u_r_error,"
             "run_vs_reduced_u_r,full_s,reduced_s\n"
          << std::setprecision(10);
      for (std::size_t i = 0; i < housing.size(); ++i)
        {
          const auto &h = housing[i];
          csv << i << ',' << plan.instants[i].time << ',' << h.full_max_u_r << ',' << h.reduced_error << ','
              << h.reduced_residual_error << ',' << h.run_error << ',' << h.run_vs_reduced << ',' << h.full_seconds
              << ',' << h.reduced_seconds << '\n';
        }
    }

    /// One line per full-FE transient: its timing against the run's.
    void write_transient_csv(const std::string &path, const std::vector<TransientTiming> &timings, const RunFields &run)
    {
      std::ofstream csv(path);
      csv << "housing_meshed,dofs,steps,time_step_s,start_time_s,solves,factorisations,start_s,full_s_per_step,"
             "run_steps,run_s,reduced_s_per_step,full_over_reduced,peak_pressure_Pa,factorisation_s\n"
          << std::setprecision(10);
      for (const TransientTiming &t : timings)
        csv << (t.housing_meshed ? 1 : 0) << ',' << t.dofs << ',' << t.steps << ',' << t.time_step << ','
            << t.start_time << ',' << t.solves << ',' << t.factorisations << ',' << t.start_seconds << ','
            << t.full_per_step() << ',' << run.integrator_steps << ',' << run.run_seconds << ',' << t.reduced_per_step
            << ',' << t.full_per_step() / t.reduced_per_step << ',' << t.peak_pressure << ','
            << t.mean_factorisation_seconds() << '\n';
    }

    void write_csv(const std::string &path, const std::vector<Row> &rows)
    {
      std::ofstream csv(path);
      csv << "instant,snapshot,time_s,fixed_interface_modes,characteristic_constraint_modes,reduced_size,"
             "whole_model,balls,ball_load_sum_N,max_pressure_Pa,net_force_N,full_setup_s,full_solve_s,reduced_s,"
             "error_u_r,error_u_theta,error_u_z,error_stress_grid,error_stress_raceway,error_stress_raceway_far,"
             "error_ball_approach,error_energy,run_error_u_r,run_error_u_theta,run_error_u_z,run_error_stress_grid,"
             "run_error_stress_raceway,run_error_stress_raceway_far,run_error_ball_approach,full_max_u_r_m,"
             "reduced_max_u_r_m,full_max_stress_grid_Pa,full_max_stress_raceway_Pa,full_max_u_r_balls_m,"
             "error_u_r_balls,error_stress_grid_balls,error_stress_raceway_balls,error_energy_balls,"
             "error_u_r_tractions,error_stress_grid_tractions,error_stress_raceway_tractions,error_energy_tractions,"
             "winkler_normal_stiffness_Pa_per_m,winkler_radial_interference_m,winkler_full_peak_pressure_Pa,"
             "winkler_reduced_peak_pressure_Pa,winkler_error_pressure_max,winkler_error_pressure_l2,"
             "winkler_full_contact_fraction,winkler_reduced_contact_fraction,winkler_full_iterations,"
             "winkler_reduced_iterations,winkler_full_s,winkler_reduced_s,winkler_run_error_pressure_max,"
             "winkler_run_error_pressure_l2,winkler_run_vs_reduced_error_pressure_max,"
             "error_u_r_with_residual,error_u_r_balls_with_residual,winkler_with_residual_peak_pressure_Pa,"
             "winkler_with_residual_error_pressure_max,winkler_with_residual_error_pressure_l2,"
             "winkler_with_residual_contact_fraction,winkler_with_residual_iterations,winkler_with_residual_s\n";
      csv << std::setprecision(10);
      for (const Row &r : rows)
        {
          csv << r.instant << ',' << r.snapshot << ',' << r.time << ',' << r.fixed_interface << ',' << r.constraint
              << ',' << r.size << ',' << (r.whole_model ? 1 : 0) << ',' << r.balls << ',' << r.ball_load_sum << ','
              << r.max_pressure << ',' << r.net_force << ',' << r.full_setup << ',' << r.full_solve << ',' << r.reduced;
          for (const Errors *e : {&r.error, &r.run})
            {
              csv << ',' << e->u_r << ',' << e->u_theta << ',' << e->u_z << ',' << e->grid_stress << ','
                  << e->raceway_stress << ',' << e->raceway_stress_far << ',' << e->approach;
              if (e == &r.error)
                csv << ',' << e->energy;
            }
          csv << ',' << r.full_max_u_r << ',' << r.reduced_max_u_r << ',' << r.full_max_stress_grid << ','
              << r.full_max_stress_raceway << ',' << r.full_max_u_r_balls;
          for (const Errors *e : {&r.error_balls, &r.error_tractions})
            csv << ',' << e->u_r << ',' << e->grid_stress << ',' << e->raceway_stress << ',' << e->energy;
          const WinklerComparison &w = r.winkler;
          for (const double v : {w.normal_stiffness, w.radial_interference, w.full_peak, w.reduced_peak, w.error_max,
                                 w.error_l2, w.full_contact, w.reduced_contact, w.full_iterations,
                                 w.reduced_iterations, w.full_seconds, w.reduced_seconds, w.run_error_max,
                                 w.run_error_l2, w.run_vs_reduced_max, r.error_u_r_residual,
                                 r.error_u_r_residual_balls, w.residual_peak, w.residual_error_max,
                                 w.residual_error_l2, w.residual_contact, w.residual_iterations, w.residual_seconds})
            csv << ',' << v;
          csv << '\n';
        }
      if (!csv)
        throw std::runtime_error("cannot write " + path);
    }

    /// compare_pressure.csv: one line per grid column along the circumference.
    void write_profile(const std::string &path, const fem::CylinderGrid &grid, const PressureProfile &profile)
    {
      std::ofstream csv(path);
      csv << "# pressure on the Winkler foundation in the interface grid's axial middle at instant " << profile.instant
          << " (snapshot " << profile.snapshot << ", t = " << std::setprecision(10) << profile.time
          << " s), the one with the highest full FE peak\n";
      if (!profile.run_other_problem.empty())
        csv << "# run_Pa is the run's own pressure, with " << profile.run_other_problem
            << ": not the layer-alone problem of the other columns\n";
      csv << "theta_deg,full_Pa,run_Pa";
      for (const std::string &name : profile.reduced_names)
        csv << ",reduced_" << name << "_Pa";
      csv << '\n';
      for (std::size_t i = 0; i < profile.full.size(); ++i)
        {
          csv << grid.x(static_cast<int>(i)) / grid.radius * 180.0 / M_PI << ',' << profile.full[i] << ','
              << profile.run[i];
          for (const auto &reduced : profile.reduced)
            csv << ',' << (reduced.empty() ? not_measured : reduced[i]);
          csv << '\n';
        }
      if (!csv)
        throw std::runtime_error("cannot write " + path);
    }
  } // namespace

  void print_setup(std::ostream &out, const CompareInputs &in, const Plan &plan, const FullRingSetup &full)
  {
    const auto &matrices = plan.model.matrices;
    print_sources(out, in, plan, full);
    out << "\nerrors of the reduced model (m = " << matrices.n_modal << ", n_cc = " << matrices.n_constraint
        << ") against the full FE ring, max-norm relative to the full field's maximum\n"
        << "(u on the interface grid, stress on the grid and at the raceway points, ball approach r.q vs f.u,\n"
        << " energy norm of the Ritz error; 'run' = the run's own dynamic q, rigid motion removed, against the\n"
        << " full static solution; both models balance the loads' resultant F_net by rigid-body inertia;\n"
        << " 'race far': raceway points more than " << std::setprecision(3) << full.local_zone * 180.0 / M_PI
        << " deg from every ball, outside the footprint's local stress;\n"
        << " '+R': u_r with the basis's residual flexibility added, R = K^-1 - T K_r^-1 T^T taken circulant in"
           " theta)\n" << std::defaultfloat
        << "  inst  snapshot      t [s]  balls   sum Q [N]  p_max [MPa]  F_net [N]  max u_r full/reduced [um]    u_r err  u_theta err    u_z err"
           "  stress grid  stress race    race far   approach     energy  run u_r err  run stress"
           "  u_r: balls alone  tractions alone  u_r +R   balls +R  full [s]  reduced [ms]\n";
  }

  void print_instant(std::ostream &out, const Row &row)
  {
    out << std::setw(6) << row.instant << std::setw(10) << row.snapshot << std::setw(11) << std::setprecision(4)
        << std::defaultfloat << row.time << std::setw(7) << row.balls << std::setw(12) << std::fixed
        << std::setprecision(1) << row.ball_load_sum << std::setw(13) << std::setprecision(2) << 1e-6 * row.max_pressure
        << ' ' << sci(row.net_force) << std::fixed << std::setprecision(3) << std::setw(13)
        << 1e6 * row.full_max_u_r << std::setw(14) << 1e6 * row.reduced_max_u_r << ' '
        << sci(row.error.u_r) << "   " << sci(row.error.u_theta) << ' ' << sci(row.error.u_z)
        << "   " << sci(row.error.grid_stress) << "   " << sci(row.error.raceway_stress) << "  "
        << sci(row.error.raceway_stress_far) << ' ' << sci(row.error.approach) << ' '
        << sci(row.error.energy) << "   " << sci(row.run.u_r) << "  " << sci(row.run.grid_stress)
        << ' ' << sci(row.error_balls.u_r) << "      " << sci(row.error_tractions.u_r) << "    "
        << sci(row.error_u_r_residual) << ' ' << sci(row.error_u_r_residual_balls) << std::fixed
        << std::setprecision(3) << std::setw(10) << row.full_setup + row.full_solve << std::setw(14)
        << 1e3 * row.reduced << "\n"
        << std::defaultfloat;
  }

  void print_summary(std::ostream &out, const CompareInputs &in, const Plan &plan, const RingResults &ring,
                     const std::vector<HousingComparison::Result> &housing)
  {
    out << "full [s] = mesh + K + M + factorisation (once) + this instant's load assembly and solve\n";
    print_winkler(out, in, plan, ring);
    print_study(out, plan, ring);
    print_transients(out, in, plan, ring);
    print_housing(out, in, plan, housing);
  }

  std::vector<std::string> write_files(const std::string &output_directory, bool plots, const Plan &plan,
                                       const RingResults &ring,
                                       const std::vector<HousingComparison::Result> &housing)
  {
    std::vector<std::string> files;
    const auto               path = [&](const char *name) {
      return (std::filesystem::path(output_directory) / name).string();
    };
    std::filesystem::create_directories(output_directory);
    if (plan.housing)
      {
        files.push_back(path("compare_housing.csv"));
        write_housing_csv(files.back(), plan, housing);
      }
    const std::string csv_path = path("compare.csv");
    write_csv(csv_path, ring.rows);
    files.push_back(csv_path);
    if (!ring.transients.empty())
      {
        files.push_back(path("compare_transient.csv"));
        write_transient_csv(files.back(), ring.transients, plan.run);
      }
    if (!ring.profile.full.empty())
      {
        files.push_back(path("compare_pressure.csv"));
        write_profile(files.back(), plan.grid(), ring.profile);
      }
    if (plots)
      for (const auto &figure : scenes::run_plot_script("plot_compare.py", {csv_path}))
        files.push_back(figure);
    return files;
  }
} // namespace fretsim::app::compare
