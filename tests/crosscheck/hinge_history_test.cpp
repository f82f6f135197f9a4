// The replay inertia source (crosscheck/hinge_history.h): quintic Hermite interpolation
// of a recorded hinge history, consistent J_B(t), dJ_B/dt and h_rel_B(t).

#include "deploysim/crosscheck/hinge_history.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "deploysim/io/yaml_loader.h"
#include "deploysim/model/mass_properties.h"

namespace deploysim::crosscheck {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

// Interpolation of a quintic: exact to rounding (measured 4.4e-16 in the angle, 2.2e-15 in
// the rate).
constexpr double kExact = 1e-14;

model::HingedBody Smallsat() {
  const model::Model m = io::LoadModel(std::string(DEPLOYSIM_SOURCE_DIR) + "/models/smallsat.yaml");
  return model::ValidatedHingedBody(m.hinged, "smallsat");
}

// theta_k(t) = c0 + c1 t + ... + c5 t^5 (a different quintic per panel).
double Quintic(int k, double t, int derivative) {
  const double c[2][6] = {{1.5, -0.3, 0.02, 0.004, -0.0005, 0.00002},
                          {1.2, 0.1, -0.05, 0.003, 0.0002, -0.00001}};
  double v = 0.0;
  for (int n = derivative; n < 6; ++n) {
    double f = 1.0;
    for (int j = 0; j < derivative; ++j) f *= n - j;
    v += c[k][n] * f * std::pow(t, n - derivative);
  }
  return v;
}

HingeHistory QuinticHistory(const std::vector<double>& times) {
  HingeHistory h;
  for (double t : times) {
    Eigen::VectorXd q(2), v(2), a(2);
    for (int k = 0; k < 2; ++k) {
      q[k] = Quintic(k, t, 0);
      v[k] = Quintic(k, t, 1);
      a[k] = Quintic(k, t, 2);
    }
    h.time.push_back(t);
    h.angle.push_back(q);
    h.rate.push_back(v);
    h.acceleration.push_back(a);
  }
  return h;
}

TEST(HingeHistoryTest, ReproducesQuinticsExactly) {
  const HingeHistorySource src(Smallsat(), QuinticHistory({0.0, 0.7, 1.0, 2.5, 4.0}));
  double max_angle = 0.0, max_rate = 0.0;
  for (double t = 0.0; t <= 4.0; t += 0.05) {
    const HingeState s = src.Interpolate(t);
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(s.angle[k], Quintic(k, t, 0), kExact) << "t = " << t;
      EXPECT_NEAR(s.rate[k], Quintic(k, t, 1), kExact) << "t = " << t;
      max_angle = std::max(max_angle, std::abs(s.angle[k] - Quintic(k, t, 0)));
      max_rate = std::max(max_rate, std::abs(s.rate[k] - Quintic(k, t, 1)));
    }
  }
  std::cout << "measured max angle error " << max_angle << ", rate error " << max_rate << "\n";
}

TEST(HingeHistoryTest, ConvergesAtSixthOrderOnANonPolynomial) {
  auto error = [](int n) {
    HingeHistory h;
    for (int i = 0; i <= n; ++i) {
      const double t = 2.0 * i / n;
      Eigen::VectorXd q(2), v(2), a(2);
      q << std::sin(t), std::cos(t);
      v << std::cos(t), -std::sin(t);
      a << -std::sin(t), -std::cos(t);
      h.time.push_back(t);
      h.angle.push_back(q);
      h.rate.push_back(v);
      h.acceleration.push_back(a);
    }
    const HingeHistorySource src(Smallsat(), h);
    double e = 0.0;
    for (double t = 0.0; t <= 2.0; t += 0.0137)
      e = std::max(e, std::abs(src.Interpolate(t).angle[0] - std::sin(t)));
    return e;
  };
  const double e1 = error(4);
  const double e2 = error(8);
  std::cout << "measured e1 = " << e1 << ", e2 = " << e2 << ", ratio " << e1 / e2 << "\n";
  EXPECT_GT(e1 / e2, 40.0);  // 2^6 = 64
  EXPECT_LT(e2, 2e-8);       // measured 5.3e-9 (ratio 63)
}

TEST(HingeHistoryTest, EvaluateIsTheGeometryAtTheInterpolatedState) {
  const model::HingedBody body = Smallsat();
  const HingeHistorySource src(body, QuinticHistory({0.0, 1.0, 2.0, 3.0}));
  const double t = 1.37;
  const HingeState s = src.Interpolate(t);
  const model::MassProperties mp = model::ComputeMassProperties(body, s.angle, s.rate);
  const dynamics::InertiaSample e = src.Evaluate(t);
  std::cout << "measured J " << (e.J_B - mp.J_B).norm() / mp.J_B.norm() << ", h_rel "
            << (e.h_rel_B - mp.h_rel_B).norm() / mp.J_B.norm() << ", J_inv "
            << (e.J_inv_B * e.J_B - math::Mat3::Identity()).norm() << "\n";
  EXPECT_LE((e.J_B - mp.J_B).norm(), 1e-15 * mp.J_B.norm());
  EXPECT_LE((e.h_rel_B - mp.h_rel_B).norm(), 1e-15 * mp.J_B.norm());
  EXPECT_LE((e.J_inv_B * e.J_B - math::Mat3::Identity()).norm(), 5e-16);  // measured 1.1e-16
  // Jdot is the derivative of J (central difference).
  const double dt = 1e-5;
  const math::Mat3 dJ = (src.Evaluate(t + dt).J_B - src.Evaluate(t - dt).J_B) / (2 * dt);
  std::cout << "measured Jdot " << (dJ - e.Jdot_B).norm() / mp.J_B.norm() << "\n";
  EXPECT_LE((dJ - e.Jdot_B).norm(), 2e-11 * mp.J_B.norm());  // measured 6.4e-12 (rounding / dt)
}

TEST(HingeHistoryTest, KnotsAreBreakpointsAndEndsHold) {
  const HingeHistorySource src(Smallsat(), QuinticHistory({0.0, 1.0, 2.0, 3.0}));
  EXPECT_EQ(src.Breakpoints(0.0, 3.0), (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(src.Breakpoints(0.5, 2.0), (std::vector<double>{1.0}));
  // At the last knot the recorded rate; beyond it the end angle, at rest.
  EXPECT_NEAR(src.Interpolate(3.0, dynamics::Side::kLeft).rate[0], Quintic(0, 3.0, 1), kExact);
  EXPECT_EQ(src.Interpolate(3.5).rate.norm(), 0.0);
  EXPECT_NEAR(src.Interpolate(3.5).angle[0], Quintic(0, 3.0, 0), kExact);
}

TEST(HingeHistoryTest, RejectsBadHistories) {
  const model::HingedBody body = Smallsat();
  EXPECT_THROW(HingeHistorySource(body, QuinticHistory({0.0})), std::invalid_argument);
  EXPECT_THROW(HingeHistorySource(body, QuinticHistory({0.0, 1.0, 1.0})), std::invalid_argument);
  HingeHistory wrong = QuinticHistory({0.0, 1.0});
  wrong.angle[1] = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(HingeHistorySource(body, wrong), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::crosscheck
