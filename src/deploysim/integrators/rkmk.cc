#include "deploysim/integrators/rkmk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/math/double_double.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"

namespace deploysim::integrators {

namespace {
constexpr int kMaxStages = 16;

// Quaternion arithmetic in double-double (math::DoubleDouble, ~106 bits on every
// platform), used only for the attitude update, to compute its rounding error: written out
// here because Eigen's quaternions are not meant for it and the update is a few products.
// ("L" for the lifted precision.)
using math::DoubleDouble;

struct QuatL {
  DoubleDouble w, x, y, z;
};

// Hamilton product a b; B is QuatL or a double quaternion (then the products are the
// cheaper double-double times double).
template <class B>
QuatL MulT(const QuatL& a, const B& bw, const B& bx, const B& by, const B& bz) {
  return {a.w * bw - a.x * bx - a.y * by - a.z * bz, a.w * bx + a.x * bw + a.y * bz - a.z * by,
          a.w * by - a.x * bz + a.y * bw + a.z * bx, a.w * bz + a.x * by - a.y * bx + a.z * bw};
}

QuatL Mul(const QuatL& a, const QuatL& b) { return MulT(a, b.w, b.x, b.y, b.z); }

QuatL Mul(const QuatL& a, const math::Quat& b) { return MulT(a, b.w(), b.x(), b.y(), b.z()); }

// Exp of a rotation vector (x, y, z) [rad]: (cos(a/2), sin(a/2)/a (x, y, z)), a = |(x, y, z)|,
// from the series in a^2 / 4 (no square root, no division) up to a = pi/2.
QuatL ExpL(const DoubleDouble& x, const DoubleDouble& y, const DoubleDouble& z) {
  constexpr double kSeriesMaxA2 = 2.4674011002723395;  // (pi/2)^2
  const DoubleDouble a2 = Square(x) + Square(y) + Square(z);
  DoubleDouble s, cos_half;
  if (a2 <= kSeriesMaxA2) {
    DoubleDouble sinc;
    math::SincCosOfSquare(a2 * 0.25, &sinc, &cos_half);
    s = sinc * 0.5;
  } else {
    const DoubleDouble a = Sqrt(a2);
    DoubleDouble sin_half;
    math::SinCos(a * 0.5, &sin_half, &cos_half);
    s = sin_half / a;
  }
  return {cos_half, s * x, s * y, s * z};
}

// q1 (the rounded double quaternion, unit) and the carry delta with q1 Exp(delta) = exact
// to double-double precision.
void RoundWithCarry(const QuatL& exact, math::Quat& q1, math::Vec3& delta) {
  const DoubleDouble inv_n =
      1.0 / Sqrt(Square(exact.w) + Square(exact.x) + Square(exact.y) + Square(exact.z));
  const QuatL e{exact.w * inv_n, exact.x * inv_n, exact.y * inv_n, exact.z * inv_n};
  q1 = math::Quat(static_cast<double>(e.w), static_cast<double>(e.x), static_cast<double>(e.y),
                  static_cast<double>(e.z))
           .normalized();
  // q1^-1 e = (1, delta/2) to first order (delta ~ 1e-16 rad); q1 is double, so the
  // products are double-double times double. Only the vector part is needed, and only its
  // sign-corrected value: d.w ~ +-1.
  const double w = q1.w(), x = -q1.x(), y = -q1.y(), z = -q1.z();
  const DoubleDouble dw = e.w * w - e.x * x - e.y * y - e.z * z;
  const DoubleDouble dx = e.x * w + e.w * x + e.z * y - e.y * z;
  const DoubleDouble dy = e.y * w - e.z * x + e.w * y + e.x * z;
  const DoubleDouble dz = e.z * w + e.y * x - e.x * y + e.w * z;
  const double sign = dw < 0.0 ? -2.0 : 2.0;
  delta = math::Vec3(sign * static_cast<double>(dx), sign * static_cast<double>(dy),
                     sign * static_cast<double>(dz));
}
}  // namespace
}  // namespace deploysim::integrators

// (Included here, below the extended-precision helpers, to keep the two parts apart.)
#include "deploysim/integrators/carry_store.h"
#include "deploysim/integrators/dense_output.h"

