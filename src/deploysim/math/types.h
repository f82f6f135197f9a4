#pragma once

/// Fixed-size Eigen types shared by every module. Units and frames are carried by
/// variable names (docs/design.md section 1): `R_NB`, `w_NB_B`, `H_B`, `J_B`.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace deploysim::math {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
/// Hamilton unit quaternion. Eigen stores (x, y, z, w); files and the CLI use
/// scalar-first (w, x, y, z): convert only with quaternion.h's ToWxyz/FromWxyz.
using Quat = Eigen::Quaterniond;

}  // namespace deploysim::math
