// Sweep parameters over a model's appendages (docs/sweeps.md: bending_stiffness,
// bending_stiffness_scale, damping_ratio, fill_fraction): a case's generated hinges get
// the springs and dampers the beam's formulas give for the case's values, a tank's
// pendulum follows its fill fraction, and targets that do not fit are refused naming the
// file, key, value and rule.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/model/slosh.h"
#include "deploysim/sweep/sweep_file.h"
#include "deploysim/sweep/sweep_spec.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::SweepDirTest;

constexpr double kRoundoff = 1e-13;  // relative: a few roundings

// A wing on a spring, a two-plane boom (EI 20 and 30 N m^2), a one-plane boom, a tank
// given by its geometry and a damping ratio, and a tank given by its damper. Each boom is
// 2 m in 6 segments: l = 1/3 m, k = EI / l.
const char* const kModel = R"(name: booms_and_tanks
kind: hinged
hub: {mass: 50.0, box: [0.8, 0.8, 0.6]}
panels:
  - {name: wing, mass: 2.0, box: [0.6, 0.4, 0.02], hinge_point: [0, 0.4, 0.3],
     hinge_axis: [1, 0, 0], com_offset: [0, 0.3, 0.01]}
appendages:
  - {name: boom_px, kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20},
     {axis: [0, 0, 1], EI: 30}], damping_ratio: 0.01, segments: 6}
  - {name: boom_mx, kind: beam, root: [-0.4, 0, 0], direction: [-1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20}],
     damping_ratio: 0.01, segments: 6}
  - {name: tank, kind: slosh, direction: [0, -1, 0], axis: [0, 0, 1], damping_ratio: 0.02,
     spin_rate_rpm: 10, spin_radius: 0.2,
     tank: {shape: cylinder, center: [0, -0.2, 0], diameter: 0.3, height: 0.2,
            liquid_mass_full: 10, fill_fraction: 0.5}}
  - {name: drum, kind: slosh, pivot: [0, 0.1, -0.1], direction: [0, 1, 0], mass: 1,
     length: 0.05, damping: 0.001}
configurations:
  stowed: {hinge_angles_deg: [-60, 0, 0]}
)";

const char* const kProfile = R"(name: p
model: m.yaml
initial: {configuration: stowed, spin: {axis: z, rate_rpm: 10, nutation_deg: 2}}
until: 20
hinges:
  wing:
    free:
      release: {at: 1}
      spring: {stiffness: 2.0, rest_angle_deg: 10}
      latch: {angle_deg: 0}
)";

class AppendageSweepTest : public SweepDirTest {
 protected:
  void SetUp() override {
    SweepDirTest::SetUp();
    Write("m.yaml", kModel);
    Write("p.yaml", kProfile);
  }
  SweepSpec Load(const std::string& body) {
    return LoadSweep(Write("s.yaml", "name: s\nbase: p.yaml\n" + body));
  }
  std::string Refusal(const std::string& body) {
    try {
      (void)Load(body);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  }
};

const model::Appendage& Named(const schedule::Profile& p, const std::string& name) {
  for (const model::Appendage& a : p.model.appendages) {
    if (a.name == name) return a;
  }
  throw std::logic_error("no appendage " + name);
}

/// The beam's hinges carry k = EI_plane / l and c = 2 zeta k / omega_1 (omega_1 the
/// chain's first clamped frequency in the hinge's plane), and the case's plans are theirs.
void ExpectBeam(const schedule::Profile& p,
                const std::string& name,
                const std::vector<double>& EI,
                double zeta) {
  const model::Appendage& a = Named(p, name);
  const double l = 2.0 / 6.0;
  ASSERT_EQ(a.hinges.size(), 6 * EI.size());
  for (std::size_t i = 0; i < a.hinges.size(); ++i) {
    const std::size_t plane = i % EI.size();  // a two-plane joint's hinges come together
    const double k = EI[plane] / l;
    EXPECT_NEAR(a.stiffness[i], k, kRoundoff * k) << name << " hinge " << i;
    const double c = 2.0 * zeta * k / a.chain_frequencies[plane][0];
    EXPECT_NEAR(a.damping[i], c, kRoundoff * c) << name << " hinge " << i;
    const schedule::FreeDrive& d = p.hinges[static_cast<std::size_t>(a.hinges[i])].drive;
    EXPECT_EQ(d.spring.stiffness, a.stiffness[i]);
    EXPECT_EQ(d.damping, a.damping[i]);
  }
  // The chain's first frequency is Euler-Bernoulli's for the case's EI to the 6-segment
  // chain's error (~1/N^2).
  for (std::size_t plane = 0; plane < EI.size(); ++plane) {
    const double w_eb = 1.8751040687 * 1.8751040687 * std::sqrt(EI[plane] / (0.2 * 16.0));
    EXPECT_NEAR(a.chain_frequencies[plane][0], w_eb, 0.03 * w_eb) << name;
  }
}

TEST_F(AppendageSweepTest, BendingStiffnessAndDampingRatioSetTheBeamsHinges) {
  const SweepSpec spec = Load(R"(
grid:
  - {parameter: bending_stiffness, appendage: boom_mx, values: [5, 80]}
  - {parameter: bending_stiffness_scale, logspace: [0.5, 2, 2]}
  - {parameter: damping_ratio, appendage: boom_px, values: [0.05]}
  - {parameter: damping, values: [0.3]}
)");
  std::vector<std::string> columns, units;
  for (const Target& t : spec.targets()) {
    columns.push_back(t.column);
    units.push_back(UnitsOf(t.parameter));
  }
  EXPECT_EQ(columns,
            (std::vector<std::string>{"bending_stiffness[boom_mx]", "bending_stiffness_scale",
                                      "damping_ratio[boom_px]", "damping"}));
  EXPECT_EQ(units, (std::vector<std::string>{"N m^2", "1", "1", "N m s/rad"}));
  ExpectBeam(spec.base, "boom_px", {20, 30}, 0.01);
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const Case c = BuildCase(spec, i);
    const std::vector<double>& v = c.parameters.values;
    SCOPED_TRACE(DescribeParameters(spec, c.parameters));
    // The value set first, then every beam's EI scaled.
    ExpectBeam(c.profile(), "boom_mx", {v[0] * v[1]}, 0.01);
    ExpectBeam(c.profile(), "boom_px", {20 * v[1], 30 * v[1]}, 0.05);
    // damping without panel: the wing, not the appendages' generated hinges.
    EXPECT_EQ(c.profile().hinges[0].drive.damping, 0.3);
    const model::Appendage& drum = Named(c.profile(), "drum");
    EXPECT_EQ(c.profile().hinges[static_cast<std::size_t>(drum.hinges[0])].drive.damping, 0.001);
  }
}