namespace deploysim::integrators {
namespace {

// The Lie-group state of a run: the attitude relative to an anchor state (q_ref, H_ref),
// R_NB = R_ref dR with dR = dq Exp(carry) (carry: the rounding error of dq, ~1e-16 rad),
// and H_B = dR^T H_ref. At the anchor dq = 1 and carry = 0, so H_B is H_ref bit for bit.
struct Anchor {
  math::Quat q_ref = math::Quat::Identity();
  math::Vec3 H_ref = math::Vec3::Zero();
  math::Quat dq = math::Quat::Identity();
  math::Vec3 carry = math::Vec3::Zero();
};

using Stages3 = std::array<math::Vec3, kMaxStages>;

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
  bool have_f1 = false, have_nodes = false;
  math::Vec3 f1 = math::Vec3::Zero();
  std::array<double, kMaxHermiteNodes> x{};
  std::array<math::Vec3, kMaxHermiteNodes> u{}, f{};
  // Of the last Step call.
  Anchor last_a0;
  double last_sigma = 0.0;
  math::Vec3 last_H0 = math::Vec3::Zero(), last_u1 = math::Vec3::Zero();
  Stages3 last_stages{};
};

// H_B of the true relative attitude dq Exp(carry): Exp(-carry) dq^T H_ref.
math::Vec3 MomentumOf(const Anchor& a) {
  const math::Vec3 H_rounded = a.dq.conjugate() * a.H_ref;
  return H_rounded - a.carry.cross(H_rounded);
}

// The state at t whose relative attitude is Exp(spin) dq0 Exp(carry0 + u), composed in
// extended precision (the next carry is its rounding).
Anchor Compose(const Anchor& a0, const math::Vec3& spin, const math::Vec3& u) {
  const QuatL exact = Mul(Mul(ExpL(spin.x(), spin.y(), spin.z()), a0.dq),
                          ExpL(math::TwoSum(u.x(), a0.carry.x()), math::TwoSum(u.y(), a0.carry.y()),
                               math::TwoSum(u.z(), a0.carry.z())));
  Anchor a1 = a0;
  RoundWithCarry(exact, a1.dq, a1.carry);
  return a1;
}

// The same composition in double, for output samples (its rounding, ~1e-16 rad, is not
// propagated).
Anchor ComposeForOutput(const Anchor& a0, const math::Vec3& spin, const math::Vec3& u) {
  Anchor a1 = a0;
  a1.dq = (math::ExpQuat(spin) * a0.dq * math::ExpQuat(a0.carry + u)).normalized();
  a1.carry = math::Vec3::Zero();
  return a1;
}

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
  const int s = tableau_.stages();
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
  for (int i = 1; i < s; ++i) {
    math::Vec3 u = math::Vec3::Zero();
    for (int j = 0; j < i; ++j) {
      const double aij = tableau_.a[i][j];
      if (aij != 0.0) u += (h * aij) * k[j];
    }
    const double ci = tableau_.c[i];
    const double ti = ci == 1.0 ? t_end : y.t + ci * h;
    k[i] = AlgebraRate(problem, ti, u, H0, sigma);
  }
  math::Vec3 u1 = math::Vec3::Zero();
  for (int i = 0; i < s; ++i) {
    if (tableau_.b[i] != 0.0) u1 += (h * tableau_.b[i]) * k[i];
  }
  // dq1 = Exp(sigma h H_ref) dq0 Exp(carry) Exp(u1) ~ Exp(sigma h H_ref) dq0 Exp(carry + u1)
  // (the BCH term carry x u1 / 2 is ~1e-18 rad), in extended precision; its rounding to
  // double becomes the next carry, so rounding does not accumulate over the steps: near
  // the separatrix every 1e-16 rad would move the flips (DESIGN.md 6).
  const Anchor a1 = Compose(a0, (sigma * h) * a0.H_ref, u1);
  StepAttempt out;
  out.result = PublicState(t_end, a1);
  if (info_.adaptive) {
    math::Vec3 err = math::Vec3::Zero();
    for (int i = 0; i < s; ++i) {
      const double d = tableau_.b[i] - tableau_.b_hat[i];
      if (d != 0.0) err += (h * d) * k[i];
    }
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
  ws.have_f1 = false;
  ws.have_nodes = false;
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
  const math::Vec3 zero = math::Vec3::Zero();
  math::Vec3 u;
  if (dense_ == DenseKind::kDopri) {
    u = DopriDense<3>(th, h, zero, ws.u1, ws.stages);
  } else {
    if (!ws.have_f1) {
      ws.f1 = AlgebraRate(problem, ws.step_end.t, ws.u1, ws.H0, ws.sigma);
      ws.have_f1 = true;
    }
    if (dense_ == DenseKind::kHermiteCubic) {
      u = HermiteCubic<3>(th, h, zero, ws.stages[0], ws.u1, ws.f1);
    } else {
      const int n = kHighOrderHermiteNodes;
      if (!ws.have_nodes) {
        // Interior nodes by partial steps from the step's start (same anchor, same
        // sigma; Step writes only the workspace's "last step" fields).
        const State begin = ws.step_begin;
        for (int j = 0; j < n; ++j) {
          ws.x[j] = static_cast<double>(j) / (n - 1);
          if (j == 0) {
            ws.u[j] = zero;
            ws.f[j] = ws.stages[0];
          } else if (j == n - 1) {
            ws.u[j] = ws.u1;
            ws.f[j] = ws.f1;
          } else {
            Step(problem, begin, ws.x[j] * h, tol, ws);
            ++ws.dense_steps;
            ws.u[j] = ws.last_u1;
            ws.f[j] = AlgebraRate(problem, begin.t + ws.x[j] * h, ws.u[j], ws.H0, ws.sigma);
          }
        }
        ws.have_nodes = true;
      }
      u = HermiteNodes<3>(th, h, n, ws.x.data(), ws.u.data(), ws.f.data());
    }
  }
  return PublicState(t, ComposeForOutput(ws.a0, (ws.sigma * tau) * ws.a0.H_ref, u));
}

}  // namespace deploysim::integrators
