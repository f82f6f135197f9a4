#pragma once

/// The rotation group SO(3) and its Lie algebra so(3) ~ R^3.
/// Convention: hat(v) * u = v x u; Exp(phi) is the rotation by |phi| rad about phi/|phi|.

#include "deploysim/math/types.h"

namespace deploysim::math {

/// Skew-symmetric matrix [v]x with [v]x u = v x u.
Mat3 Hat(const Vec3& v);

/// Inverse of Hat: the vector of the skew-symmetric part of W.
Vec3 Vee(const Mat3& W);

/// Rodrigues' formula R = I + sin(a)/a [phi]x + (1-cos a)/a^2 [phi]x^2, a = |phi|,
/// with Taylor series for a < 1e-4 (no division by small numbers). Thesis eq. 2.68.
Mat3 ExpSO3(const Vec3& phi);

/// Principal logarithm: phi with ExpSO3(phi) = R and |phi| <= pi. Accurate near 0 and
/// near pi (uses the symmetric part there). R must be a rotation matrix.
Vec3 LogSO3(const Mat3& R);

/// Inverse right Jacobian of the exponential map on so(3):
/// J_r^{-1}(u) v = v + 1/2 u x v + c(|u|) u x (u x v),
/// c(a) = (1 - (a/2) cot(a/2)) / a^2  (series 1/12 + a^2/720 + ... for small a).
/// For R = R0 Exp(u(t)) the body-frame angular velocity is w = J_r(u) u', so
/// Runge-Kutta-Munthe-Kaas methods for R' = R [w]x integrate u' = J_r^{-1}(u) w.
/// Reference: Iserles, Munthe-Kaas, Norsett, Zanna, Acta Numerica 9 (2000), sec. 2.
Vec3 DexpInv(const Vec3& u, const Vec3& v);

}  // namespace deploysim::math
