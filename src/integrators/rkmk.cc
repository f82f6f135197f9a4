#include "integrators/rkmk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "dynamics/rigid_body.h"
#include "math/quaternion.h"
#include "math/so3.h"

namespace deploysim::integrators {

namespace {
constexpr int kMaxStages = 16;
}  // namespace

RkmkStepper::RkmkStepper(const ButcherTableau& tableau, std::string name, std::string summary)
    : tableau_(tableau) {
  info_.name = std::move(name);
  info_.summary = std::move(summary);
  info_.reference = "H. Munthe-Kaas, Appl. Numer. Math. 29 (1999) 115-127; tableau: " +
                    tableau.reference;
  info_.order = tableau.order;
  info_.error_order = tableau.b_hat.empty() ? 0 : tableau.embedded_order;
  info_.adaptive = !tableau.b_hat.empty();
  info_.lie_group = true;
}

StepAttempt RkmkStepper::Step(const Problem& problem,
                              const State& y,
                              double h,
                              const Tolerances& tol) const {
  const int s = tableau_.stages();
  const math::Vec3& h_N = problem.h_N();
  const double t_end = y.t + h;
  const math::Vec3 H0 = y.q_NB.conjugate() * h_N;
  // The spin about h_N is integrated exactly: R(t + tau) = Exp(sigma tau h_N) R0 Exp(u),
  // which leaves H_B = Exp(-u) R0^T h_N unchanged, with sigma frozen over the step at
  // (w . H)/|H|^2. Then u' = J_r^{-1}(u) (w - sigma H_B) only carries the motion of
  // H_B in the body: slow near a principal axis, so far fewer steps are needed than
  // when the Lie-group method also has to resolve the fast spin.
  const math::Vec3 w0 = dynamics::AngularVelocity(problem.Sample(y.t), H0);
  const double H0_2 = H0.squaredNorm();
  const double sigma = H0_2 > 0.0 ? w0.dot(H0) / H0_2 : 0.0;
  std::array<math::Vec3, kMaxStages> k;
  k[0] = w0 - sigma * H0;
  for (int i = 1; i < s; ++i) {
    math::Vec3 u = math::Vec3::Zero();
    for (int j = 0; j < i; ++j) {
      const double aij = tableau_.a[i][j];
      if (aij != 0.0) u += (h * aij) * k[j];
    }
    const math::Vec3 Hi = math::ExpQuat(-u) * H0;
    const double ci = tableau_.c[i];
    const double ti = ci == 1.0 ? t_end : y.t + ci * h;
    const math::Vec3 wi = dynamics::AngularVelocity(problem.Sample(ti), Hi);
    k[i] = math::DexpInv(u, wi - sigma * Hi);
  }
  math::Vec3 u1 = math::Vec3::Zero();
  for (int i = 0; i < s; ++i) {
    if (tableau_.b[i] != 0.0) u1 += (h * tableau_.b[i]) * k[i];
  }
  const math::Quat q1 =
      (math::ExpQuat((sigma * h) * h_N) * y.q_NB * math::ExpQuat(u1)).normalized();
  StepAttempt out;
  if (info_.adaptive) {
    math::Vec3 err = math::Vec3::Zero();
    for (int i = 0; i < s; ++i) {
      const double d = tableau_.b[i] - tableau_.b_hat[i];
      if (d != 0.0) err += (h * d) * k[i];
    }
    // An attitude error du moves H_B = Exp(-du) R^T h_N by about H_B x du: weigh it per
    // component exactly like the momentum components of the vector-space steppers.
    const math::Vec3 H1 = q1.conjugate() * h_N;
    const math::Vec3 dH = H1.cross(err);
    const double scale = problem.momentum_scale();
    double norm = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double ref = std::max(std::abs(H0[i]), std::abs(H1[i]));
      norm = std::max(norm, std::abs(dH[i]) / (tol.atol * scale + tol.rtol * ref));
    }
    out.error_norm = norm;
  }
  out.result.t = t_end;
  out.result.q_NB = q1;
  out.result.H_B = out.result.q_NB.conjugate() * h_N;
  return out;
}

}  // namespace deploysim::integrators
