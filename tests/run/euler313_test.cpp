// The seed's appendix A.1 3-1-3 Euler angles of B relative to a frame whose third axis
// is h_N (precession, nutation, spin), including the singular nutations 0 and pi.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "deploysim/math/so3.h"
#include "deploysim/run/mission.h"

namespace deploysim::run {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

constexpr double kAngleTolerance = 1e-12;  // [rad]

math::Mat3 Rz(double a) { return math::ExpSO3(math::Vec3(0, 0, a)); }
math::Mat3 Rx(double a) { return math::ExpSO3(math::Vec3(a, 0, 0)); }

// The frame P used by Euler313RelativeToMomentum for h_N along +z is N itself, so
// R_NB = Rz(phi) Rx(theta) Rz(psi) must give back (phi, theta, psi).
TEST(Euler313Test, RecoversAnglesAboutMomentumAlongZ) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ang(-3.0, 3.0);
  std::uniform_real_distribution<double> nut(0.01, 3.13);
  const math::Vec3 h_N(0, 0, 2.5);
  for (int i = 0; i < 500; ++i) {
    const double phi = ang(rng), theta = nut(rng), psi = ang(rng);
    const math::Quat q(math::Mat3(Rz(phi) * Rx(theta) * Rz(psi)));
    const math::Vec3 e = Euler313RelativeToMomentum(q, h_N);
    EXPECT_NEAR(e[0], phi, kAngleTolerance);
    EXPECT_NEAR(e[1], theta, kAngleTolerance);
    EXPECT_NEAR(e[2], psi, kAngleTolerance);
  }
}

TEST(Euler313Test, NutationIsTheAngleBetweenBodyZAndMomentum) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const math::Quat q(math::ExpSO3(3.0 * math::Vec3(u(rng), u(rng), u(rng))));
    const math::Vec3 h_N(u(rng), u(rng), u(rng));
    const double expected =
        std::acos(std::clamp((q * math::Vec3::UnitZ()).dot(h_N.normalized()), -1.0, 1.0));
    EXPECT_NEAR(Euler313RelativeToMomentum(q, h_N)[1], expected,
                1e-7);  // acos is ill-conditioned near 0, pi
  }
}

TEST(Euler313Test, SingularNutationsPutTheRotationIntoPrecession) {
  const math::Vec3 h_N(0, 0, 1);
  // theta = 0: R = Rz(phi + psi); theta = pi: R = Rz(phi) Rx(pi) Rz(psi).
  const math::Vec3 e0 = Euler313RelativeToMomentum(math::Quat(math::Mat3(Rz(0.7) * Rz(0.4))), h_N);
  EXPECT_NEAR(e0[1], 0.0, kAngleTolerance);
  EXPECT_NEAR(e0[0] + e0[2], 1.1, kAngleTolerance);
  EXPECT_TRUE(std::isfinite(e0[0]) && std::isfinite(e0[2]));
  const math::Mat3 Rpi = Rz(0.7) * Rx(M_PI) * Rz(0.4);
  const math::Vec3 epi = Euler313RelativeToMomentum(math::Quat(Rpi), h_N);
  EXPECT_NEAR(epi[1], M_PI, kAngleTolerance);
  const math::Mat3 back = Rz(epi[0]) * Rx(epi[1]) * Rz(epi[2]);
  EXPECT_LT((back - Rpi).norm(), 1e-12);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::run
