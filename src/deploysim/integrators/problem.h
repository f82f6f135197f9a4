#pragma once

/// The integration state and the view of the problem a stepper gets.

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/math/types.h"

namespace deploysim::integrators {

/// Attitude state of the reduced model at time t [s].
struct State {
  double t = 0.0;
  math::Vec3 H_B = math::Vec3::Zero();       ///< [kg m^2/s] total momentum, B components.
  math::Quat q_NB = math::Quat::Identity();  ///< Attitude of B in N (unit).
};

/// The source of J(t), h_rel(t) plus what is fixed for a whole run: the inertial
/// momentum h_N = R_NB(t0) H_B(t0) (for reporting and the error weights; the Lie-group
/// steppers carry the attitude relative to the state they start from, see rkmk.h) and
/// the current smooth segment.
/// Counts the source evaluations (right-hand-side evaluations) for benchmarks.
class Problem {
 public:
  Problem(const dynamics::InertiaSource& source, const math::Vec3& h_N);

  const dynamics::InertiaSource& source() const { return source_; }
  const math::Vec3& h_N() const { return h_N_; }
  /// Momentum magnitude |h_N| [kg m^2/s], the scale of the error weights.
  double momentum_scale() const { return momentum_scale_; }

  double segment_begin() const { return segment_begin_; }
  double segment_end() const { return segment_end_; }
  void SetSegment(double begin, double end);

  /// The source at t: from the left when t is at (or, by rounding, past) the end of
  /// the segment, else from the right. Counts one evaluation.
  dynamics::InertiaSample Sample(double t) const;

  long evaluations() const { return evaluations_; }

 private:
  const dynamics::InertiaSource& source_;
  math::Vec3 h_N_;
  double momentum_scale_;
  double segment_begin_ = 0.0;
  double segment_end_ = 0.0;
  mutable long evaluations_ = 0;
};

}  // namespace deploysim::integrators
