// The asymmetric cross-check model of models/asymmetric_sat.yaml, built in C++ without
// reading YAML: it must really be asymmetric (moving CoM, products of inertia, h_rel
// with three components), its tilted wing's tensor must be the rotated box the file
// says it is, and the folded wing must lie on its hub face.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "deploysim/math/inertia.h"
#include "deploysim/math/so3.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

constexpr double kDegree = M_PI / 180.0;
/// Agreement of the file's 17-digit literals with the formulas they came from (a few ulp).
constexpr double kLiteralTolerance = 4e-16;

/// Numbers duplicated from models/asymmetric_sat.yaml (keep both in step).
HingedBody AsymmetricBody() {
  HingedBody b;
  b.hub.body.mass = 80.0;
  b.hub.body.inertia_cm = BoxInertia(80.0, Vec3(0.6, 1.0, 0.8));
  b.hub.com_B = Vec3(0.02, -0.01, 0.03);
  Panel plus;
  plus.name = "wing_plus_x";
  plus.body.mass = 7.0;
  plus.body.inertia_cm = BoxInertia(7.0, Vec3(0.8, 1.0, 0.02));
  plus.hinge_point_B = Vec3(0.3, 0.0, 0.4);
  plus.hinge_axis_B = Vec3(0.0, 1.0, 0.0);
  plus.com_offset_B = Vec3(0.4, 0.0, 0.01);
  Panel minus;
  minus.name = "wing_minus_x";
  minus.body.mass = 4.0;
  minus.body.inertia_cm << 0.12013333333333333, 0, 0,  //
      0, 0.11343333333333332, -0.051903789200147349,   //
      0, -0.051903789200147349, 0.17336666666666667;
  minus.hinge_point_B = Vec3(-0.3, 0.1, -0.25);
  minus.hinge_axis_B = Vec3(0.0, 0.86602540378443865, 0.5);
  minus.com_offset_B = Vec3(-0.25, 0.005, -0.0086602540378443865);
  b.panels = {plus, minus};
  return ValidatedHingedBody(b, "models/asymmetric_sat.yaml (C++ copy)");
}

MassProperties At(const HingedBody& b, double deg, double rate_deg_s = 0.0) {
  return ComputeMassProperties(b, Eigen::Vector2d(deg, deg) * kDegree,
                               Eigen::Vector2d(rate_deg_s, rate_deg_s) * kDegree);
}

TEST(AsymmetricSatGeometryTest, TiltedWingIsTheRotatedBoxOfTheFile) {
  const double tilt = 30.0 * kDegree;
  const Vec3 e1(-1.0, 0.0, 0.0);
  const Vec3 e2(0.0, std::cos(tilt), std::sin(tilt));
  const Vec3 e3 = e1.cross(e2);
  Mat3 Q;
  Q << e1, e2, e3;
  const Mat3 I = Q * BoxInertia(4.0, Vec3(0.5, 0.6, 0.02)) * Q.transpose();
  const HingedBody body = AsymmetricBody();
  const Panel& minus = body.panels[1];
  EXPECT_LT((minus.body.inertia_cm - I).cwiseAbs().maxCoeff(), kLiteralTolerance);
  EXPECT_LT((minus.hinge_axis_B - e2).norm(), kLiteralTolerance);
  EXPECT_LT((minus.com_offset_B - (0.25 * e1 + 0.01 * e3)).norm(), kLiteralTolerance);
}

TEST(AsymmetricSatGeometryTest, StowedTiltedWingLiesOnItsFace) {
  // Corners of the stowed (90 deg) wing_minus_x mid-plane: on the plane x = -0.31 and
  // inside the -x face (|y| <= 0.5, |z| <= 0.4).
  const HingedBody body = AsymmetricBody();
  const Panel& p = body.panels[1];
  const Mat3 R = AxisAngle(p.hinge_axis_B, 90.0 * kDegree);
  const Vec3 e1(-1.0, 0.0, 0.0);
  const Vec3 e3 = e1.cross(p.hinge_axis_B);
  for (double along : {-0.3, 0.3}) {
    for (double out : {0.0, 0.5}) {
      const Vec3 corner = p.hinge_point_B + along * p.hinge_axis_B + R * (out * e1 + 0.01 * e3);
      EXPECT_NEAR(corner.x(), -0.31, 1e-15);
      EXPECT_LE(std::abs(corner.y()), 0.5 + 1e-12);
      EXPECT_LE(std::abs(corner.z()), 0.4 + 1e-12);
    }
  }
}

TEST(AsymmetricSatGeometryTest, ComMovesAndEveryProductOfInertiaAppears) {
  // A component counts as present above this fraction of its tensor's or vector's norm.
  constexpr double kPresent = 1e-4;
  const HingedBody b = AsymmetricBody();
  const MassProperties closed = At(b, 90.0);
  const MassProperties half = At(b, 45.0, -9.0);
  const MassProperties open = At(b, 0.0);
  EXPECT_DOUBLE_EQ(open.mass, 91.0);
  // The CoM moves by centimetres relative to the hub between stowed and deployed.
  EXPECT_GT((open.com_B - closed.com_B).norm(), 0.02);
  EXPECT_GT(half.com_rate_B.norm(), 1e-3);
  for (const MassProperties* mp : {&closed, &half, &open}) {
    EXPECT_NO_THROW(math::InertiaTensor::FromMatrix(mp->J_B));
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      EXPECT_GT(std::abs(half.J_B(i, j)), kPresent * half.J_B.norm()) << i << j;
      EXPECT_GT(std::abs(open.J_B(i, j)), kPresent * open.J_B.norm()) << i << j;
    }
  }
  // While deploying, the relative momentum has all three components.
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(std::abs(half.h_rel_B[i]), kPresent * half.h_rel_B.norm()) << i;
  }

  std::ostringstream os;
  os.precision(9);
  for (const auto& [name, mp] : {std::pair<const char*, const MassProperties*>{"closed", &closed},
                                 {"half_open", &half},
                                 {"open", &open}}) {
    const math::PrincipalAxes p = math::PrincipalDecomposition(mp->J_B);
    os << name << ": moments " << p.moments.transpose() << "; com " << mp->com_B.transpose()
       << "; axes (columns)\n"
       << p.axes << "\n";
  }
  RecordProperty("configurations", os.str());
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
