#pragma once

/// One stepper interface for every method (STYLE.md: one interface, many tableaus).
/// A stepper advances a State by one step on one smooth segment of the inertia source;
/// the driver in integrate.h handles step-size control, breakpoints, output sampling
/// and event location for all of them alike.

#include <cstddef>
#include <limits>
#include <memory>
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
  std::string name;       ///< Key used in profiles and on the CLI, e.g. "rkmk-rkf78".
  std::string summary;    ///< One line: what the method is.
  std::string reference;  ///< Citation of the tableau or method.
  int order = 0;          ///< Order of the propagated solution.
  int error_order = 0;    ///< Order of the embedded solution (0: no error estimate).
  bool adaptive = false;  ///< Has an embedded error estimate and is run with step control.
  /// Advances q_NB on SO(3) and derives H_B from it (H_B = dR^T H_B(t0), with dR the
  /// attitude relative to the start, rkmk.h): h_N and |H_B| conserved to rounding.
  bool lie_group = false;
};

/// Per-run scratch space of a stepper: its caches, its rounding carries and the data of
/// the last accepted step for the continuous extension (dense output). Created by
/// Stepper::NewWorkspace, owned by the driver for one run (one Problem), never shared
/// between threads. The stepper itself is a const, stateless object: one stepper may
/// serve any number of runs at once, each with its own workspace.
///
/// Keying rule: a carry or cache entry belongs to the exact bits (t, H_B, q_NB) of the
/// state it was produced with. Step uses it only when its input is bit-equal to that
/// state (the result of an earlier step on this workspace); any other input is advanced
/// from scratch, with zero carries, as the flow of exactly that state.
class StepperWorkspace {
 public:
  virtual ~StepperWorkspace() = default;
  /// The last accepted step (Stepper::Accept): begin and end states.
  State step_begin;
  State step_end;
  long dense_steps = 0;  ///< Partial steps taken by the continuous extensions.
};

/// True when a and b are the same state bit for bit (t, H_B, q_NB).
bool SameBits(const State& a, const State& b);

class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual const StepperInfo& info() const = 0;

  /// A fresh workspace for one run (the driver owns it).
  virtual std::unique_ptr<StepperWorkspace> NewWorkspace() const = 0;

  /// Advances y by h > 0: the result is the method's approximation of the flow of
  /// exactly y (see the keying rule of StepperWorkspace). Requires
  /// y.t + h <= problem.segment_end() (up to rounding). Deterministic: the same inputs
  /// (and workspace history) give the same output bits. `ws` must come from this
  /// stepper's NewWorkspace.
  virtual StepAttempt Step(const Problem& problem,
                           const State& y,
                           double h,
                           const Tolerances& tol,
                           StepperWorkspace& ws) const = 0;

  /// The driver accepts the result of the last Step call on `ws`, which started at y0,
  /// as y1 (its time possibly snapped onto the segment end). Commits the carries of y1
  /// and makes [y0.t, y1.t] the interval of the continuous extension.
  virtual void Accept(const Problem& problem,
                      const State& y0,
                      const State& y1,
                      StepperWorkspace& ws) const = 0;

  /// The continuous extension of the last accepted step at t in [y0.t, y1.t]: the
  /// method's dense output (see each stepper's header for the interpolant and its error).
  virtual State Dense(const Problem& problem,
                      double t,
                      const Tolerances& tol,
                      StepperWorkspace& ws) const = 0;

  /// The continuous extension for an output sample at t in [y0.t, y1.t] of the last
  /// accepted step; `samples` is the number of output samples the driver takes in this
  /// step (a hint). A stepper may answer from an approximation of Dense accurate to
  /// rounding where that is cheaper (`exact`: a Chebyshev interpolant of the closed
  /// form); event location and event states always use Dense. Default: Dense.
  virtual State DenseSample(const Problem& problem,
                            double t,
                            std::size_t /*samples*/,
                            const Tolerances& tol,
                            StepperWorkspace& ws) const {
    return Dense(problem, t, tol, ws);
  }

  /// True when Dense() on the last accepted step is the solution itself, not an
  /// interpolant (the closed form of `exact` on rigid segments): events located on it
  /// need no finishing on partial steps.
  virtual bool DenseIsExact(const StepperWorkspace& /*ws*/) const { return false; }

  /// Largest step this method may take from y on the current segment
  /// (the exact flow limits itself to a fraction of the period so that events are seen).
  virtual double MaxStep(const Problem& /*problem*/,
                         const State& /*y*/,
                         StepperWorkspace& /*ws*/) const {
    return std::numeric_limits<double>::infinity();
  }
};

}  // namespace deploysim::integrators
