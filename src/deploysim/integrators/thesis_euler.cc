#include "deploysim/integrators/thesis_euler.h"

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::integrators {

ThesisEulerStepper::ThesisEulerStepper() {
  info_.name = "thesis-euler";
  info_.summary = "explicit Euler on H_B + midpoint-exp attitude (the seed thesis, baseline)";
  info_.reference = "seed thesis eqs. 3.13-3.15 and 2.66-2.70";
  info_.order = 1;
}

StepAttempt ThesisEulerStepper::Step(const Problem& problem,
                                     const State& y,
                                     double h,
                                     const Tolerances& /*tol*/) const {
  const math::Vec3 w0 = dynamics::AngularVelocity(problem.Sample(y.t), y.H_B);
  StepAttempt out;
  out.result.t = y.t + h;
  out.result.H_B = y.H_B + h * dynamics::MomentumRate(y.H_B, w0);
  const math::Vec3 w1 = dynamics::AngularVelocity(problem.Sample(out.result.t), out.result.H_B);
  out.result.q_NB = (y.q_NB * math::ExpQuat((0.5 * h) * (w0 + w1))).normalized();
  return out;
}

}  // namespace deploysim::integrators
