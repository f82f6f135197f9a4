#include "deploysim/integrators/splitting.h"

#include <cmath>
#include <memory>
#include <utility>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/carry_store.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"

namespace deploysim::integrators {

namespace {

// Yoshida's fourth-order triple-jump coefficients: g1 + g2 + g1 = 1.
const double kCbrt2 = std::cbrt(2.0);
const double kG1 = 1.0 / (2.0 - kCbrt2);
const double kG2 = -kCbrt2 / (2.0 - kCbrt2);

// Exact flow of T_i = H_i^2/(2 I_i) for time tau, in principal components: the body
// turns by alpha = H_i/I_i tau about principal axis i, so the body components of the
// fixed h_N turn by -alpha, and the attitude R_NP by +alpha.
void AxisFlow(int i, double inv_I, double tau, math::Vec3& H_P, math::Quat& q_NP) {
  const double alpha = H_P[i] * inv_I * tau;
  math::Vec3 phi = math::Vec3::Zero();
  phi[i] = alpha;
  const math::Quat r = math::ExpQuat(phi);
  q_NP = q_NP * r;
  H_P = r.conjugate() * H_P;
}

void Strang(const math::Vec3& inv_I, double h, math::Vec3& H_P, math::Quat& q_NP) {
  AxisFlow(0, inv_I[0], 0.5 * h, H_P, q_NP);
  AxisFlow(1, inv_I[1], 0.5 * h, H_P, q_NP);
  AxisFlow(2, inv_I[2], h, H_P, q_NP);
  AxisFlow(1, inv_I[1], 0.5 * h, H_P, q_NP);
  AxisFlow(0, inv_I[0], 0.5 * h, H_P, q_NP);
}

}  // namespace

SplittingStepper::SplittingStepper() : fallback_(ClassicRk4(), "rkmk4", "fallback") {
  info_.name = "split4";
  info_.summary =
      "symplectic Lie-Poisson splitting, Yoshida order 4, fixed step (constant inertia; "
      "rkmk4 elsewhere)";
  info_.reference =
      "McLachlan, PRL 71 (1993) 3043; Touma & Wisdom, AJ 107 (1994) 1189; Yoshida, Phys. "
      "Lett. A 150 (1990) 262";
  info_.order = 4;
  info_.lie_group = true;
}

namespace {

// The attitude relative to the anchor state (q_ref, H_ref): R_NB = R_ref dR,
// H_B = dR^T H_ref (rkmk.h).
struct SplitAnchor {
  math::Quat q_ref = math::Quat::Identity();
  math::Vec3 H_ref = math::Vec3::Zero();
  math::Quat dq = math::Quat::Identity();
};

class SplittingWorkspace final : public StepperWorkspace {
 public:
  explicit SplittingWorkspace(std::unique_ptr<StepperWorkspace> fallback)
      : fallback_ws(std::move(fallback)) {}
  std::unique_ptr<StepperWorkspace> fallback_ws;
  CarryStore<SplitAnchor> anchors;
  bool last_by_fallback = false;
  bool accepted_by_fallback = false;
  SplitAnchor last_a0, a0;
  SplitAnchor last_a1, a1;
  bool have_ends = false;
  math::Vec3 H0 = math::Vec3::Zero(), w0 = math::Vec3::Zero(), u1 = math::Vec3::Zero(),
             f1 = math::Vec3::Zero();
};

State PublicState(double t, const SplitAnchor& a) {
  State s;
  s.t = t;
  s.q_NB = (a.q_ref * a.dq).normalized();
  s.H_B = a.dq.conjugate() * a.H_ref;
  return s;
}

}  // namespace

std::unique_ptr<StepperWorkspace> SplittingStepper::NewWorkspace() const {
  return std::make_unique<SplittingWorkspace>(fallback_.NewWorkspace());
}

StepAttempt SplittingStepper::Step(const Problem& problem,
                                   const State& y,
                                   double h,
                                   const Tolerances& tol,
                                   StepperWorkspace& workspace) const {
  auto& ws = static_cast<SplittingWorkspace&>(workspace);
  if (!problem.source().IsRigidOn(y.t, y.t + h)) {
    ws.last_by_fallback = true;
    return fallback_.Step(problem, y, h, tol, *ws.fallback_ws);
  }
  ws.last_by_fallback = false;
  SplitAnchor a0;
  if (const SplitAnchor* found = ws.anchors.Find(y)) {
    a0 = *found;
  } else {
    a0.q_ref = y.q_NB;
    a0.H_ref = y.H_B;
  }
  const dynamics::InertiaSample s = problem.Sample(y.t);
  const math::PrincipalAxes p = math::PrincipalDecomposition(s.J_B);
  const math::Quat q_BP(p.axes);  // principal axes are right-handed: a rotation
  // Relative to the anchor: q_RP = dq q_BP, H_P = q_RP^T H_ref.
  math::Quat q_RP = a0.dq * q_BP;
  math::Vec3 H_P = q_RP.conjugate() * a0.H_ref;
  const math::Vec3 inv_I = p.moments.cwiseInverse();
  Strang(inv_I, kG1 * h, H_P, q_RP);
  Strang(inv_I, kG2 * h, H_P, q_RP);
  Strang(inv_I, kG1 * h, H_P, q_RP);
  SplitAnchor a1 = a0;
  a1.dq = (q_RP * q_BP.conjugate()).normalized();
  StepAttempt out;
  out.result = PublicState(y.t + h, a1);
  ws.anchors.Propose(out.result, a1);
  ws.last_a0 = a0;
  ws.last_a1 = a1;
  return out;
}

void SplittingStepper::Accept(const Problem& problem,
                              const State& y0,
                              const State& y1,
                              StepperWorkspace& workspace) const {
  auto& ws = static_cast<SplittingWorkspace&>(workspace);
  ws.step_begin = y0;
  ws.step_end = y1;
  ws.accepted_by_fallback = ws.last_by_fallback;
  if (ws.last_by_fallback) {
    fallback_.Accept(problem, y0, y1, *ws.fallback_ws);
    return;
  }
  ws.anchors.Accept(y1);
  ws.a0 = ws.last_a0;
  ws.a1 = ws.last_a1;
  ws.have_ends = false;
}

State SplittingStepper::Dense(const Problem& problem,
                              double t,
                              const Tolerances& tol,
                              StepperWorkspace& workspace) const {
  auto& ws = static_cast<SplittingWorkspace&>(workspace);
  if (ws.accepted_by_fallback) return fallback_.Dense(problem, t, tol, *ws.fallback_ws);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  const double h = ws.step_end.t - ws.step_begin.t;
  if (!ws.have_ends) {
    ws.H0 = ws.a0.dq.conjugate() * ws.a0.H_ref;
    const math::Vec3 H1 = ws.a1.dq.conjugate() * ws.a1.H_ref;
    ws.w0 = dynamics::AngularVelocity(problem.Sample(ws.step_begin.t), ws.H0);
    const math::Vec3 w1 = dynamics::AngularVelocity(problem.Sample(ws.step_end.t), H1);
    ws.u1 = math::LogQuat(ws.a0.dq.conjugate() * ws.a1.dq);
    ws.f1 = math::DexpInv(ws.u1, w1);
    ws.have_ends = true;
  }
  const math::Vec3 u =
      HermiteCubic<3>((t - ws.step_begin.t) / h, h, math::Vec3::Zero(), ws.w0, ws.u1, ws.f1);
  SplitAnchor a = ws.a0;
  a.dq = (ws.a0.dq * math::ExpQuat(u)).normalized();
  return PublicState(t, a);
}

}  // namespace deploysim::integrators
