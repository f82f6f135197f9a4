#pragma once

/// For the integration drivers (integrate.cc, shape_integrate.cc), not for users: the
/// step-size controller's constants and the location of an event (a sign change of a
/// scalar function of the state) within an accepted step.

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>

namespace deploysim::integrators::driver {

// Step-size controller constants (Hairer, Norsett, Wanner I, sec. II.4).
inline constexpr double kSafety = 0.9;
inline constexpr double kMinShrink = 0.2;
inline constexpr double kMaxGrow = 5.0;
// Fraction of the step to which an event is located.
inline constexpr double kEventRelTolerance = 1e-13;
// Half-width, as a fraction of the step, of the bracket around the root on the
// continuous extension in which an event is finished on exact partial steps (the
// interpolants are accurate to far better than this, dense_output.h).
inline constexpr double kEventDenseBracket = 1e-6;
inline constexpr std::uintmax_t kMaxEventIterations = 100;
// Two times closer than this fraction of the segment length are the same time.
inline constexpr double kTimeEps = 1e-14;

// The factor on the step size after a step whose weighted error norm is err, for a
// method of (error-estimate) order q: after a rejected step (err > 1 or not finite) a
// shrink factor, after an accepted one a growth factor (Hairer, Norsett, Wanner I, II.4).
inline double RejectedStepFactor(double err, int q) {
  return std::isfinite(err) ? std::max(kMinShrink, kSafety * std::pow(err, -1.0 / (q + 1)))
                            : kMinShrink;
}
inline double AcceptedStepFactor(double err, int q) {
  return err == 0.0
             ? kMaxGrow
             : std::min(kMaxGrow, std::max(kMinShrink, kSafety * std::pow(err, -1.0 / (q + 1))));
}

// The steps across one segment [a, b] between breakpoints. Adaptive methods: the
// proposed step, cut so that a step that would end within eps of b ends on b exactly.
// Fixed-step methods: the largest step <= the requested one that divides the segment;
// step k of n ends at a + k (b - a) / n, computed afresh so that times do not drift.
class SegmentSteps {
 public:
  SegmentSteps(double a, double b, bool adaptive, double fixed_step)
      : a_(a),
        b_(b),
        eps_(kTimeEps * std::max(b - a, std::abs(b))),
        adaptive_(adaptive),
        n_fixed_(adaptive ? 0.0 : std::max(1.0, std::ceil((b - a) / fixed_step * (1.0 - 1e-12)))) {}

  // Times within eps of b count as b.
  double eps() const { return eps_; }
  bool Done(double t) const { return !(t < b_ - eps_); }

  // The next step from t (adaptive: at most h_proposed); *last is set if it ends on b.
  double Next(double t, double h_proposed, bool* last) {
    if (adaptive_) {
      *last = t + h_proposed >= b_ - eps_;
      return *last ? b_ - t : h_proposed;
    }
    k_fixed_ += 1.0;
    *last = k_fixed_ >= n_fixed_;
    return (*last ? b_ : a_ + (b_ - a_) * (k_fixed_ / n_fixed_)) - t;
  }

 private:
  double a_, b_, eps_;
  bool adaptive_;
  double n_fixed_;
  double k_fixed_ = 0.0;
};

// Whether g may cross zero and return inside a step [t0, t0 + h] whose ends have the
// same sign (a grazing crossing: a hinge that just reaches its latch and swings back):
// g heads towards zero at the start (rate r0) and away from it at the end (r1), and the
// cubic through the values and rates at the ends comes more than half-way to zero.
// Such a step is then searched on the continuous extension (Driver::Grazing).
inline bool GrazingCandidate(double g0, double r0, double g1, double r1, double h) {
  if (g0 == 0.0 || g1 == 0.0 || (g0 < 0.0) != (g1 < 0.0)) return false;
  const double sigma = g0 > 0.0 ? 1.0 : -1.0;
  if (!(sigma * r0 < 0.0 && sigma * r1 > 0.0)) return false;
  // p(x) = g0 + m0 x + c2 x^2 + c3 x^3 on x in [0, 1]; p' = m0 + 2 c2 x + 3 c3 x^2.
  const double m0 = h * r0, m1 = h * r1;
  const double c2 = 3.0 * (g1 - g0) - 2.0 * m0 - m1;
  const double c3 = 2.0 * (g0 - g1) + m0 + m1;
  auto p = [&](double x) { return g0 + x * (m0 + x * (c2 + x * c3)); };
  double low = std::min(sigma * g0, sigma * g1);
  const double qa = 3.0 * c3, qb = 2.0 * c2, qc = m0;
  auto consider = [&](double x) {
    if (x > 0.0 && x < 1.0) low = std::min(low, sigma * p(x));
  };
  if (qa == 0.0) {
    if (qb != 0.0) consider(-qc / qb);
  } else {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      const double root = std::sqrt(disc);
      consider((-qb + root) / (2.0 * qa));
      consider((-qb - root) / (2.0 * qa));
    }
  }
  return low <= 0.5 * std::min(sigma * g0, sigma * g1);
}

// The time of the sign change of g over the bracket [t0, t1] inside an accepted step
// (g0, g1 of opposite signs, g1 != 0; gd0, gd1: the continuous extension's values at
// the bracket's ends, which differ from g0, g1 only at a grazing crossing's extremum):
// bracketed on the continuous extension (no right-hand sides), then, unless the
// stepper's dense output is exact, finished on exact partial steps inside a narrow
// bracket around that root (so the located time has the accuracy of the steps, not of
// the interpolant); if the narrow bracket holds no sign change, or the extension does
// not change sign over the bracket, on the whole bracket.
// g_dense(t) and g_exact(t): g of the continuous extension and of a partial step at t.
template <class GDense, class GExact>
double LocateEvent(double t0,
                   double t1,
                   double g0,
                   double g1,
                   double gd0,
                   double gd1,
                   GDense&& g_dense,
                   GExact&& g_exact,
                   bool dense_is_exact,
                   double step) {
  const double tol_t = kEventRelTolerance * step;
  auto term = [tol_t](double lo, double hi) { return hi - lo <= tol_t; };
  auto solve = [&](auto&& g, double a, double b, double ga, double gb) {
    if (ga == 0.0) return a;
    if (gb == 0.0) return b;
    std::uintmax_t iters = kMaxEventIterations;
    const auto bracket = boost::math::tools::toms748_solve(g, a, b, ga, gb, term, iters);
    return 0.5 * (bracket.first + bracket.second);
  };
  if ((gd0 < 0.0) == (gd1 < 0.0)) return solve(g_exact, t0, t1, g0, g1);
  const double t_dense = solve(g_dense, t0, t1, gd0, gd1);
  if (dense_is_exact) return t_dense;
  const double delta = kEventDenseBracket * step;
  const double a = std::max(t0, t_dense - delta);
  const double b = std::min(t1, t_dense + delta);
  const double ga = a == t0 ? g0 : g_exact(a);
  const double gb = b == t1 ? g1 : g_exact(b);
  if (ga == 0.0) return a;
  if (gb == 0.0) return b;
  if ((ga < 0.0) != (gb < 0.0)) return solve(g_exact, a, b, ga, gb);
  return solve(g_exact, t0, t1, g0, g1);
}

}  // namespace deploysim::integrators::driver
