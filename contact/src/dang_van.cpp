// Dang Van criterion on a field of points (docs/theory.md §2.6, docs/references.md §5).
// Everything deviatoric is carried in the 5-D orthonormal coordinates of
// detail::deviator_coordinates: the Euclidean norm there is sqrt(s:s), so
// means, path centres and balls are genuine ones in stress space (rotation
// invariant), and a state needs 5 doubles instead of 6.
#include <fretsim/contact/dang_van.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace fretsim::contact
{
  namespace
  {
    constexpr int    dim      = detail::deviator_dimension;
    constexpr double sqrt2    = 1.4142135623730950488;
    constexpr double sqrt6    = 2.4494897427831780982;
    // Products with reciprocals instead of divisions: the hot loop divides
    // nowhere it need not (a division costs several multiplications).
    constexpr double inverse_sqrt2 = 0.70710678118654752440;
    constexpr double inverse_sqrt6 = 0.40824829046386301637;
    constexpr double third         = 1.0 / 3.0;
    constexpr double pi       = 3.1415926535897932385;
    constexpr double infinity = std::numeric_limits<double>::infinity();
    // Below this many points a step (~60 ns a point) is cheaper than waking
    // the OpenMP team, which costs tens of microseconds per parallel region.
    constexpr std::int64_t parallel_points = 2048;

    // x = cos 3theta within this of +-1 means two principal values of the
    // deviator nearly coincide (1 - x^2 ~ 3.4 (gap/spread)^2; 1e-5 is a gap
    // below 0.2 % of the spread). There d theta/dx ~ 1/sqrt(1 - x^2) amplifies
    // the round-off eps of det(s) into ~sqrt(eps) errors, so Jacobi takes over.
    // Above it the closed forms lose at most eps / (6 sqrt(2e-5)) ~ 40 eps of
    // the spread. At 1e-3 Jacobi took 3.6 % of the paper case's point-steps
    // and a third of its Dang Van time, at 1e-5 0.2 %. Both forms agree with
    // Eigen's QR solver to 1e-14 |A| (unit_dang_van), where Eigen's own closed
    // form (computeDirect) is off by 1e-8.
    constexpr double lode_degeneracy = 1e-5;

    inline void coordinates(const double *s, double *u)
    {
      u[0] = (2.0 * s[zz] - s[xx] - s[yy]) * inverse_sqrt6;
      u[1] = (s[xx] - s[yy]) * inverse_sqrt2;
      u[2] = sqrt2 * s[yz];
      u[3] = sqrt2 * s[xz];
      u[4] = sqrt2 * s[xy];
    }

    /// The traceless symmetric matrix of coordinates u: diagonal d, off-diagonals
    /// o[k] = the entry not in row/column k (o[0] = yz, o[1] = xz, o[2] = xy).
    inline void deviator_matrix(const double *u, double *d, double *o)
    {
      d[2] = 2.0 * u[0] * inverse_sqrt6;
      d[0] = -u[0] * inverse_sqrt6 + u[1] * inverse_sqrt2;
      d[1] = -u[0] * inverse_sqrt6 - u[1] * inverse_sqrt2;
      o[0] = u[2] * inverse_sqrt2;
      o[1] = u[3] * inverse_sqrt2;
      o[2] = u[4] * inverse_sqrt2;
    }

    /// Eigenvalues of a symmetric 3x3 (diagonal d, off-diagonals o as above) by
    /// cyclic Jacobi rotations (Golub & Van Loan §8.5; quadratic convergence,
    /// 3-5 sweeps), in place in d. Backward stable: error ~ eps |A|.
    void jacobi_eigenvalues(double *d, double *o)
    {
      for (int sweep = 0; sweep < 50; ++sweep)
        {
          const double off = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
          const double all = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * off;
          if (!(off > 1e-36 * all)) // off-diagonal below 1e-18 |A|: below round-off of the diagonal
            return;
          for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q)
              {
                const int r   = 3 - p - q;
                double    apq = o[r];
                if (apq == 0.0)
                  continue;
                const double theta = (d[q] - d[p]) / (2.0 * apq);
                // Smaller root of t^2 + 2 theta t - 1 = 0 (rotation angle <= pi/4);
                // for huge theta, t = 1/(2 theta) avoids overflowing theta^2.
                const double t = std::abs(theta) > 1e150 ? 0.5 / theta
                                                         : std::copysign(1.0, theta) /
                                                             (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                d[p] -= t * apq;
                d[q] += t * apq;
                o[r]           = 0.0;
                const double g = o[q], h = o[p]; // entries (r, p) and (r, q)
                o[q]           = c * g - s * h;
                o[p]           = s * g + c * h;
              }
        }
    }

    /// The traceless tensor with coordinates u scaled to |u| = 1 (J2 = 1/2),
    /// and its Lode invariant x = cos 3theta = 3 sqrt6 det(s).
    struct UnitDeviator
    {
      double norm = 0.0, x = 0.0, d[3] = {}, o[3] = {};
      bool   near_degenerate() const { return 1.0 - std::abs(x) < lode_degeneracy; }
    };

    inline UnitDeviator unit_deviator(const double *u)
    {
      UnitDeviator s;
      s.norm = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + u[3] * u[3] + u[4] * u[4]);
      if (!(s.norm > 0.0))
        return s;
      const double scale = 1.0 / s.norm;
      double       w[dim];
      for (int k = 0; k < dim; ++k)
        w[k] = u[k] * scale;
      deviator_matrix(w, s.d, s.o);
      const double *d = s.d, *o = s.o;
      const double  det =
        d[0] * (d[1] * d[2] - o[0] * o[0]) - o[2] * (o[2] * d[2] - o[0] * o[1]) + o[1] * (o[2] * o[0] - d[1] * o[1]);
      s.x = std::clamp(3.0 * sqrt6 * det, -1.0, 1.0);
      return s;
    }

    /// Principal values (descending) of the traceless tensor with coordinates
    /// u. Closed form: sqrt(2/3) |u| cos(theta - 2 pi k / 3), theta = acos(x)/3.
    inline void deviator_eigenvalues(const double *u, double *lambda)
    {
      UnitDeviator s = unit_deviator(u);
      if (!(s.norm > 0.0))
        {
          lambda[0] = lambda[1] = lambda[2] = 0.0;
          return;
        }
      if (s.near_degenerate())
        {
          jacobi_eigenvalues(s.d, s.o);
          std::sort(s.d, s.d + 3, [](double a, double b) { return a > b; });
          for (int k = 0; k < 3; ++k)
            lambda[k] = s.norm * s.d[k];
          return;
        }
      const double theta = std::acos(s.x) / 3.0, scale = s.norm * std::sqrt(2.0 / 3.0);
      lambda[0] = scale * std::cos(theta);
      lambda[1] = scale * std::cos(theta - 2.0 * pi / 3.0);
      lambda[2] = scale * std::cos(theta + 2.0 * pi / 3.0);
    }

    /// g(x) = sin(acos(x)/3 + pi/3), without trigonometric calls. g is even
    /// in x, so take x' = -|x|: c = cos(acos(x')/3) in [1/2, sqrt3/2] is the
    /// largest root of 4c^3 - 3c = x', i.e. (c + 1)(2c - 1)^2 = 1 - |x|. With
    /// c = 1/2 + delta that is h(delta) = delta sqrt(2 delta + 3) - t = 0,
    /// t = sqrt((1 - |x|)/2) in [0, 1/sqrt2], delta in [0, 0.37]. h' >= sqrt3
    /// everywhere (no double root, unlike the cubic in c at x' = -1), so Newton
    /// converges quadratically from delta_0 = t/sqrt3 - t^2/9 (the series at
    /// t = 0; relative error <= 4 %): after 2 steps the error is 2e-11, after
    /// 3 round-off (2.5e-16 against long double, as the trigonometric form). Then g = (sqrt3/2) c + (1/2) sqrt((1 - c)(1 + c)),
    /// every term well conditioned. A fixed step count keeps it branch-free.
    inline double lode_factor(double x)
    {
      constexpr double sqrt3 = 1.7320508075688772935;
      const double     t     = std::sqrt(0.5 * (1.0 - std::abs(x)));
      double           delta = t * (1.0 / sqrt3) - t * t * (1.0 / 9.0);
      for (int step = 0; step < 3; ++step)
        {
          const double root = std::sqrt(2.0 * delta + 3.0);
          delta -= (delta * (2.0 * delta + 3.0) - t * root) / (3.0 * (delta + 1.0));
        }
      return 0.5 * sqrt3 * (0.5 + delta) + 0.5 * std::sqrt((0.5 - delta) * (1.5 + delta));
    }

    /// (lambda_1 - lambda_3)/2 of the traceless tensor with coordinates u; in
    /// closed form |u| sin(theta + pi/3) / sqrt2.
    inline double deviator_tresca(const double *u)
    {
      UnitDeviator s = unit_deviator(u);
      if (!(s.norm > 0.0))
        return 0.0;
      if (s.near_degenerate())
        {
          jacobi_eigenvalues(s.d, s.o);
          return 0.5 * s.norm * (std::max({s.d[0], s.d[1], s.d[2]}) - std::min({s.d[0], s.d[1], s.d[2]}));
        }
      return s.norm * lode_factor(s.x) * inverse_sqrt2;
    }

    double squared_distance(const double *a, const double *b)
    {
      double sum = 0.0;
      for (int k = 0; k < dim; ++k)
        sum += (a[k] - b[k]) * (a[k] - b[k]);
      return sum;
    }

    /// Index and squared distance of the point farthest from c.
    std::pair<std::size_t, double> farthest(const double *points, std::size_t count, const double *c)
    {
      std::size_t best = 0;
      double      d2   = -1.0;
      for (std::size_t k = 0; k < count; ++k)
        {
          const double e = squared_distance(points + dim * k, c);
          if (e > d2)
            {
              d2   = e;
              best = k;
            }
        }
      return {best, d2};
    }

    // A ball through an affinely independent set U is the MEB of a set S ⊇ U
    // exactly when its centre lies in conv(U) (barycentric weights >= 0) and it
    // holds S (the KKT conditions of the dual QP of docs/references.md §5.2).
    // Relative slack on squared distances for "holds": round-off of |p - c|^2
    // is ~1e-15 relative for the well-conditioned supports accepted below.
    constexpr double hold_slack     = 1e-12;
    constexpr double weight_slack   = 1e-10; // barycentric weights are O(1)
    constexpr double pivot_fraction = 1e-12; // Cholesky pivot / diagonal below this: dependent

    struct SupportBall
    {
      int    members[dim + 1]; // point indices, the forced point first
      int    size = 0;
      double centre[dim];
      double r2 = -1.0;
    };

    /// MEB of T ∪ {f} when f lies outside MEB(T) (so f is on its boundary,
    /// Welzl 1991 Lemma 1): try the affinely independent subsets of T with f
    /// until one satisfies the KKT conditions; that ball is unique, so the
    /// first found is the answer. Largest subsets first: usually at most one
    /// point of T leaves the support. |T| <= 6 (supports in R^5 are affinely
    /// independent), so at most 63 subsets.
    SupportBall ball_with_forced_point(const double *points, const SupportBall &current, int f)
    {
      const int     t    = current.size;
      const double *base = points + dim * f;
      double        v[dim + 1][dim];
      double        gram[dim + 1][dim + 1];
      for (int j = 0; j < t; ++j)
        for (int k = 0; k < dim; ++k)
          v[j][k] = points[dim * current.members[j] + k] - base[k];
      for (int i = 0; i < t; ++i)
        for (int j = 0; j <= i; ++j)
          {
            double sum = 0.0;
            for (int k = 0; k < dim; ++k)
              sum += v[i][k] * v[j][k];
            gram[i][j] = gram[j][i] = sum;
          }

      SupportBall fallback;
      double      best_excess = infinity;
      unsigned order[1u << (dim + 1)];
      int      subsets = 0;
      for (int size = std::min(t, dim); size >= 0; --size) // with f, at most 6 points in R^5
        for (unsigned mask = 0; mask < (1u << t); ++mask)
          {
            int members = 0;
            for (int j = 0; j < t; ++j)
              members += (mask >> j) & 1u;
            if (members == size)
              order[subsets++] = mask;
          }
      for (int o = 0; o < subsets; ++o)
        {
          const unsigned mask = order[o];
          int            chosen[dim + 1], k = 0;
          for (int j = 0; j < t; ++j)
            if (mask & (1u << j))
              chosen[k++] = j;
          // Centre c = f + sum mu_j v_j equidistant from f and the chosen points:
          // 2 v_i . (sum_j mu_j v_j) = |v_i|^2, a Gram system, by Cholesky.
          double l[dim][dim] = {}, mu[dim];
          bool   independent = true;
          for (int i = 0; i < k && independent; ++i)
            {
              for (int j = 0; j <= i; ++j)
                {
                  double sum = gram[chosen[i]][chosen[j]];
                  for (int m = 0; m < j; ++m)
                    sum -= l[i][m] * l[j][m];
                  if (i == j)
                    {
                      if (!(sum > pivot_fraction * gram[chosen[i]][chosen[i]]))
                        independent = false;
                      else
                        l[i][i] = std::sqrt(sum);
                    }
                  else
                    l[i][j] = sum / l[j][j];
                }
            }
          if (!independent)
            continue;
          for (int i = 0; i < k; ++i)
            {
              double sum = 0.5 * gram[chosen[i]][chosen[i]];
              for (int m = 0; m < i; ++m)
                sum -= l[i][m] * mu[m];
              mu[i] = sum / l[i][i];
            }
          for (int i = k - 1; i >= 0; --i)
            {
              double sum = mu[i];
              for (int m = i + 1; m < k; ++m)
                sum -= l[m][i] * mu[m];
              mu[i] = sum / l[i][i];
            }
          SupportBall ball;
          double      weight_f = 1.0;
          bool        inside_hull = true;
          for (int kk = 0; kk < dim; ++kk)
            ball.centre[kk] = base[kk];
          for (int i = 0; i < k; ++i)
            {
              weight_f -= mu[i];
              inside_hull = inside_hull && mu[i] >= -weight_slack;
              for (int kk = 0; kk < dim; ++kk)
                ball.centre[kk] += mu[i] * v[chosen[i]][kk];
            }
          inside_hull = inside_hull && weight_f >= -weight_slack;
          ball.r2     = squared_distance(ball.centre, base);
          double excess = 0.0; // worst relative excess over the ball of T ∪ {f}
          for (int j = 0; j < t; ++j)
            excess = std::max(excess, squared_distance(points + dim * current.members[j], ball.centre) - ball.r2);
          excess /= std::max(ball.r2, std::numeric_limits<double>::min());
          ball.members[0] = f;
          ball.size       = k + 1;
          for (int i = 0; i < k; ++i)
            ball.members[i + 1] = current.members[chosen[i]];
          if (inside_hull && excess <= hold_slack)
            return ball;
          // In case round-off rejects every candidate: the one closest to
          // holding the set.
          if (excess < best_excess || (excess == best_excess && ball.r2 < fallback.r2))
            {
              best_excess = excess;
              fallback    = ball;
            }
        }
      return fallback;
    }
  } // namespace

  namespace detail
  {
    std::array<double, deviator_dimension> deviator_coordinates(const StressTensor &stress)
    {
      const double s[6] = {stress.xx, stress.yy, stress.zz, stress.yz, stress.xz, stress.xy};
      std::array<double, deviator_dimension> u;
      coordinates(s, u.data());
      return u;
    }

    StressTensor deviator_from_coordinates(const std::array<double, deviator_dimension> &u)
    {
      double d[3], o[3];
      deviator_matrix(u.data(), d, o);
      StressTensor s;
      s.xx = d[0];
      s.yy = d[1];
      s.zz = d[2];
      s.yz = o[0];
      s.xz = o[1];
      s.xy = o[2];
      return s;
    }

    double tresca_shear_of_deviator(const double *u) { return deviator_tresca(u); }

    double lode_tresca_factor(double x) { return lode_factor(x); }

    // Iterative support update (the pivoting idea of Gärtner's miniball, with
    // an exhaustive small solve): keep the support T of the current ball, add
    // the farthest outside point f and replace T by the support of MEB(T ∪ {f}).
    // The radius grows strictly each time, so this ends, normally after a few
    // to a few tens of passes over the points. The result is the exact MEB of
    // its support set (a Cholesky solve, round-off only), holding every point
    // within a relative 1e-12 on squared distances. The stability bound
    // |c - c*|^2 <= R^2 - r*^2 then guarantees |c - c*| <= 1e-6 r* in the
    // worst case; against an independent brute force (unit_dang_van) the
    // centres agree to 2e-15 r.
    double minimum_enclosing_ball(const double *points, std::size_t count, double *centre)
    {
      if (count == 0)
        throw std::invalid_argument("minimum enclosing ball of an empty point set");
      const std::size_t first = farthest(points, count, points).first;
      SupportBall ball;
      ball.members[0] = static_cast<int>(first);
      ball.size       = 1;
      ball.r2         = 0.0;
      std::copy(points + dim * first, points + dim * first + dim, ball.centre);
      const double extent2 = farthest(points, count, ball.centre).second;
      // Points closer than this (relative to the path's size) are one point.
      const double floor2 = 1e-28 * extent2;
      for (int pass = 0; pass < 1000; ++pass)
        {
          const auto [f, d2] = farthest(points, count, ball.centre);
          if (d2 <= ball.r2 * (1.0 + hold_slack) + floor2)
            break;
          const SupportBall next = ball_with_forced_point(points, ball, static_cast<int>(f));
          if (!(next.r2 > ball.r2)) // round-off floor reached: no progress possible
            break;
          ball = next;
        }
      std::copy(ball.centre, ball.centre + dim, centre);
      return std::sqrt(farthest(points, count, centre).second);
    }

    std::array<double, 3> principal_stresses_reference(const StressTensor &stress)
    {
      Eigen::Matrix3d a;
      a << stress.xx, stress.xy, stress.xz, stress.xy, stress.yy, stress.yz, stress.xz, stress.yz, stress.zz;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(a, Eigen::EigenvaluesOnly);
      const Eigen::Vector3d                                 values = solver.eigenvalues(); // ascending
      return {values[2], values[1], values[0]};
    }
  } // namespace detail

  std::array<double, 3> principal_stresses(const StressTensor &stress)
  {
    const double s[6] = {stress.xx, stress.yy, stress.zz, stress.yz, stress.xz, stress.xy};
    double       u[dim], lambda[3];
    coordinates(s, u);
    deviator_eigenvalues(u, lambda);
    const double mean = (stress.xx + stress.yy + stress.zz) / 3.0;
    return {mean + lambda[0], mean + lambda[1], mean + lambda[2]};
  }

  double tresca_shear(const StressTensor &stress)
  {
    const double s[6] = {stress.xx, stress.yy, stress.zz, stress.yz, stress.xz, stress.xy};
    double       u[dim];
    coordinates(s, u);
    return deviator_tresca(u);
  }

  DangVanConstants DangVanConstants::from_fatigue_limits(double bending_limit, double torsion_limit)
  {
    std::ostringstream message;
    if (!(std::isfinite(bending_limit) && bending_limit > 0.0 && std::isfinite(torsion_limit) &&
          torsion_limit > 0.0))
      message << "Dang Van: the fatigue limits must be positive and finite [Pa]; got f_-1 = " << bending_limit
              << ", t_-1 = " << torsion_limit;
    else if (torsion_limit < 0.5 * bending_limit)
      message << "Dang Van: t_-1/f_-1 = " << torsion_limit / bending_limit << " (t_-1 = " << torsion_limit
              << " Pa, f_-1 = " << bending_limit
              << " Pa) is below 1/2, which gives alpha = 3 (t/f - 1/2) < 0: hydrostatic tension would"
                 " raise the allowable shear. Check the limits (fully reversed bending/tension f_-1,"
                 " torsion t_-1).";
    else if (torsion_limit > bending_limit)
      message << "Dang Van: the torsion fatigue limit t_-1 = " << torsion_limit
              << " Pa exceeds the bending limit f_-1 = " << bending_limit
              << " Pa; no metal does (t/f is 0.5-0.8, about 1 for cast irons). Are the two swapped?";
    if (!message.str().empty())
      throw std::invalid_argument(message.str());
    return {3.0 * (torsion_limit / bending_limit - 0.5), torsion_limit};
  }

  ResidualStressCentre parse_residual_stress_centre(const std::string &name)
  {
    if (name == "running_mean")
      return ResidualStressCentre::running_mean;
    if (name == "last_cycle_mean")
      return ResidualStressCentre::last_cycle_mean;
    if (name == "hypersphere")
      return ResidualStressCentre::hypersphere;
    throw std::invalid_argument("Dang Van: unknown residual-stress centre '" + name +
                                "'; use running_mean, last_cycle_mean or hypersphere");
  }

  std::string to_string(ResidualStressCentre centre)
  {
    switch (centre)
      {
        case ResidualStressCentre::running_mean:
          return "running_mean";
        case ResidualStressCentre::last_cycle_mean:
          return "last_cycle_mean";
        case ResidualStressCentre::hypersphere:
          return "hypersphere";
      }
    return "unknown";
  }

  std::size_t largest_finite_point(const std::vector<double> &values)
  {
    std::size_t largest = values.size();
    for (std::size_t point = 0; point < values.size(); ++point)
      if (std::isfinite(values[point]) && (largest == values.size() || values[point] > values[largest]))
        largest = point;
    return largest;
  }

  DangVanField::DangVanField(std::size_t n_points, const DangVanConstants &constants,
                             const DangVanSettings &settings)
    : n(n_points)
    , material(constants)
    , options(settings)
  {
    std::ostringstream message;
    if (n == 0)
      message << "Dang Van: no points";
    else if (!(std::isfinite(constants.beta) && constants.beta > 0.0))
      message << "Dang Van: beta must be positive and finite [Pa]; got " << constants.beta;
    else if (!(std::isfinite(constants.alpha) && constants.alpha >= 0.0))
      message << "Dang Van: alpha must be >= 0 and finite; got " << constants.alpha
              << " (alpha < 0 means t_-1/f_-1 < 1/2, see DangVanConstants::from_fatigue_limits)";
    else if (settings.steps_per_cycle < 0)
      message << "Dang Van: steps per cycle must be >= 0 (0: the caller ends cycles); got "
              << settings.steps_per_cycle;
    else if (settings.warmup_cycles < 0)
      message << "Dang Van: warm-up cycles must be >= 0; got " << settings.warmup_cycles;
    if (!message.str().empty())
      throw std::invalid_argument(message.str());
    reset();
  }

  void DangVanField::reset()
  {
    steps = 0;
    cycles = cycle_steps = 0;
    infinite_now         = 0;
    mean.assign(dim * n, 0.0);
    if (options.centre != ResidualStressCentre::running_mean)
      centre.assign(dim * n, 0.0);
    if (options.centre == ResidualStressCentre::hypersphere)
      // Reserved up front when the cycle length is known, so that no step allocates.
      path.assign(static_cast<std::size_t>(options.steps_per_cycle) * n * dim, 0.0);
    risk_now.assign(n, 0.0);
    reset_maximum();
  }

  void DangVanField::reset_maximum()
  {
    risk_peak.assign(n, 0.0);
    risk_peak_step.assign(n, -1);
  }

  bool DangVanField::maximum_active() const
  {
    const int needed = options.centre == ResidualStressCentre::running_mean ? options.warmup_cycles
                                                                            : std::max(1, options.warmup_cycles);
    return cycles >= needed;
  }

  std::size_t DangVanField::infinite_risk_max_count() const
  {
    return static_cast<std::size_t>(std::count(risk_peak.begin(), risk_peak.end(), infinity));
  }

  std::size_t DangVanField::memory_bytes() const
  {
    return sizeof(double) * (mean.capacity() + centre.capacity() + path.capacity() + risk_now.capacity() +
                             risk_peak.capacity()) +
           sizeof(std::int64_t) * risk_peak_step.capacity();
  }

  void DangVanField::check_finite(const double *values, std::size_t count) const
  {
    std::size_t bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static) if (count > 6 * parallel_points)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(count); ++k)
      bad += !std::isfinite(values[k]);
    if (bad > 0)
      {
        std::ostringstream message;
        message << "Dang Van: " << bad << " stress values at step " << steps << " are not finite";
        throw std::invalid_argument(message.str());
      }
  }

  void DangVanField::add_step(const StressField &stress)
  {
    const std::size_t plane = static_cast<std::size_t>(stress.ny) * stress.nx;
    if (stress.n_layers < 0 || stress.ny < 0 || stress.nx < 0 || plane * stress.n_layers != n ||
        stress.values.size() != stress_component_count * n)
      {
        std::ostringstream message;
        message << "Dang Van: the stress field has " << stress.n_layers << " x " << stress.ny << " x " << stress.nx
                << " points (" << stress.values.size() << " values); the criterion was set up for " << n
                << " points";
        throw std::invalid_argument(message.str());
      }
    check_finite(stress.values.data(), stress.values.size());
    advance(stress.values.data(), plane, 1, stress_component_count * plane, plane, static_cast<std::size_t>(stress.n_layers));
  }

  void DangVanField::add_step(const double *voigt, std::size_t point_count)
  {
    if (point_count != n || voigt == nullptr)
      {
        std::ostringstream message;
        message << "Dang Van: got " << point_count << " stress tensors; the criterion was set up for " << n
                << " points";
        throw std::invalid_argument(message.str());
      }
    check_finite(voigt, stress_component_count * n);
    advance(voigt, 1, stress_component_count, 0, n, 1);
  }

  void DangVanField::add_step(std::size_t plane, const BlockSource &source)
  {
    if (plane == 0 || n % plane != 0)
      {
        std::ostringstream message;
        message << "Dang Van: layers of " << plane << " points do not make up the " << n << " points";
        throw std::invalid_argument(message.str());
      }
    const std::size_t bad = advance(nullptr, 0, 0, 0, plane, n / plane, &source);
    if (bad > 0)
      {
        std::ostringstream message;
        message << "Dang Van: " << bad << " stress values at step " << steps - 1 << " are not finite";
        throw std::invalid_argument(message.str());
      }
  }

  namespace
  {
    /// What a step of the criterion needs besides the stresses: the state
    /// arrays ([5][points] for the mean and centre) and the step's constants.
    struct StepContext
    {
      double       *mean = nullptr;
      const double *centre = nullptr; ///< after the mean's update: the mean itself or the last cycle's
      double       *path_row = nullptr;
      bool          update_mean = false, count_maximum = false;
      double        inverse = 0.0, alpha = 0.0, beta = 0.0;
      std::int64_t  step = 0;
      std::size_t   points = 0;
      double       *now = nullptr; ///< D(t) written here, and the infinite ones counted, if set
      double       *peak = nullptr;
      std::int64_t *peak_step = nullptr;
    };

// The step's vector loops in AVX2 where the processor has it, chosen when
// the program loads: twice the lanes of the baseline's SSE2, and the same
// IEEE operations (AVX2 alone allows no fused multiply-add), so the same
// digits on every processor.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define FRETSIM_WIDE_VECTORS __attribute__((target_clones("avx2", "default")))
#else
#define FRETSIM_WIDE_VECTORS
#endif

    /// One step of `count` points of a block from point p0 on, the six
    /// components in component[c][k]. A branch-free pass over the block
    /// (deviator, mean, Lode invariant, Newton's Tresca) that the compiler
    /// vectorises, then the few near-repeated principal values by Jacobi.
    /// Each point's arithmetic is the same whatever block or step batch it
    /// is in.
    FRETSIM_WIDE_VECTORS
    void block_step(const StepContext &x, const double *const *component, std::size_t count, std::size_t p0,
                    std::size_t &infinite)
    {
      constexpr std::size_t block = DangVanField::block_size;
      alignas(64) double u[dim][block], w[dim][block];
      alignas(64) double norm[block], lode[block], tresca[block], denominator[block];
      const double alpha = x.alpha, beta = x.beta, inverse = x.inverse;
      // The loops below keep to scalars (no local arrays), which the
      // compiler vectorises; the arithmetic is that of coordinates() and
      // unit_deviator(), operation for operation.
      const double *sxx = component[xx], *syy = component[yy], *szz = component[zz];
      const double *syz = component[yz], *sxz = component[xz], *sxy = component[xy];
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k)
        {
          u[0][k]        = (2.0 * szz[k] - sxx[k] - syy[k]) * inverse_sqrt6;
          u[1][k]        = (sxx[k] - syy[k]) * inverse_sqrt2;
          u[2][k]        = sqrt2 * syz[k];
          u[3][k]        = sqrt2 * sxz[k];
          u[4][k]        = sqrt2 * sxy[k];
          denominator[k] = beta - alpha * ((sxx[k] + syy[k] + szz[k]) * third);
        }
      if (x.update_mean)
        for (int d = 0; d < dim; ++d)
          {
            double *md = x.mean + d * x.points + p0;
#pragma omp simd
            for (std::size_t k = 0; k < count; ++k)
              md[k] += (u[d][k] - md[k]) * inverse; // paper eq. 5
          }
      if (x.path_row)
        for (std::size_t k = 0; k < count; ++k)
          for (int d = 0; d < dim; ++d)
            x.path_row[dim * (p0 + k) + d] = u[d][k];
      for (int d = 0; d < dim; ++d)
        {
          const double *cd = x.centre + d * x.points + p0;
#pragma omp simd
          for (std::size_t k = 0; k < count; ++k)
            w[d][k] = u[d][k] - cd[k];
        }
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k)
        {
          // The Lode invariant as unit_deviator computes it.
          const double w0 = w[0][k], w1 = w[1][k], w2 = w[2][k], w3 = w[3][k], w4 = w[4][k];
          const double r     = std::sqrt(w0 * w0 + w1 * w1 + w2 * w2 + w3 * w3 + w4 * w4);
          const double scale = 1.0 / r;
          const double a0 = w0 * scale, a1 = w1 * scale, a2 = w2 * scale, a3 = w3 * scale, a4 = w4 * scale;
          const double d2 = 2.0 * a0 * inverse_sqrt6;
          const double d0 = -a0 * inverse_sqrt6 + a1 * inverse_sqrt2;
          const double d1 = -a0 * inverse_sqrt6 - a1 * inverse_sqrt2;
          const double o0 = a2 * inverse_sqrt2, o1 = a3 * inverse_sqrt2, o2 = a4 * inverse_sqrt2;
          const double det = d0 * (d1 * d2 - o0 * o0) - o2 * (o2 * d2 - o0 * o1) + o1 * (o2 * o0 - d1 * o1);
          double       lx  = 3.0 * sqrt6 * det;
          lx               = lx < -1.0 ? -1.0 : lx; // std::clamp's order
          lx               = 1.0 < lx ? 1.0 : lx;
          norm[k]          = r;
          lode[k]          = lx;
        }
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k)
        tresca[k] = norm[k] * lode_factor(lode[k]) * inverse_sqrt2;
      for (std::size_t k = 0; k < count; ++k)
        if (!(norm[k] > 0.0))
          tresca[k] = 0.0;
        else if (1.0 - std::abs(lode[k]) < lode_degeneracy)
          {
            const double wk[dim] = {w[0][k], w[1][k], w[2][k], w[3][k], w[4][k]};
            tresca[k]            = deviator_tresca(wk);
          }
      double *const       peak      = x.peak;
      std::int64_t *const peak_step = x.peak_step;
      const std::int64_t  step      = x.step;
      const bool          count_maximum = x.count_maximum;
      for (std::size_t k = 0; k < count; ++k)
        {
          const std::size_t p    = p0 + k;
          double            risk = infinity;
          if (denominator[k] > 0.0)
            risk = tresca[k] / denominator[k];
          else if (x.now)
            ++infinite;
          if (x.now)
            x.now[p] = risk;
          // peak_step < 0 means peak = 0 (never set), so that test is only
          // needed when risk > peak fails there: it spares reading
          // peak_step for every point.
          if (count_maximum && (risk > peak[p] || (!(risk > 0.0) && peak_step[p] < 0)))
            {
              peak[p]      = risk;
              peak_step[p] = step;
            }
        }
    }

    /// How many of `count` values are not finite.
    inline std::size_t count_not_finite(const double *values, std::size_t count)
    {
      std::size_t bad = 0;
#pragma omp simd reduction(+ : bad)
      for (std::size_t k = 0; k < count; ++k)
        bad += !(std::abs(values[k]) <= std::numeric_limits<double>::max());
      return bad;
    }
  } // namespace

  std::size_t DangVanField::advance(const double *values, std::size_t component_stride, std::size_t point_stride,
                                    std::size_t layer_stride, std::size_t plane, std::size_t layers,
                                    const BlockSource *source)
  {
    const ResidualStressCentre method      = options.centre;
    const bool                 first_cycle = cycles == 0;
    // running_mean: mean over every step so far. The per-cycle centres: mean
    // over the current cycle (it becomes last_cycle_mean's next centre, and is
    // the provisional centre of both during cycle 1).
    const bool   running     = method == ResidualStressCentre::running_mean;
    const bool   mean_centre = running || first_cycle;
    StepContext  x;
    x.update_mean = method != ResidualStressCentre::hypersphere || first_cycle;
    x.inverse     = 1.0 / static_cast<double>(running ? steps + 1 : cycle_steps + 1);
    if (method == ResidualStressCentre::hypersphere)
      {
        const std::size_t needed = (static_cast<std::size_t>(cycle_steps) + 1) * n * dim;
        if (path.size() < needed) // only before the first cycle end, and only without steps_per_cycle
          path.resize(std::max(needed, std::min(2 * path.size(), path.max_size())));
        x.path_row = path.data() + static_cast<std::size_t>(cycle_steps) * n * dim;
      }
    x.count_maximum = maximum_active();
    x.step          = steps;
    x.alpha         = material.alpha;
    x.beta          = material.beta;
    x.mean          = mean.data();
    x.centre        = mean_centre ? mean.data() : centre.data();
    x.points        = n;
    x.now           = risk_now.data();
    x.peak          = risk_peak.data();
    x.peak_step     = risk_peak_step.data();
    std::size_t infinite = 0, not_finite = 0;

    // Blocks of points within a layer, handed out 8 at a time as threads
    // come free: on a loaded machine a thread that loses its core does not
    // hold the others up.
    constexpr std::size_t block  = block_size;
    const std::size_t     blocks = (plane + block - 1) / block;
    const std::int64_t    tasks  = static_cast<std::int64_t>(blocks * layers);
#pragma omp parallel for reduction(+ : infinite, not_finite) schedule(dynamic, 8) if (n > parallel_points)
    for (std::int64_t task = 0; task < tasks; ++task)
      {
        const std::size_t layer = static_cast<std::size_t>(task) / blocks;
        const std::size_t first = static_cast<std::size_t>(task) % blocks * block;
        const std::size_t count = std::min(block, plane - first);
        const double     *in    = source ? nullptr : values + layer * layer_stride + first * point_stride;
        alignas(64) double load[stress_component_count][block];
        // Component planes read in place; interleaved tensors gathered first.
        const double *component[stress_component_count];
        if (source)
          {
            double *out[stress_component_count];
            for (int comp = 0; comp < stress_component_count; ++comp)
              out[comp] = load[comp];
            (*source)(layer, first, count, out);
            for (int comp = 0; comp < stress_component_count; ++comp)
              {
                not_finite += count_not_finite(load[comp], count);
                component[comp] = load[comp];
              }
          }
        else
          for (int comp = 0; comp < stress_component_count; ++comp)
            if (point_stride == 1)
              component[comp] = in + comp * component_stride;
            else
              {
                for (std::size_t k = 0; k < count; ++k)
                  load[comp][k] = in[comp * component_stride + k * point_stride];
                component[comp] = load[comp];
              }
        block_step(x, component, count, layer * plane + first, infinite);
      }
    infinite_now = infinite;
    ++steps;
    ++cycle_steps;
    if (options.steps_per_cycle > 0 && cycle_steps >= options.steps_per_cycle)
      end_cycle();
    return not_finite;
  }

  void DangVanField::add_steps(std::size_t plane, std::size_t count, const StepBlockSource &source)
  {
    if (plane == 0 || n % plane != 0)
      {
        std::ostringstream message;
        message << "Dang Van: layers of " << plane << " points do not make up the " << n << " points";
        throw std::invalid_argument(message.str());
      }
    const std::int64_t first_step = steps;
    std::size_t        bad        = 0;
    for (std::size_t done = 0; done < count;)
      {
        // A segment ends where a cycle does: the centre and the counting of
        // D_max may change there.
        std::size_t segment = count - done;
        if (options.steps_per_cycle > 0)
          segment = std::min(segment, static_cast<std::size_t>(options.steps_per_cycle - cycle_steps));
        bad += advance_segment(plane, n / plane, source, done, segment, done + segment == count);
        done += segment;
      }
    if (bad > 0)
      {
        std::ostringstream message;
        message << "Dang Van: " << bad << " stress values in steps " << first_step << " to " << steps - 1
                << " are not finite";
        throw std::invalid_argument(message.str());
      }
  }

  std::size_t DangVanField::advance_segment(std::size_t plane, std::size_t layers, const StepBlockSource &source,
                                            std::size_t first_step, std::size_t count, bool last)
  {
    const ResidualStressCentre method      = options.centre;
    const bool                 first_cycle = cycles == 0;
    const bool                 running     = method == ResidualStressCentre::running_mean;
    const bool                 mean_centre = running || first_cycle;
    if (method == ResidualStressCentre::hypersphere)
      {
        const std::size_t needed = (static_cast<std::size_t>(cycle_steps) + count) * n * dim;
        if (path.size() < needed) // only before the first cycle end, and only without steps_per_cycle
          path.resize(std::max(needed, std::min(2 * path.size(), path.max_size())));
      }
    // The constants of each step, as advance() sets them.
    std::vector<StepContext> contexts(count);
    for (std::size_t s = 0; s < count; ++s)
      {
        StepContext &x  = contexts[s];
        x.update_mean   = method != ResidualStressCentre::hypersphere || first_cycle;
        x.inverse       = 1.0 / static_cast<double>(running ? steps + s + 1 : cycle_steps + s + 1);
        x.path_row      = method == ResidualStressCentre::hypersphere ?
                            path.data() + (static_cast<std::size_t>(cycle_steps) + s) * n * dim :
                            nullptr;
        x.count_maximum = maximum_active();
        x.step          = steps + static_cast<std::int64_t>(s);
        x.alpha         = material.alpha;
        x.beta          = material.beta;
        x.mean          = mean.data();
        x.centre        = mean_centre ? mean.data() : centre.data();
        x.points        = n;
        x.now           = last && s + 1 == count ? risk_now.data() : nullptr;
        x.peak          = risk_peak.data();
        x.peak_step     = risk_peak_step.data();
      }
    std::size_t infinite = 0, not_finite = 0;

    constexpr std::size_t block  = block_size;
    const std::size_t     blocks = (plane + block - 1) / block;
    const std::int64_t    tasks  = static_cast<std::int64_t>(blocks * layers);
#pragma omp parallel for reduction(+ : infinite, not_finite) schedule(dynamic, 1) if (n > parallel_points)
    for (std::int64_t task = 0; task < tasks; ++task)
      {
        const std::size_t layer = static_cast<std::size_t>(task) / blocks;
        const std::size_t first = static_cast<std::size_t>(task) % blocks * block;
        const std::size_t size  = std::min(block, plane - first);
        alignas(64) double load[stress_component_count][block];
        double            *out[stress_component_count];
        for (int comp = 0; comp < stress_component_count; ++comp)
          out[comp] = load[comp];
        for (std::size_t s = 0; s < count; ++s)
          {
            source(first_step + s, layer, first, size, out);
            for (int comp = 0; comp < stress_component_count; ++comp)
              not_finite += count_not_finite(load[comp], size);
            block_step(contexts[s], out, size, layer * plane + first, infinite);
          }
      }
    if (last)
      infinite_now = infinite;
    steps += static_cast<std::int64_t>(count);
    cycle_steps += static_cast<int>(count);
    if (options.steps_per_cycle > 0 && cycle_steps >= options.steps_per_cycle)
      end_cycle();
    return not_finite;
  }

  void DangVanField::end_cycle()
  {
    if (cycle_steps == 0)
      throw std::logic_error("Dang Van: end_cycle() without a step since the last cycle ended");
    if (options.centre == ResidualStressCentre::last_cycle_mean)
      {
        mean.swap(centre);
        std::fill(mean.begin(), mean.end(), 0.0);
      }
    else if (options.centre == ResidualStressCentre::hypersphere)
      {
        const std::size_t  length = static_cast<std::size_t>(cycle_steps);
        const std::size_t  points = n;
        const double      *stored = path.data();
        double            *c      = centre.data();
#pragma omp parallel if (points * length > parallel_points)
        {
          std::vector<double> own(length * dim);
#pragma omp for schedule(dynamic, 64)
          for (std::int64_t ip = 0; ip < static_cast<std::int64_t>(points); ++ip)
            {
              const std::size_t p = static_cast<std::size_t>(ip);
              for (std::size_t k = 0; k < length; ++k)
                std::copy(stored + (k * points + p) * dim, stored + (k * points + p + 1) * dim,
                          own.data() + k * dim);
              double ball_centre[dim];
              detail::minimum_enclosing_ball(own.data(), length, ball_centre);
              for (int k = 0; k < dim; ++k)
                c[k * points + p] = ball_centre[k];
            }
        }
      }
    ++cycles;
    cycle_steps = 0;
  }
} // namespace fretsim::contact
