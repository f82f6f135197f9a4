#pragma once

/// For the Lie-group steppers (rkmk.cc, shape_stepper.cc), not for users of the steppers:
/// the attitude of a run relative to an anchor state, composed in double-double so that
/// rounding does not accumulate over the steps (the carry), docs/design.md 2.1.

#include "deploysim/math/double_double.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/so3.h"
#include "deploysim/math/types.h"

namespace deploysim::integrators::lie {

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
inline QuatL MulT(const QuatL& a, const B& bw, const B& bx, const B& by, const B& bz) {
  return {a.w * bw - a.x * bx - a.y * by - a.z * bz, a.w * bx + a.x * bw + a.y * bz - a.z * by,
          a.w * by - a.x * bz + a.y * bw + a.z * bx, a.w * bz + a.x * by - a.y * bx + a.z * bw};
}

inline QuatL Mul(const QuatL& a, const QuatL& b) { return MulT(a, b.w, b.x, b.y, b.z); }

inline QuatL Mul(const QuatL& a, const math::Quat& b) {
  return MulT(a, b.w(), b.x(), b.y(), b.z());
}

// Exp of a rotation vector (x, y, z) [rad]: (cos(a/2), sin(a/2)/a (x, y, z)), a = |(x, y, z)|,
// from the series in a^2 / 4 (no square root, no division) up to a = pi/2.
inline QuatL ExpL(const DoubleDouble& x, const DoubleDouble& y, const DoubleDouble& z) {
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
inline void RoundWithCarry(const QuatL& exact, math::Quat& q1, math::Vec3& delta) {
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
// The Lie-group state of a run: the attitude relative to an anchor state (q_ref, H_ref),
// R_NB = R_ref dR with dR = dq Exp(carry) (carry: the rounding error of dq, ~1e-16 rad),
// and H_B = dR^T H_ref. At the anchor dq = 1 and carry = 0, so H_B is H_ref bit for bit.
struct Anchor {
  math::Quat q_ref = math::Quat::Identity();
  math::Vec3 H_ref = math::Vec3::Zero();
  math::Quat dq = math::Quat::Identity();
  math::Vec3 carry = math::Vec3::Zero();
};

// H_B of the true relative attitude dq Exp(carry): Exp(-carry) dq^T H_ref.
inline math::Vec3 MomentumOf(const Anchor& a) {
  const math::Vec3 H_rounded = a.dq.conjugate() * a.H_ref;
  return H_rounded - a.carry.cross(H_rounded);
}

// The state at t whose relative attitude is Exp(spin) dq0 Exp(carry0 + u), composed in
// extended precision (the next carry is its rounding).
inline Anchor Compose(const Anchor& a0, const math::Vec3& spin, const math::Vec3& u) {
  const QuatL exact = Mul(Mul(ExpL(spin.x(), spin.y(), spin.z()), a0.dq),
                          ExpL(math::TwoSum(u.x(), a0.carry.x()), math::TwoSum(u.y(), a0.carry.y()),
                               math::TwoSum(u.z(), a0.carry.z())));
  Anchor a1 = a0;
  RoundWithCarry(exact, a1.dq, a1.carry);
  return a1;
}

// The same composition in double, for output samples (its rounding, ~1e-16 rad, is not
// propagated).
inline Anchor ComposeForOutput(const Anchor& a0, const math::Vec3& spin, const math::Vec3& u) {
  Anchor a1 = a0;
  a1.dq = (math::ExpQuat(spin) * a0.dq * math::ExpQuat(a0.carry + u)).normalized();
  a1.carry = math::Vec3::Zero();
  return a1;
}

}  // namespace deploysim::integrators::lie
