// The initial spin as analysts give it (schedule/initial_spin.h): a body axis, a rate and
// a nutation (and its azimuth) resolved to H_B(t0). The resolved momentum's rate along
// the axis and its angle from the axis are checked against the request, the tilt's
// direction against the rule (the transverse momentum, else the next principal axis),
// hand-computed momenta for principal axes, and the refusals.

#include "deploysim/schedule/initial_spin.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "schedule_fixtures.h"

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Mat3;
using math::Vec3;

dynamics::InertiaSample Sample(const Mat3& J, const Vec3& h_rel = Vec3::Zero()) {
  dynamics::InertiaSample s;
  s.J_B = J;
  s.J_inv_B = J.inverse();
  s.h_rel_B = h_rel;
  s.Jdot_B.setZero();
  return s;
}

InitialSpin Spin(const Vec3& axis,
                 double rate,
                 std::optional<double> nutation = std::nullopt,
                 std::optional<double> azimuth = std::nullopt) {
  InitialSpin s;
  s.axis_B = axis;
  s.rate = rate;
  s.nutation = nutation;
  s.azimuth = azimuth;
  return s;
}

/// The rate along s of the angular velocity H gives, w = J^-1 (H - h_rel).
double RateAlong(const dynamics::InertiaSample& s0, const Vec3& H, const Vec3& s) {
  return (s0.J_inv_B * (H - s0.h_rel_B)).dot(s);
}

/// The angle of H from the unit axis s.
double Nutation(const Vec3& H, const Vec3& s) { return std::atan2(H.cross(s).norm(), H.dot(s)); }

// J = diag(1, 2, 3): a pure spin about a principal axis is H = J (rate s), exactly.
TEST(InitialSpinTest, APureSpinAboutAPrincipalAxisIsJTimesTheRate) {
  const dynamics::InertiaSample s0 = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal());
  EXPECT_EQ(SpinMomentum(s0, Spin(Vec3::UnitY(), 0.5)), Vec3(0.0, 1.0, 0.0));
  EXPECT_EQ(SpinMomentum(s0, Spin(-Vec3::UnitZ(), 0.5)), Vec3(0.0, 0.0, -1.5));
  // The axis is normalized: [0, 0, 4] is z.
  EXPECT_EQ(SpinMomentum(s0, Spin(Vec3(0.0, 0.0, 4.0), 2.0)), Vec3(0.0, 0.0, 6.0));
  // Nutation 0 given explicitly: the same.
  EXPECT_EQ(SpinMomentum(s0, Spin(Vec3::UnitX(), 0.5, 0.0)), Vec3(0.5, 0.0, 0.0));
}

// About a principal axis a pure spin has no transverse momentum: H tilts towards the next
// principal axis (ascending moments, cyclic): y (intermediate) towards z, z (major)
// towards x, x (minor) towards y, then turns about s by the azimuth, and is scaled so that
// w . s is the rate. By hand for s = y, rate r, nutation th, azimuth ph, J = diag(1, 2, 3):
// w_y = H_y / 2 = r, so H = 2 r (+-sin ph tan th, 1, +-cos ph tan th) (the sign that of
// the principal axis z the decomposition returns). Measured to 1.5e-16 relative; bound
// 4e-16.
TEST(InitialSpinTest, NutationAboutAPrincipalAxisTiltsTowardsTheNextAxis) {
  const dynamics::InertiaSample s0 = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal());
  const double r = 0.5, th = 0.3;
  const Vec3 H0 = SpinMomentum(s0, Spin(Vec3::UnitY(), r, th, 0.0));
  const double sign = H0.z() > 0.0 ? 1.0 : -1.0;
  double worst = 0.0;
  for (double ph : {0.0, 0.7, -2.0, 3.0}) {
    const Vec3 H = SpinMomentum(s0, Spin(Vec3::UnitY(), r, th, ph));
    const Vec3 expected =
        2.0 * r * Vec3(sign * std::sin(ph) * std::tan(th), 1.0, sign * std::cos(ph) * std::tan(th));
    worst = std::max(worst, (H - expected).norm() / expected.norm());
    EXPECT_LT((H - expected).norm(), 4e-16 * expected.norm()) << ph << ": " << H.transpose();
  }
  std::printf("principal-axis tilt against the hand-computed momentum: %.2e\n", worst);
  // z (major) tilts towards x, x (minor) towards y: the transverse part lies along them.
  const Vec3 Hz = SpinMomentum(s0, Spin(Vec3::UnitZ(), r, th, 0.0));
  EXPECT_EQ(Hz.y(), 0.0);
  EXPECT_NEAR(std::abs(Hz.x()), 3.0 * r * std::tan(th), 4e-16);
  EXPECT_NEAR(Hz.z(), 3.0 * r, 4e-16);
  const Vec3 Hx = SpinMomentum(s0, Spin(Vec3::UnitX(), r, th, 0.0));
  EXPECT_EQ(Hx.z(), 0.0);
  EXPECT_NEAR(std::abs(Hx.y()), 1.0 * r * std::tan(th), 4e-16);
  EXPECT_NEAR(Hx.x(), 1.0 * r, 4e-16);
}

