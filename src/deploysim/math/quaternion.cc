#include "deploysim/math/quaternion.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace deploysim::math {

Vec4 ToWxyz(const Quat& q) { return Vec4(q.w(), q.x(), q.y(), q.z()); }

Quat FromWxyz(const Vec4& wxyz) { return Quat(wxyz[0], wxyz[1], wxyz[2], wxyz[3]); }

Quat ValidateUnitQuaternion(const Quat& q, const std::string& what) {
  const double n = q.norm();
  if (!q.coeffs().allFinite() || !(std::abs(n - 1.0) <= kUnitQuaternionTolerance)) {
    std::ostringstream os;
    os.precision(17);
    os << what << " = (" << q.w() << ", " << q.x() << ", " << q.y() << ", " << q.z()
       << ") has norm " << n
       << " (rule: a finite unit quaternion, | |q| - 1 | <= " << kUnitQuaternionTolerance << ")";
    throw std::invalid_argument(os.str());
  }
  return q.normalized();
}

Quat ExpQuat(const Vec3& phi) {
  const double a2 = phi.squaredNorm();
  const double half2 = 0.25 * a2;
  double c;  // cos(a/2)
  double s;  // sin(a/2)/a
  if (a2 < 1e-8) {
    c = 1.0 - half2 / 2.0 * (1.0 - half2 / 12.0);
    s = 0.5 * (1.0 - half2 / 6.0 * (1.0 - half2 / 20.0));
  } else {
    const double a = std::sqrt(a2);
    c = std::cos(0.5 * a);
    s = std::sin(0.5 * a) / a;
  }
  return Quat(c, s * phi.x(), s * phi.y(), s * phi.z());
}

Vec3 LogQuat(const Quat& q_in) {
  Quat q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Vec3 v = q.vec();
  const double s = v.norm();
  // angle = 2 atan2(|v|, w); with a series for tiny |v| to keep v's direction exact.
  if (s < 1e-8) {
    return (2.0 / q.w()) * (1.0 - s * s / (3.0 * q.w() * q.w())) * v;
  }
  return (2.0 * std::atan2(s, q.w()) / s) * v;
}

double AngleBetween(const Quat& q1, const Quat& q2) { return LogQuat(q1.conjugate() * q2).norm(); }

}  // namespace deploysim::math