TEST_F(AppendageSweepTest, FillFractionSetsTheTanksPendulum) {
  const SweepSpec spec = Load(R"(
grid:
  - {parameter: fill_fraction, appendage: tank, values: [0.1, 0.5, 1]}
  - {parameter: damping_ratio, appendage: tank, values: [0.02, 0.1]}
)");
  const double base_hub = spec.base.model.declared.hub.body.mass;
  const double drum_m0 = 0.0;  // the drum has no fixed mass
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const Case c = BuildCase(spec, i);
    const std::vector<double>& v = c.parameters.values;
    SCOPED_TRACE(DescribeParameters(spec, c.parameters));
    // NASA SP-106 / Dodge 2000, upright cylinder: d = 0.3 m, h = f 0.2 m, 10 kg full.
    const double d = 0.3;
    const double h = v[0] * 0.2;
    const double liquid = v[0] * 10.0;
    const double m1 = liquid * d / (4.4 * h) * std::tanh(3.68 * h / d);
    const double L1 = d / 3.68 / std::tanh(3.68 * h / d);
    const model::Appendage& tank = Named(c.profile(), "tank");
    const model::Panel& bob =
        c.profile().model.hinged.panels[static_cast<std::size_t>(tank.hinges[1])];
    EXPECT_NEAR(bob.body.mass, m1, kRoundoff * m1);
    EXPECT_NEAR(bob.com_offset_B.norm(), L1, kRoundoff * L1);
    EXPECT_NEAR(c.profile().model.hinged.hub.body.mass, base_hub + liquid - m1 + drum_m0,
                kRoundoff * base_hub);
    // c = 2 zeta omega_out m1 L1^2, omega_out = Omega sqrt((r + L1) / L1), 10 rpm, r = 0.2.
    const double omega = 10.0 * 2.0 * M_PI / 60.0;
    const double c_expected = 2.0 * v[1] * omega * std::sqrt((0.2 + L1) / L1) * m1 * L1 * L1;
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(tank.damping[k], c_expected, kRoundoff * c_expected);
      EXPECT_EQ(c.profile().hinges[static_cast<std::size_t>(tank.hinges[k])].drive.damping,
                tank.damping[k]);
    }
  }
  // A fuller tank is a heavier craft: the case's J_B(t0) follows the hub's mass.
  EXPECT_LT(BuildCase(spec, 0).profile().model.hinged.hub.body.mass,
            BuildCase(spec, 4).profile().model.hinged.hub.body.mass);
}

