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
  /// Compensated-summation carry of H_B (Kahan): the rounding error of the last
  /// update, added back in the next one by the vector-space steppers. Zero elsewhere.
  math::Vec3 H_B_carry = math::Vec3::Zero();
  /// The Lie-group steppers' carry of the attitude: the true attitude is
  /// q_NB * Exp(attitude_carry), the rounding error of the last update (~1e-16 rad),
  /// computed in extended precision and folded into the next step. Zero elsewhere.
  math::Vec3 attitude_carry = math::Vec3::Zero();
};

/// The source of J(t), h_rel(t) plus what is fixed for a whole run: the inertial
/// momentum h_N (for Lie-group methods) and the end of the current smooth segment.
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
