#pragma once

/// One stepper interface for every method (STYLE.md: one interface, many tableaus).
/// A stepper advances a State by one step on one smooth segment of the inertia source;
/// the driver in integrate.h handles step-size control, breakpoints, output sampling
/// and event location for all of them alike.

#include <limits>
#include <string>

#include "deploysim/integrators/problem.h"

namespace deploysim::integrators {

/// Tolerances of the adaptive methods. The local error of a step is measured in the
/// max norm with weights 1 / (atol + rtol |y_i|), where y is the momentum divided by
/// |H_B(0)| (so atol is relative to the momentum magnitude) and the quaternion.
struct Tolerances {
  double rtol = 1e-10;
  double atol = 1e-12;
};

/// Result of one step attempt.
struct StepAttempt {
  State result;
  /// Weighted local error estimate (accept when <= 1); 0 for fixed-step methods.
  double error_norm = 0.0;
};

struct StepperInfo {
  std::string name;        ///< Key used in profiles and on the CLI, e.g. "rkmk-rkf78".
  std::string summary;     ///< One line: what the method is.
  std::string reference;   ///< Citation of the tableau or method.
  int order = 0;           ///< Order of the propagated solution.
  int error_order = 0;     ///< Order of the embedded solution (0: no error estimate).
  bool adaptive = false;   ///< Has an embedded error estimate and is run with step control.
  bool lie_group = false;  ///< Advances q_NB on SO(3); H_B = R_NB^T h_N exactly.
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual const StepperInfo& info() const = 0;

  /// Advances y by h > 0. Requires y.t + h <= problem.segment_end() (up to rounding).
  /// Deterministic: the same inputs give the same output bits, which is what makes a
  /// partial step from a step's start a valid dense output of the same order.
  virtual StepAttempt Step(const Problem& problem,
                           const State& y,
                           double h,
                           const Tolerances& tol) const = 0;

  /// Largest step this method may take from y on the current segment
  /// (the exact flow limits itself to a fraction of the period so that events are seen).
  virtual double MaxStep(const Problem& /*problem*/, const State& /*y*/) const {
    return std::numeric_limits<double>::infinity();
  }
};

}  // namespace deploysim::integrators
