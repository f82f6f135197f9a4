#include "deploysim/math/so3.h"

#include <algorithm>
#include <cmath>

namespace deploysim::math {

namespace {
// Below this rotation angle [rad] the closed forms lose digits to cancellation and the
// Taylor series (truncated after the a^4 term, error < a^6 ~ 1e-24) is used instead.
constexpr double kSmallAngle = 1e-4;
}  // namespace

Mat3 Hat(const Vec3& v) {
  Mat3 W;
  W << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return W;
}

Vec3 Vee(const Mat3& W) {
  return Vec3(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1)));
}

Mat3 ExpSO3(const Vec3& phi) {
  const double a2 = phi.squaredNorm();
  const double a = std::sqrt(a2);
  double s;  // sin(a)/a
  double c;  // (1 - cos a)/a^2
  if (a < kSmallAngle) {
    s = 1.0 - a2 / 6.0 * (1.0 - a2 / 20.0);
    c = 0.5 - a2 / 24.0 * (1.0 - a2 / 30.0);
  } else {
    s = std::sin(a) / a;
    c = (1.0 - std::cos(a)) / a2;
  }
  const Mat3 W = Hat(phi);
  return Mat3::Identity() + s * W + c * (W * W);
}

Vec3 LogSO3(const Mat3& R) {
  const double cos_a = std::clamp(0.5 * (R.trace() - 1.0), -1.0, 1.0);
  const Vec3 v = Vee(R);  // sin(a) * axis
  const double sin_a = v.norm();
  const double a = std::atan2(sin_a, cos_a);
  if (a < kSmallAngle) {
    // a / sin(a) = 1 + a^2/6 + 7 a^4/360
    const double a2 = a * a;
    return (1.0 + a2 / 6.0 + 7.0 * a2 * a2 / 360.0) * v;
  }
  if (cos_a > -0.5) {
    return (a / sin_a) * v;
  }
  // Near pi: sin(a) is small and inaccurate; read the axis from the symmetric part,
  // R + R^T - 2 cos(a) I = 2 (1 - cos a) n n^T, and take its sign from vee(R).
  const Mat3 S = 0.5 * (R + R.transpose()) - cos_a * Mat3::Identity();
  int k = 0;
  S.diagonal().maxCoeff(&k);
  Vec3 n = S.col(k) / std::sqrt(S(k, k));
  n.normalize();
  if (n.dot(v) < 0.0) n = -n;
  return a * n;
}

Vec3 DexpInv(const Vec3& u, const Vec3& v) {
  const double a2 = u.squaredNorm();
  double c;
  if (a2 < kSmallAngle * kSmallAngle) {
    c = 1.0 / 12.0 + a2 / 720.0;
  } else {
    const double a = std::sqrt(a2);
    const double half = 0.5 * a;
    c = (1.0 - half * std::cos(half) / std::sin(half)) / a2;
  }
  const Vec3 uxv = u.cross(v);
  return v + 0.5 * uxv + c * u.cross(uxv);
}

}  // namespace deploysim::math
