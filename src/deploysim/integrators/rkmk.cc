#include "deploysim/integrators/rkmk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/carry_store.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/lie_anchor.h"
#include "deploysim/integrators/rk_engine.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"

namespace deploysim::integrators {
namespace {

using lie::Anchor;
using lie::Compose;
using lie::ComposeForOutput;
using lie::MomentumOf;

using Stages3 = std::array<math::Vec3, kMaxRkStages>;

class RkmkWorkspace final : public StepperWorkspace {
 public:
  CarryStore<Anchor> anchors;
  // The accepted step, for Dense: its start, the frozen spin rate, the increment u1 and
  // the stages of u' = F(u).
  Anchor a0;
  double sigma = 0.0;
  math::Vec3 H0 = math::Vec3::Zero();
  math::Vec3 u1 = math::Vec3::Zero();
  Stages3 stages{};
  StepInterpolant<math::Vec3> dense;
  // Of the last Step call.
  Anchor last_a0;
  double last_sigma = 0.0;
  math::Vec3 last_H0 = math::Vec3::Zero(), last_u1 = math::Vec3::Zero();
  Stages3 last_stages{};
};

State PublicState(double t, const Anchor& a) {
  State s;
  s.t = t;
  s.q_NB = (a.q_ref * a.dq).normalized();
  s.H_B = MomentumOf(a);
  return s;
}

// u' = F(u) = J_r^{-1}(u) (w - sigma H) with H = Exp(-u) H0, at time t.
math::Vec3 AlgebraRate(
    const Problem& problem, double t, const math::Vec3& u, const math::Vec3& H0, double sigma) {
  const math::Vec3 H = math::ExpQuat(-u) * H0;
  const math::Vec3 w = dynamics::AngularVelocity(problem.Sample(t), H);
  return math::DexpInv(u, w - sigma * H);
}

}  // namespace

RkmkStepper::RkmkStepper(const ButcherTableau& tableau, std::string name, std::string summary)
    : tableau_(tableau) {
  info_.name = std::move(name);
  info_.summary = std::move(summary);
  info_.reference =
      "H. Munthe-Kaas, Appl. Numer. Math. 29 (1999) 115-127; tableau: " + tableau.reference;
  info_.order = tableau.order;
  info_.error_order = tableau.b_hat.empty() ? 0 : tableau.embedded_order;
  info_.adaptive = !tableau.b_hat.empty();
  info_.lie_group = true;
  dense_ = ChooseDenseKind(tableau);
}

std::unique_ptr<StepperWorkspace> RkmkStepper::NewWorkspace() const {
  return std::make_unique<RkmkWorkspace>();
}

StepAttempt RkmkStepper::Step(const Problem& problem,
                              const State& y,
                              double h,
                              const Tolerances& tol,
                              StepperWorkspace& workspace) const {
  auto& ws = static_cast<RkmkWorkspace&>(workspace);
  Anchor a0;
  if (const Anchor* found = ws.anchors.Find(y)) {
    a0 = *found;
  } else {
    // A state this workspace did not produce: anchor the relative attitude on it.
    a0.q_ref = y.q_NB;
    a0.H_ref = y.H_B;
  }
  const double t_end = y.t + h;
  const math::Vec3 H0 = MomentumOf(a0);
  // The spin about h_N is integrated exactly: R(t + tau) = Exp(sigma tau h_N) R0 Exp(u),
  // which leaves H_B = Exp(-u) R0^T h_N unchanged, with sigma frozen over the step at
  // (w . H)/|H|^2. Then u' = J_r^{-1}(u) (w - sigma H_B) only carries the motion of
  // H_B in the body: slow near a principal axis, so far fewer steps are needed than
  // when the Lie-group method also has to resolve the fast spin. Relative to the
  // anchor, Exp(sigma tau h_N) R_ref = R_ref Exp(sigma tau H_ref).
  const math::Vec3 w0 = dynamics::AngularVelocity(problem.Sample(y.t), H0);
  const double H0_2 = H0.squaredNorm();
  const double sigma = H0_2 > 0.0 ? w0.dot(H0) / H0_2 : 0.0;
  Stages3& k = ws.last_stages;
  k[0] = w0 - sigma * H0;
  math::Vec3 u;
  RkStages<math::Vec3>(
      tableau_,
      [&](double ti, const math::Vec3& ui, math::Vec3& ki) {
        ki = AlgebraRate(problem, ti, ui, H0, sigma);
      },
      y.t, h, math::Vec3::Zero(), u, k);
  math::Vec3 u1;
  RkWeightedSum<math::Vec3>(tableau_.b, nullptr, h, k, u1);
  // dq1 = Exp(sigma h H_ref) dq0 Exp(carry) Exp(u1) ~ Exp(sigma h H_ref) dq0 Exp(carry + u1)
  // (the BCH term carry x u1 / 2 is ~1e-18 rad), in extended precision; its rounding to
  // double becomes the next carry, so rounding does not accumulate over the steps: near
  // the separatrix every 1e-16 rad would move the flips (docs/design.md 2.3).
  const Anchor a1 = Compose(a0, (sigma * h) * a0.H_ref, u1);
  StepAttempt out;
  out.result = PublicState(t_end, a1);
  if (info_.adaptive) {
    math::Vec3 err;
    RkWeightedSum<math::Vec3>(tableau_.b, &tableau_.b_hat, h, k, err);
    // An attitude error du moves H_B = Exp(-du) R^T h_N by about H_B x du: weigh it per
    // component exactly like the momentum components of the vector-space steppers.
    const math::Vec3 H1 = a1.dq.conjugate() * a1.H_ref;
    const math::Vec3 dH = H1.cross(err);
    const double scale = problem.momentum_scale();
    double norm = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double ref = std::max(std::abs(H0[i]), std::abs(H1[i]));
      norm = std::max(norm, std::abs(dH[i]) / (tol.atol * scale + tol.rtol * ref));
    }
    out.error_norm = norm;
  }
  ws.anchors.Propose(out.result, a1);
  ws.last_a0 = a0;
  ws.last_sigma = sigma;
  ws.last_H0 = H0;
  ws.last_u1 = u1;
  return out;
}

