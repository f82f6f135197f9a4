#include "deploysim/integrators/splitting.h"

#include <cmath>

#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"

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

StepAttempt SplittingStepper::Step(const Problem& problem,
                                   const State& y,
                                   double h,
                                   const Tolerances& tol) const {
  if (!problem.source().IsRigidOn(y.t, y.t + h)) return fallback_.Step(problem, y, h, tol);
  const dynamics::InertiaSample s = problem.Sample(y.t);
  const math::PrincipalAxes p = math::PrincipalDecomposition(s.J_B);
  const math::Quat q_BP(p.axes);  // principal axes are right-handed: a rotation
  math::Quat q_NP = y.q_NB * q_BP;
  math::Vec3 H_P = q_NP.conjugate() * problem.h_N();
  const math::Vec3 inv_I = p.moments.cwiseInverse();
  Strang(inv_I, kG1 * h, H_P, q_NP);
  Strang(inv_I, kG2 * h, H_P, q_NP);
  Strang(inv_I, kG1 * h, H_P, q_NP);
  StepAttempt out;
  out.result.t = y.t + h;
  out.result.q_NB = (q_NP * q_BP.conjugate()).normalized();
  out.result.H_B = out.result.q_NB.conjugate() * problem.h_N();
  return out;
}

}  // namespace deploysim::integrators