// The same rule for a rotated inertia and an axis given along a rotated principal axis:
// the tilt lies in the plane of s and the next rotated axis.
TEST(InitialSpinTest, NutationFollowsTheRotatedPrincipalAxes) {
  const Mat3 R = Eigen::AngleAxisd(0.8, Vec3(0.3, -1.0, 0.6).normalized()).toRotationMatrix();
  const dynamics::InertiaSample s0 = Sample(R * Vec3(1.0, 2.0, 3.0).asDiagonal() * R.transpose());
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 s = R.col(axis);
    const Vec3 H = SpinMomentum(s0, Spin(s, 0.4, 0.2, 0.0));
    const Vec3 next = R.col((axis + 1) % 3);
    const Vec3 other = R.col((axis + 2) % 3);
    EXPECT_NEAR(H.dot(other), 0.0, 1e-15 * H.norm()) << axis;
    EXPECT_NEAR(std::abs(std::atan2(H.dot(next), H.dot(s))), 0.2, 1e-15) << axis;
    EXPECT_NEAR(RateAlong(s0, H, s), 0.4, 1e-15) << axis;
  }
}

// Any axis, rate, nutation and azimuth, with no relative momentum: the result's angle from
// the axis is the nutation and its rate along the axis the rate. s = (1, 1, 0)/sqrt 2 in
// J = diag(1, 2, 3) is no principal axis: a pure spin has the transverse momentum
// r (-1, 1, 0)/(2 sqrt 2), so the tilt stays in the x-y plane at azimuth 0 and leaves z
// at azimuth pi/2. Nutations up to 1 rad (larger ones: the disabled test below).
// Measured angle errors 2.0e-15 rad, rates 4.4e-16 relative; bounds 6e-15 and 1.5e-15.
TEST(InitialSpinTest, TheResolvedMomentumHasTheRequestedNutationAndRate) {
  const Vec3 s = Vec3(1.0, 1.0, 0.0).normalized();
  const dynamics::InertiaSample diag = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal());
  const Vec3 H = SpinMomentum(diag, Spin(s, 0.5, 0.25, 0.0));
  EXPECT_EQ(H.z(), 0.0);
  EXPECT_GT(H.dot(Vec3(-1.0, 1.0, 0.0)), 0.0);  // towards the transverse momentum
  const Vec3 Hq = SpinMomentum(diag, Spin(s, 0.5, 0.25, M_PI / 2));
  EXPECT_NEAR(std::abs(std::atan2(Hq.z(), Hq.dot(s))), 0.25, 1e-15);
  // No nutation given: a pure spin, J (r s), whose own tilt is kept.
  const Vec3 pure = SpinMomentum(diag, Spin(s, 0.5));
  EXPECT_LT((pure - 0.5 * Vec3(1.0, 2.0, 0.0) / std::sqrt(2.0)).norm(), 4e-16);

  const Mat3 R = Eigen::AngleAxisd(2.1, Vec3(1.0, 0.4, -0.2).normalized()).toRotationMatrix();
  const Mat3 J = R * Vec3(3.0, 4.5, 5.0).asDiagonal() * R.transpose();
  const dynamics::InertiaSample s0 = Sample(J);
  double worst_angle = 0.0, worst_rate = 0.0;
  for (const Vec3& axis :
       {Vec3(0.2, -0.9, 0.4), Vec3(1.0, 0.0, 0.0), Vec3(-0.3, 0.3, 0.9), Vec3(R.col(1))}) {
    const Vec3 su = axis.normalized();
    for (double nut : {0.0, 0.01, 0.5, 1.0}) {
      for (double az : {0.0, 1.0, -2.5}) {
        for (double rate : {0.05, 3.0}) {
          const Vec3 Hr = SpinMomentum(s0, Spin(axis, rate, nut, az));
          worst_angle = std::max(worst_angle, std::abs(Nutation(Hr, su) - nut));
          worst_rate = std::max(worst_rate, std::abs(RateAlong(s0, Hr, su) / rate - 1.0));
          EXPECT_NEAR(Nutation(Hr, su), nut, 6e-15) << axis.transpose() << " " << nut << " " << az;
          EXPECT_NEAR(RateAlong(s0, Hr, su), rate, 1.5e-15 * rate) << axis.transpose();
        }
      }
    }
  }
  std::printf("nutation error %.2e rad, rate error %.2e relative\n", worst_angle, worst_rate);
}

