#include "deploysim/integrators/explicit_rk.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/carry_store.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/rk_engine.h"
#include "deploysim/integrators/vector_state.h"

namespace deploysim::integrators {

namespace {

using Stages = std::array<Vec7, kMaxRkStages>;

class ExplicitRkWorkspace final : public StepperWorkspace {
 public:
  CarryStore<math::Vec3> carries;  // Kahan carry of H_B
  Stages last_stages{};            // of the last Step call
  // The accepted step, for Dense.
  Stages stages{};
  double h = 0.0;
  Vec7 y0 = Vec7::Zero(), y1 = Vec7::Zero();
  StepInterpolant<Vec7> dense;
};

}  // namespace

ExplicitRkStepper::ExplicitRkStepper(const ButcherTableau& tableau,
                                     std::string name,
                                     std::string summary)
    : tableau_(tableau) {
  info_.name = std::move(name);
  info_.summary = std::move(summary);
  info_.reference = tableau.reference;
  info_.order = tableau.order;
  info_.error_order = tableau.b_hat.empty() ? 0 : tableau.embedded_order;
  info_.adaptive = !tableau.b_hat.empty();
  info_.lie_group = false;
  dense_ = ChooseDenseKind(tableau);
}

std::unique_ptr<StepperWorkspace> ExplicitRkStepper::NewWorkspace() const {
  return std::make_unique<ExplicitRkWorkspace>();
}

StepAttempt ExplicitRkStepper::Step(const Problem& problem,
                                    const State& y,
                                    double h,
                                    const Tolerances& tol,
                                    StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExplicitRkWorkspace&>(workspace);
  const math::Vec3* found = ws.carries.Find(y);
  const math::Vec3 carry = found != nullptr ? *found : math::Vec3::Zero();
  const Vec7 y0 = ToVec(y);
  Vec7 err = Vec7::Zero();
  auto f = [&problem](double t, const Vec7& v) { return RigidBodyDerivative(problem, t, v); };
  const Vec7 dy =
      RkIncrement<7>(tableau_, f, y.t, y0, h, info_.adaptive ? &err : nullptr, &ws.last_stages);
  // Compensated (Kahan) summation of the momentum: near the separatrix the distance to
  // it, 2T I2 - M^2, is a small difference of large numbers, and the plain update's
  // rounding (1e-16 |H| per step) moves it enough to scatter the flip times by ~1e-9 s
  // over 40 s; carrying the rounding error removes most of that.
  Vec7 y1 = y0 + dy;
  const math::Vec3 d = dy.head<3>() + carry;
  const math::Vec3 H1 = y.H_B + d;
  y1.head<3>() = H1;
  StepAttempt out;
  if (info_.adaptive) {
    const double scale = problem.momentum_scale();
    double norm = 0.0;
    for (int i = 0; i < 7; ++i) {
      const double ref = std::max(std::abs(y0[i]), std::abs(y1[i]));
      const double w = i < 3 ? tol.atol * scale + tol.rtol * ref : tol.atol + tol.rtol * ref;
      norm = std::max(norm, std::abs(err[i]) / w);
    }
    out.error_norm = norm;
  }
  out.result.t = y.t + h;
  out.result.H_B = H1;
  out.result.q_NB = math::Quat(y1[6], y1[3], y1[4], y1[5]).normalized();
  ws.carries.Propose(out.result, math::Vec3((y.H_B - H1) + d));
  return out;
}

void ExplicitRkStepper::Accept(const Problem& /*problem*/,
                               const State& y0,
                               const State& y1,
                               StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExplicitRkWorkspace&>(workspace);
  ws.carries.Accept(y1);
  ws.step_begin = y0;
  ws.step_end = y1;
  ws.stages = ws.last_stages;
  ws.h = y1.t - y0.t;
  ws.y0 = ToVec(y0);
  ws.y1 = ToVec(y1);
  // The quaternion's sign is continuous over a step (it is renormalized, not flipped).
  ws.dense.Reset();
}

State ExplicitRkStepper::Dense(const Problem& problem,
                               double t,
                               const Tolerances& tol,
                               StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExplicitRkWorkspace&>(workspace);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  const double th = (t - ws.step_begin.t) / ws.h;
  const State begin = ws.step_begin;
  return FromVec(t, ws.dense.At(
                        dense_, th, ws.h, ws.y0, ws.y1, ws.stages,
                        [&] { return RigidBodyDerivative(problem, ws.step_end.t, ws.y1); },
                        [&](double x, Vec7& y, Vec7& f) {
                          // A partial step from the step's start (its carry is still known).
                          const State node = Step(problem, begin, x * ws.h, tol, ws).result;
                          ++ws.dense_steps;
                          y = ToVec(node);
                          f = RigidBodyDerivative(problem, node.t, y);
                        }));
}

}  // namespace deploysim::integrators
