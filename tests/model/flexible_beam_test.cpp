#include "deploysim/model/flexible_beam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "deploysim/model/mass_properties.h"

namespace deploysim::model {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using math::Vec3;

/// A 2 m boom of 0.5 kg/m, EI 10 N m^2, in one plane (bending about z).
BeamSpec Boom(int segments) {
  BeamSpec s;
  s.name = "boom";
  s.root_point = Vec3(0.5, 0, 0);
  s.direction = Vec3::UnitX();
  s.length = 2.0;
  s.mass_per_length = 0.5;
  s.radius = 0.005;
  s.planes = {BeamPlane{Vec3::UnitZ(), 10.0}};
  s.segments = segments;
  return s;
}

HingedBody Hub() {
  HingedBody b;
  b.hub.body.mass = 50.0;
  b.hub.body.inertia_cm = Eigen::Vector3d(5, 6, 7).asDiagonal();
  return b;
}

TEST(CantileverRoot, RootsOfTheFrequencyEquation) {
  // Tabulated values (e.g. Blevins, Formulas for Natural Frequency and Mode Shape, table 8-1).
  EXPECT_NEAR(CantileverRoot(1), 1.87510407, 1e-8);
  EXPECT_NEAR(CantileverRoot(2), 4.69409113, 1e-8);
  EXPECT_NEAR(CantileverRoot(3), 7.85475744, 1e-8);
  for (int n = 1; n <= 6; ++n) {
    const double x = CantileverRoot(n);
    EXPECT_NEAR(std::cos(x) * std::cosh(x), -1.0, 1e-9 * std::cosh(x));
  }
}

TEST(SouthwellCoefficient, UniformCantileverFirstMode) {
  // 1.193 at zero hub radius (Wright et al. 1982, table 1), growing ~linearly with r/L.
  EXPECT_NEAR(SouthwellCoefficient(0.0), 1.1933, 5e-4);
  const double slope = (SouthwellCoefficient(0.1) - SouthwellCoefficient(0.0)) / 0.1;
  EXPECT_NEAR(slope, 1.5709, 5e-3);
  // Linear in rho exactly (the Rayleigh quotient's numerator is).
  EXPECT_NEAR(SouthwellCoefficient(1.0), SouthwellCoefficient(0.0) + slope, 1e-10);
}

/// Relative errors of the clamped chain's first two frequencies at N segments.
std::vector<double> ChainErrors(int n) {
  HingedBody body = Hub();
  BeamSpec spec = Boom(n);
  // A thin section: with radius r the chain converges to the beam with the section's
  // rotary inertia (Rayleigh's), ~(beta_n r)^2 / 8 below Euler-Bernoulli's.
  spec.radius = 1e-5;
  const Appendage app = AddBeam(body, spec, "test");
  std::vector<double> e;
  for (int i = 0; i < 2; ++i) {
    e.push_back(app.chain_frequencies[0][static_cast<std::size_t>(i)] /
                    CantileverFrequency(spec, 0, i + 1) -
                1.0);
  }
  return e;
}

TEST(FlexibleBeam, ChainConvergesToEulerBernoulliAtSecondOrder) {
  // The table of docs/appendages.md: the error falls 4x per doubling of N.
  std::vector<std::vector<double>> e;
  for (int n : {4, 8, 16, 32, 64}) e.push_back(ChainErrors(n));
  for (std::size_t k = 1; k < e.size(); ++k) {
    for (int i = 0; i < 2; ++i) {
      const double order =
          std::log2(e[k - 1][static_cast<std::size_t>(i)] / e[k][static_cast<std::size_t>(i)]);
      // Measured: 2.014 and 2.051 from N = 4 to 8, then within 0.011 of 2.
      EXPECT_NEAR(order, 2.0, k == 1 ? 0.1 : 0.02) << "N " << (4 << k) << " mode " << i + 1;
    }
  }
  // The chain is stiffer than the beam (errors > 0): 0.23 / N^2 and 0.80 / N^2 measured.
  for (const std::vector<double>& ek : e) {
    EXPECT_GT(ek[0], 0.0);
    EXPECT_GT(ek[1], 0.0);
  }
  EXPECT_LT(e.back()[0], 1e-4);  // 5.6e-5 at N = 64
  EXPECT_LT(e.back()[1], 4e-4);  // 1.95e-4
}

TEST(FlexibleBeam, PanelsMassAndStiffness) {
  HingedBody body = Hub();
  const Appendage app = AddBeam(body, Boom(8), "test");
  ASSERT_EQ(body.panels.size(), 9u);  // stub + 8 segments
  EXPECT_EQ(app.root, 0);
  EXPECT_EQ(app.hinges.size(), 8u);
  double mass = 0.0;
  for (const Panel& p : body.panels) mass += p.body.mass;
  EXPECT_NEAR(mass, 1.0, 1e-14);                                    // 2 m of 0.5 kg/m
  for (double k : app.stiffness) EXPECT_DOUBLE_EQ(k, 10.0 / 0.25);  // EI / l
  for (double c : app.damping) EXPECT_EQ(c, 0.0);
  EXPECT_NO_THROW(ValidatedHingedBody(body, "test"));
}

TEST(FlexibleBeam, RayleighDampingGivesTheFirstModeItsRatio) {
  HingedBody body = Hub();
  BeamSpec spec = Boom(10);
  spec.damping_ratio = 0.02;
  const Appendage app = AddBeam(body, spec, "test");
  // c = 2 zeta k / omega_1: the first mode's ratio c omega_1 / (2 k) is zeta.
  EXPECT_NEAR(app.damping[0] * app.chain_frequencies[0][0] / (2.0 * app.stiffness[0]), 0.02, 1e-15);
}

TEST(FlexibleBeam, TwoPlanesUseMasslessLinks) {
  HingedBody body = Hub();
  BeamSpec spec = Boom(6);
  spec.planes = {BeamPlane{Vec3::UnitZ(), 10.0}, BeamPlane{Vec3::UnitY(), 40.0}};
  const Appendage app = AddBeam(body, spec, "test");
  ASSERT_EQ(body.panels.size(), 13u);  // stub + 6 (link + segment)
  EXPECT_EQ(app.hinges.size(), 12u);
  EXPECT_EQ(body.panels[1].body.mass, 0.0);
  EXPECT_EQ(body.panels[1].name, "boom_1a");
  EXPECT_EQ(body.panels[2].name, "boom_1b");
  EXPECT_NO_THROW(ValidatedHingedBody(body, "test"));
  // Each plane's chain is the one-plane chain of its own EI: 4x the stiffness, 2x the frequency.
  ASSERT_EQ(app.chain_frequencies.size(), 2u);
  EXPECT_NEAR(app.chain_frequencies[1][0] / app.chain_frequencies[0][0], 2.0, 1e-12);
}

TEST(FlexibleBeam, SegmentsFromAFrequencyTolerance) {
  HingedBody body = Hub();
  BeamSpec spec = Boom(0);
  spec.frequency_tolerance = 0.01;
  const Appendage app = AddBeam(body, spec, "test");
  // The smallest N meeting 1 % on both modes: N - 1 does not.
  const std::vector<double> e = ChainErrors(app.segments);
  const std::vector<double> before = ChainErrors(app.segments - 1);
  EXPECT_LE(std::max(std::abs(e[0]), std::abs(e[1])), 0.01);
  EXPECT_GT(std::max(std::abs(before[0]), std::abs(before[1])), 0.01);
}

TEST(FlexibleBeam, RefusesBadSpecs) {
  HingedBody body = Hub();
  BeamSpec spec = Boom(8);
  spec.planes[0].axis = Vec3(1, 0, 1);
  EXPECT_THROW(AddBeam(body, spec, "m.yaml: appendages[0]"), std::invalid_argument);
  spec = Boom(1);
  EXPECT_THROW(AddBeam(body, spec, "m"), std::invalid_argument);
  spec = Boom(8);
  spec.mass_per_length = -1;
  try {
    AddBeam(body, spec, "m.yaml: appendages[0]");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("m.yaml: appendages[0].mass_per_length = -1"),
              std::string::npos)
        << e.what();
  }
}

TEST(FlexibleBeam, ValidationRefusesAMasslessLeaf) {
  HingedBody body = Hub();
  Panel p;
  p.name = "link";
  p.body.mass = 0.0;
  p.body.inertia_cm.setZero();
  body.panels.push_back(p);
  EXPECT_THROW(ValidatedHingedBody(body, "test"), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::model