// The azimuth turns the tilt about s: the transverse parts of the results at azimuths a
// and b are a - b apart, in the right-handed sense about s.
TEST(InitialSpinTest, TheAzimuthTurnsTheTiltAboutTheAxis) {
  const Mat3 R = Eigen::AngleAxisd(2.1, Vec3(1.0, 0.4, -0.2).normalized()).toRotationMatrix();
  const dynamics::InertiaSample s0 = Sample(R * Vec3(3.0, 4.5, 5.0).asDiagonal() * R.transpose());
  const Vec3 s = Vec3(0.2, -0.9, 0.4).normalized();
  const Vec3 H0 = SpinMomentum(s0, Spin(s, 1.0, 0.3, 0.0));
  const Vec3 t0 = H0 - H0.dot(s) * s;
  for (double az : {0.5, 2.0, -1.0}) {
    const Vec3 H = SpinMomentum(s0, Spin(s, 1.0, 0.3, az));
    const Vec3 t = H - H.dot(s) * s;
    const double turned = std::atan2(t0.cross(t).dot(s), t0.dot(t));
    EXPECT_NEAR(turned, az, 1e-15) << az;
  }
}

// TiltMomentum alone: |H| is kept; with neither nutation nor azimuth H is unchanged; a
// given nutation replaces H's tilt, towards its own transverse direction.
TEST(InitialSpinTest, TiltMomentumKeepsTheMagnitude) {
  const Mat3 J = Vec3(1.0, 2.0, 3.0).asDiagonal();
  const Vec3 s = Vec3::UnitZ();
  const Vec3 H(0.3, -0.4, 2.0);
  EXPECT_LT((TiltMomentum(H, s, J, std::nullopt, std::nullopt) - H).norm(), 4e-16 * H.norm());
  const Vec3 T = TiltMomentum(H, s, J, 0.5, std::nullopt);
  EXPECT_NEAR(T.norm(), H.norm(), 4e-16 * H.norm());
  EXPECT_NEAR(Nutation(T, s), 0.5, 1e-15);
  // Towards (0.3, -0.4, 0) / 0.5: the transverse direction kept.
  EXPECT_NEAR(T.x() / T.y(), -0.75, 1e-15);
  // The present tilt turned by pi/2 about z: (0.4, 0.3, 2).
  EXPECT_LT((TiltMomentum(H, s, J, std::nullopt, M_PI / 2) - Vec3(0.4, 0.3, 2.0)).norm(), 1e-15);
}