TEST_F(AppendageSweepTest, ACaseWithoutAppendageParametersKeepsTheBaseModel) {
  const SweepSpec spec = Load("grid:\n  - {parameter: spin_rate_rpm, values: [5]}\n");
  const Case c = BuildCase(spec, 0);
  EXPECT_EQ(c.profile().model.appendages[0].beam, spec.base.model.appendages[0].beam);
  EXPECT_EQ(c.profile().model.appendages[0].stiffness, spec.base.model.appendages[0].stiffness);
}

TEST_F(AppendageSweepTest, TheShippedSloshDampingSweepLoads) {
  // sweeps/spin_stabilized_tank_slosh_damping.yaml: both tanks' dampers follow the ratio
  // (c = 2 zeta omega_out m1 L1^2: proportional to zeta for the same tank).
  const SweepSpec spec = LoadSweep(std::string(DEPLOYSIM_SOURCE_DIR) +
                                   "/sweeps/spin_stabilized_tank_slosh_damping.yaml");
  ASSERT_EQ(spec.case_count(), 2u);
  ASSERT_EQ(spec.targets().front().column, "damping_ratio");
  const Case bare = BuildCase(spec, 0);
  const Case baffled = BuildCase(spec, 1);
  for (const std::string tank : {"tank_px", "tank_mx"}) {
    const double c_bare = Named(bare.profile(), tank).damping[0];
    const double c_baffled = Named(baffled.profile(), tank).damping[0];
    EXPECT_NEAR(c_baffled, 10.0 * c_bare, kRoundoff * c_baffled) << tank;
    EXPECT_EQ(c_baffled, Named(spec.base, tank).damping[0]) << tank;  // the model's 5 %
  }
}

TEST_F(AppendageSweepTest, BadTargetsAreRefused) {
  auto grid = [this](const std::string& axis) { return Refusal("grid:\n  - " + axis + "\n"); };
  EXPECT_NE(grid("{parameter: bending_stiffness, appendage: boom_pz, values: [1]}")
                .find("s.yaml: grid[0].appendage = boom_pz: no appendage of that name in model "
                      "'booms_and_tanks' (appendages: boom_px, boom_mx, tank, drum)"),
            std::string::npos)
      << grid("{parameter: bending_stiffness, appendage: boom_pz, values: [1]}");
  EXPECT_NE(grid("{parameter: bending_stiffness, appendage: tank, values: [1]}")
                .find("grid[0].appendage = tank: bending_stiffness applies to beams (of model "
                      "'booms_and_tanks': boom_px, boom_mx)"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: fill_fraction, appendage: drum, values: [0.5]}")
                .find("fill_fraction applies to slosh pendulums given by a tank"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: fill_fraction, values: [0.5]}")
                .find("grid[0].parameter = fill_fraction: fill_fraction applies to every "
                      "appendage of its kinds without `appendage:`, but slosh pendulum 'drum'"),
            std::string::npos)
      << grid("{parameter: fill_fraction, values: [0.5]}");
  EXPECT_NE(grid("{parameter: damping_ratio, values: [0.1]}").find("'drum'"), std::string::npos);
  EXPECT_NE(grid("{parameter: fill_fraction, appendage: tank, values: [0.5, 1.5]}")
                .find("s.yaml: grid[0].values[1] = 1.5: fill_fraction must be in (0, 1]"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: fill_fraction, appendage: tank, values: [0]}")
                .find("grid[0].values[0] = 0: fill_fraction must be in (0, 1]"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: damping_ratio, appendage: boom_px, values: [1]}")
                .find("grid[0].values[0] = 1: damping_ratio must be in [0, 1)"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: bending_stiffness_scale, appendage: boom_px, values: [0]}")
                .find("bending_stiffness_scale must be > 0"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: spring_stiffness, appendage: boom_px, values: [1]}")
                .find("grid[0].appendage = boom_px: not used by parameter spring_stiffness"),
            std::string::npos);
  EXPECT_NE(grid("{parameter: damping, panel: boom_mx_1, values: [1]}")
                .find("grid[0].panel = boom_mx_1: a hinge generated by appendage boom_mx"),
            std::string::npos)
      << grid("{parameter: damping, panel: boom_mx_1, values: [1]}");
  EXPECT_EQ(grid("{parameter: fill_fraction, appendage: tank, values: [1]}"), "accepted");
  // A base without appendages.
  const std::string spring =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_spring_deploy.yaml";
  try {
    (void)LoadSweep(Write(
        "t.yaml",
        "name: t\nbase: " + spring + "\ngrid:\n  - {parameter: bending_stiffness, values: [1]}\n"));
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("t.yaml: grid[0].parameter = bending_stiffness: "
                                         "bending_stiffness applies to the model's beams; model "
                                         "'smallsat' has none"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
