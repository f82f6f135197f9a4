#pragma once

/// Quaternion helpers. Hamilton convention; `q_NB` is the rotation whose matrix is
/// `R_NB` (v_N = q_NB * v_B). Outside the core (files, CLI) quaternions are always
/// scalar-first (w, x, y, z): ToWxyz/FromWxyz are the only conversions.

#include <string>

#include "deploysim/math/types.h"

namespace deploysim::math {

/// Scalar-first 4-vector (w, x, y, z) of q.
Vec4 ToWxyz(const Quat& q);

/// Quaternion from a scalar-first 4-vector (w, x, y, z). Not normalized.
Quat FromWxyz(const Vec4& wxyz);

/// The one rule for an attitude quaternion given to a library entry point (Integrate,
/// RunMission, FreeBodySolution): finite and of norm 1 within kUnitQuaternionTolerance.
/// Returns q normalized; throws std::invalid_argument naming `what`, the value and the
/// rule otherwise. (Files are the user's rounded text: a profile's `attitude_wxyz` is any
/// finite non-zero quaternion and is normalized on load, docs/file_formats.md; what
/// reaches the library is then unit to rounding.)
inline constexpr double kUnitQuaternionTolerance = 1e-12;
Quat ValidateUnitQuaternion(const Quat& q, const std::string& what);

/// Unit quaternion of the rotation by |phi| rad about phi/|phi| (exact series near 0).
Quat ExpQuat(const Vec3& phi);

/// Rotation vector of a unit quaternion (|result| <= pi; q and -q give the same result).
Vec3 LogQuat(const Quat& q);

/// Angle [rad] of the rotation q1^-1 q2, in [0, pi]; the same for -q1 or -q2.
double AngleBetween(const Quat& q1, const Quat& q2);

}  // namespace deploysim::math
