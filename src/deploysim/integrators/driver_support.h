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

// The time of the sign change of g over the step [t0, t1] (g0, g1 of opposite signs,
// g1 != 0): bracketed on the continuous extension (no right-hand sides), then, unless
// the stepper's dense output is exact, finished on exact partial steps inside a narrow
// bracket around that root (so the located time has the accuracy of the steps, not of
// the interpolant); if the narrow bracket holds no sign change, on the whole step.
// g_dense(t) and g_exact(t): g of the continuous extension and of a partial step at t.
template <class GDense, class GExact>
double LocateEvent(double t0,
                   double t1,
                   double g0,
                   double g1,
                   GDense&& g_dense,
                   GExact&& g_exact,
                   bool dense_is_exact) {
  const double tol_t = kEventRelTolerance * (t1 - t0);
  auto term = [tol_t](double lo, double hi) { return hi - lo <= tol_t; };
  auto solve = [&](auto&& g, double a, double b, double ga, double gb) {
    std::uintmax_t iters = kMaxEventIterations;
    const auto bracket = boost::math::tools::toms748_solve(g, a, b, ga, gb, term, iters);
    return 0.5 * (bracket.first + bracket.second);
  };
  const double t_dense = solve(g_dense, t0, t1, g0, g1);
  if (dense_is_exact) return t_dense;
  const double delta = kEventDenseBracket * (t1 - t0);
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
