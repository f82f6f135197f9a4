#include "deploysim/integrators/thesis_euler.h"

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/vector_state.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::integrators {

namespace {
class ThesisEulerWorkspace final : public StepperWorkspace {
 public:
  bool have_ends = false;
  Vec7 y0 = Vec7::Zero(), f0 = Vec7::Zero(), y1 = Vec7::Zero(), f1 = Vec7::Zero();
};
}  // namespace

ThesisEulerStepper::ThesisEulerStepper() {
  info_.name = "thesis-euler";
  info_.summary = "explicit Euler on H_B + midpoint-exp attitude (the seed thesis, baseline)";
  info_.reference = "seed thesis eqs. 3.13-3.15 and 2.66-2.70";
  info_.order = 1;
}

std::unique_ptr<StepperWorkspace> ThesisEulerStepper::NewWorkspace() const {
  return std::make_unique<ThesisEulerWorkspace>();
}

StepAttempt ThesisEulerStepper::Step(const Problem& problem,
                                     const State& y,
                                     double h,
                                     const Tolerances& /*tol*/,
                                     StepperWorkspace& /*ws*/) const {
  const math::Vec3 w0 = dynamics::AngularVelocity(problem.Sample(y.t), y.H_B);
  StepAttempt out;
  out.result.t = y.t + h;
  out.result.H_B = y.H_B + h * dynamics::MomentumRate(y.H_B, w0);
  const math::Vec3 w1 = dynamics::AngularVelocity(problem.Sample(out.result.t), out.result.H_B);
  out.result.q_NB = (y.q_NB * math::ExpQuat((0.5 * h) * (w0 + w1))).normalized();
  return out;
}

void ThesisEulerStepper::Accept(const Problem& /*problem*/,
                                const State& y0,
                                const State& y1,
                                StepperWorkspace& workspace) const {
  auto& ws = static_cast<ThesisEulerWorkspace&>(workspace);
  ws.step_begin = y0;
  ws.step_end = y1;
  ws.have_ends = false;
}

State ThesisEulerStepper::Dense(const Problem& problem,
                                double t,
                                const Tolerances& /*tol*/,
                                StepperWorkspace& workspace) const {
  auto& ws = static_cast<ThesisEulerWorkspace&>(workspace);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  if (!ws.have_ends) {
    ws.y0 = ToVec(ws.step_begin);
    ws.y1 = ToVec(ws.step_end);
    ws.f0 = RigidBodyDerivative(problem, ws.step_begin.t, ws.y0);
    ws.f1 = RigidBodyDerivative(problem, ws.step_end.t, ws.y1);
    ws.have_ends = true;
  }
  const double h = ws.step_end.t - ws.step_begin.t;
  return FromVec(t, HermiteCubic<7>((t - ws.step_begin.t) / h, h, ws.y0, ws.f0, ws.y1, ws.f1));
}

}  // namespace deploysim::integrators