void RkmkStepper::Accept(const Problem& /*problem*/,
                         const State& y0,
                         const State& y1,
                         StepperWorkspace& workspace) const {
  auto& ws = static_cast<RkmkWorkspace&>(workspace);
  ws.anchors.Accept(y1);
  ws.step_begin = y0;
  ws.step_end = y1;
  ws.a0 = ws.last_a0;
  ws.sigma = ws.last_sigma;
  ws.H0 = ws.last_H0;
  ws.u1 = ws.last_u1;
  ws.stages = ws.last_stages;
  ws.dense.Reset();
}

State RkmkStepper::Dense(const Problem& problem,
                         double t,
                         const Tolerances& tol,
                         StepperWorkspace& workspace) const {
  auto& ws = static_cast<RkmkWorkspace&>(workspace);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  // Hermite interpolation of the Lie-algebra coordinate u(tau) of the step (the spin
  // about h_N is exact): u(0) = 0, u'(0) = F(0), u(h) = u1, u'(h) = F(u1).
  const double h = ws.step_end.t - ws.step_begin.t;
  const double tau = t - ws.step_begin.t;
  const double th = tau / h;
  const State begin = ws.step_begin;
  const math::Vec3 u = ws.dense.At(
      dense_, th, h, math::Vec3::Zero(), ws.u1, ws.stages,
      [&] { return AlgebraRate(problem, ws.step_end.t, ws.u1, ws.H0, ws.sigma); },
      [&](double x, math::Vec3& u_x, math::Vec3& f_x) {
        // A partial step from the step's start (same anchor, same sigma; Step writes
        // only the workspace's "last step" fields).
        Step(problem, begin, x * h, tol, ws);
        ++ws.dense_steps;
        u_x = ws.last_u1;
        f_x = AlgebraRate(problem, begin.t + x * h, u_x, ws.H0, ws.sigma);
      });
  return PublicState(t, ComposeForOutput(ws.a0, (ws.sigma * tau) * ws.a0.H_ref, u));
}

}  // namespace deploysim::integrators