// ScaleToSpinRate scales w (not H): H' = J (k w) + h_rel with k = rate / |w . s|; it
// refuses a momentum whose angular velocity has no component along s.
TEST(InitialSpinTest, ScaleToSpinRateScalesTheAngularVelocityAndRefusesNone) {
  const Vec3 h(0.1, 0.2, -0.3);
  const dynamics::InertiaSample s0 = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal(), h);
  const Vec3 s = Vec3::UnitY();
  const Vec3 H(1.1, 0.6, 2.7);  // w = (1, 0.2, 1)
  const Vec3 scaled = ScaleToSpinRate(H, s, s0, 0.5);
  EXPECT_LT((scaled - (Vec3(2.5, 1.0, 7.5) + h)).norm(), 1e-15) << scaled.transpose();
  EXPECT_NEAR(RateAlong(s0, scaled, s), 0.5, 1e-16);
  try {
    ScaleToSpinRate(Vec3(1.1, 0.2, 2.7), s, s0, 0.5);  // w = (1, 0, 1)
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "spin_rate: the base angular velocity has no component along the spin axis");
  }
  // A spin of rate 0 with no relative momentum has no momentum to scale.
  EXPECT_THROW(SpinMomentum(Sample(Vec3(1.0, 2.0, 3.0).asDiagonal()), Spin(Vec3::UnitY(), 0.0)),
               std::invalid_argument);
}

// A relative momentum (a rotor spinning at t0) enters the pure spin, H = J (r s) + h_rel,
// and the rate along s holds with a nutation too (measured 1e-16; bound 1e-15).
TEST(InitialSpinTest, TheRateHoldsWithARelativeMomentum) {
  const Vec3 h(0.1, 0.2, -0.3);
  const dynamics::InertiaSample s0 = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal(), h);
  EXPECT_LT((SpinMomentum(s0, Spin(Vec3::UnitY(), 0.5)) - (Vec3(0.0, 1.0, 0.0) + h)).norm(), 1e-16);
  for (const Vec3& hr : {Vec3(0.1, 0.2, -0.3), Vec3(0.0, 1.0, 0.0), Vec3(0.3, 0.0, 0.0)}) {
    const dynamics::InertiaSample sh = Sample(Vec3(1.0, 2.0, 3.0).asDiagonal(), hr);
    const Vec3 H = SpinMomentum(sh, Spin(Vec3::UnitY(), 0.5, 0.3, 0.7));
    EXPECT_NEAR(RateAlong(sh, H, Vec3::UnitY()), 0.5, 1e-15) << hr.transpose();
  }
}

// InitialInertia of a stage profile is its schedule at t_begin: the first configuration's
// tensor (diag(10, 6, 8) of the test's three-tensor model), no relative momentum.
TEST(InitialSpinTest, InitialInertiaOfAStageProfileIsItsFirstConfiguration) {
  const Profile p = testing::MakeProfile(testing::TensorModel(), Mode::kTensor,
                                         Coupling::kQuasiRigid, Law::kSmoothstep);
  const dynamics::InertiaSample s0 = InitialInertia(p);
  EXPECT_LT((s0.J_B - Mat3(Vec3(10.0, 6.0, 8.0).asDiagonal())).norm(), 1e-14);
  EXPECT_LT((s0.J_inv_B * s0.J_B - Mat3::Identity()).norm(), 1e-15);
  EXPECT_EQ(s0.h_rel_B, Vec3::Zero());
  // Its spin about y (the minor axis, 6) tilted 0.1 rad: towards the next axis, z (8).
  const Vec3 H = SpinMomentum(s0, Spin(Vec3::UnitY(), 0.5, 0.1, 0.0));
  EXPECT_NEAR(H.y(), 3.0, 1e-15);
  EXPECT_NEAR(std::abs(H.z()), 3.0 * std::tan(0.1), 1e-15);
  EXPECT_EQ(H.x(), 0.0);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
