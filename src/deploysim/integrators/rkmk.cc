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
}

StepAttempt RkmkStepper::Step(const Problem& problem,
                              const State& y,
                              double h,
                              const Tolerances& tol) const {
  const int s = tableau_.stages();
  const math::Vec3& h_N = problem.h_N();
  const double t_end = y.t + h;
  // H_B of the true attitude q_NB Exp(carry): Exp(-carry) R^T h_N.
  const math::Vec3 H0_rounded = y.q_NB.conjugate() * h_N;
  const math::Vec3 H0 = H0_rounded - y.attitude_carry.cross(H0_rounded);
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
  // q1 = Exp(sigma h h_N) q0 Exp(carry) Exp(u1) ~ Exp(sigma h h_N) q0 Exp(carry + u1)
  // (the BCH term carry x u1 / 2 is ~1e-18 rad), in extended precision; its rounding to
  // double becomes the next carry, so rounding does not accumulate over the steps: near
  // the separatrix every 1e-16 rad would move the flips (DESIGN.md 6).
  const math::Vec3 a = (sigma * h) * h_N;
  const QuatL q1_exact =
      Mul(Mul(ExpL(a.x(), a.y(), a.z()), y.q_NB), ExpL(math::TwoSum(u1.x(), y.attitude_carry.x()),
                                                       math::TwoSum(u1.y(), y.attitude_carry.y()),
                                                       math::TwoSum(u1.z(), y.attitude_carry.z())));
  math::Quat q1;
  math::Vec3 carry1;
  RoundWithCarry(q1_exact, q1, carry1);
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
  out.result.attitude_carry = carry1;
  const math::Vec3 H1_rounded = q1.conjugate() * h_N;
  out.result.H_B = H1_rounded - carry1.cross(H1_rounded);
  return out;
}

}  // namespace deploysim::integrators
