#pragma once

/// For the model's own computations (mass_properties.cc, mass_matrix.cc): the inertia of a
/// unit point mass and the rotation about a unit axis, written out (measured 3x faster than
/// Eigen's 3x3 outer products and AngleAxis here; they run at every Runge-Kutta stage).

#include <cmath>

#include "deploysim/math/types.h"

namespace deploysim::model::geometry {

/// S(d) = |d|^2 I - d d^T: the inertia [kg m^2 per kg] of a unit point mass at d.
inline math::Mat3 PointInertia(const math::Vec3& d) {
  const double xx = d.x() * d.x();
  const double yy = d.y() * d.y();
  const double zz = d.z() * d.z();
  const double xy = d.x() * d.y();
  const double xz = d.x() * d.z();
  const double yz = d.y() * d.z();
  math::Mat3 S;
  S << yy + zz, -xy, -xz,  //
      -xy, xx + zz, -yz,   //
      -xz, -yz, xx + yy;
  return S;
}

/// Rodrigues: R = cos(t) I + sin(t) [a]x + (1 - cos(t)) a a^T for a unit axis a.
inline math::Mat3 UnitAxisRotation(const math::Vec3& a, double angle) {
  const double s = std::sin(angle);
  const double c = std::cos(angle);
  const double v = 1.0 - c;
  const double x = a.x();
  const double y = a.y();
  const double z = a.z();
  math::Mat3 R;
  R << c + v * x * x, v * x * y - s * z, v * x * z + s * y,  //
      v * x * y + s * z, c + v * y * y, v * y * z - s * x,   //
      v * x * z - s * y, v * y * z + s * x, c + v * z * z;
  return R;
}

}  // namespace deploysim::model::geometry
