// Sweep files (docs/sweeps.md): reading, case numbering, parameter application, the
// Monte Carlo streams, and the rejection of invalid files (one line naming the file, the
// key, the value and the rule, as for profiles).

#include "deploysim/sweep/sweep_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <ostream>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/run/mission.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/schedule/initial_spin.h"
#include "deploysim/sweep/sweep_spec.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::SmallsatProfile;
using testing::SpringProfile;
using testing::SweepDirTest;

constexpr double kRpm = 2.0 * M_PI / 60.0;
constexpr double kDeg = M_PI / 180.0;
constexpr double kTight = 1e-12;  // relative: values that are computed, not measured

std::string Header() {
  return "name: test\nbase: " + SmallsatProfile() +
         "\nintegrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}\n";
}

/// The start of a sweep over the spring deployment (a hinge profile).
std::string HingeHeader() { return "name: test\nbase: " + SpringProfile() + "\n"; }

const char* const kGridAndMonteCarlo = R"(
grid:
  - {parameter: deploy_duration_scale, values: [0.5, 1, 2]}
  - {parameter: spin_rate_rpm, linspace: [2, 6, 3]}
monte_carlo:
  samples: 4
  seed: 7
  parameters:
    - {parameter: panel_mass_scale, panel: wing_plus_x, normal: {mean: 1, sigma: 0.05, min: 0.8, max: 1.2}}
    - {parameter: nutation_deg, uniform: [0.5, 3]}
    - {parameter: law, choice: [smoothstep, minimum-jerk]}
)";

TEST_F(SweepDirTest, ReadsGridAndMonteCarlo) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", Header() + kGridAndMonteCarlo));
  EXPECT_EQ(spec.name, "test");
  EXPECT_EQ(spec.grid_points(), 9u);
  EXPECT_EQ(spec.samples(), 4u);
  EXPECT_EQ(spec.case_count(), 36u);
  std::vector<std::string> columns;
  for (const Target& t : spec.targets()) columns.push_back(t.column);
  EXPECT_EQ(columns,
            (std::vector<std::string>{"deploy_duration_scale", "spin_rate",
                                      "panel_mass_scale[wing_plus_x]", "nutation", "law"}));
  EXPECT_EQ(spec.base.integrator.method, "exact");
  EXPECT_EQ(spec.base.integrator.rtol, 1e-9);
  ASSERT_EQ(spec.grid[1].values.size(), 3u);
  EXPECT_NEAR(spec.grid[1].values[1], 4 * kRpm, kTight);
  EXPECT_EQ(spec.grid[1].values[2], 6 * kRpm);

  // Case 21 = grid point 5 (axis 0 index 1, axis 1 index 2), sample 1.
  const CaseParameters p = ParametersOf(spec, 21);
  EXPECT_EQ(p.grid_index, 5u);
  EXPECT_EQ(p.sample_index, 1u);
  EXPECT_EQ(p.values[0], 1.0);
  EXPECT_EQ(p.values[1], 6 * kRpm);
  // Common random numbers: sample 1 has the same draws at every grid point.
  const CaseParameters q = ParametersOf(spec, 1);
  for (std::size_t k = 2; k < 5; ++k) EXPECT_EQ(p.values[k], q.values[k]);
  // Draws within their bounds.
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const CaseParameters c = ParametersOf(spec, i);
    EXPECT_GE(c.values[2], 0.8);
    EXPECT_LE(c.values[2], 1.2);
    EXPECT_GE(c.values[3], 0.5 * kDeg);
    EXPECT_LT(c.values[3], 3 * kDeg);
    EXPECT_TRUE(c.values[4] == 2.0 || c.values[4] == 3.0);  // smoothstep, minimum-jerk
  }
  EXPECT_THROW(ParametersOf(spec, 36), std::out_of_range);
}

TEST_F(SweepDirTest, ChoicesAreEquallyLikely) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", Header() + R"(
monte_carlo:
  samples: 400
  seed: 3
  parameters:
    - {parameter: law, choice: [linear, smoothstep, minimum-jerk]}
)"));
  std::vector<int> counts(4, 0);
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    ++counts[static_cast<std::size_t>(ParametersOf(spec, i).values[0])];
  }
  EXPECT_EQ(counts[0], 0);  // step is not among the choices
  for (int k = 1; k < 4; ++k) EXPECT_NEAR(counts[k], 133, 40) << k;
}

TEST_F(SweepDirTest, CaseProfilesApplyTheParameters) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", Header() + kGridAndMonteCarlo));
  const schedule::Profile& base = spec.base;
  for (std::size_t i : {0u, 21u, 35u}) {
    const Case c = BuildCase(spec, i);
    const std::vector<double>& v = c.parameters.values;
    const schedule::Profile& p = c.profile();
    // Timing: move stages scaled, holds kept, stages contiguous from 0.
    ASSERT_EQ(p.stages.size(), base.stages.size());
    EXPECT_EQ(p.stages[0].t_begin, 0.0);
    for (std::size_t k = 0; k < p.stages.size(); ++k) {
      const double d0 = base.stages[k].t_end - base.stages[k].t_begin;
      const double d = p.stages[k].t_end - p.stages[k].t_begin;
      EXPECT_NEAR(d, base.stages[k].is_hold() ? d0 : d0 * v[0], kTight * 600) << "stage " << k;
      if (k > 0) {
        EXPECT_EQ(p.stages[k].t_begin, p.stages[k - 1].t_end);
        if (!p.stages[k].is_hold()) {
          EXPECT_EQ(schedule::ToString(p.stages[k].law),
                    CategoriesOf(Parameter::kLaw)[static_cast<std::size_t>(v[4])]);
        }
      }
    }
    // Model: wing_plus_x mass scaled, the other wing kept.
    EXPECT_NEAR(p.model.hinged.panels[0].body.mass, 6.0 * v[2], kTight);
    EXPECT_EQ(p.model.hinged.panels[1].body.mass, 6.0);
    // Initial state: spin rate about s and nutation of H_B from s.
    const dynamics::InertiaSample s0 = c.run->schedule()->Evaluate(0.0);
    ASSERT_TRUE(p.initial.H_B.has_value());
    EXPECT_FALSE(p.initial.w_NB_B.has_value());
    const math::Vec3 H = *p.initial.H_B;
    const math::Vec3 w = s0.J_inv_B * H;
    EXPECT_NEAR(w.dot(c.spin_axis_B), v[1], kTight * v[1]);
    EXPECT_NEAR(std::acos(H.normalized().dot(c.spin_axis_B)), v[3], 1e-9);
    // The spin axis is body y (the smallsat spins about y).
    EXPECT_NEAR(c.spin_axis_B.y(), 1.0, kTight);
  }
}

TEST_F(SweepDirTest, StageDurationAndCouplingAndAzimuth) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", Header() + R"(
grid:
  - {parameter: stage_duration, stage: full deploy, values: [5, 40]}
  - {parameter: coupling, values: [quasi-rigid, exact]}
  - {parameter: nutation_azimuth_deg, values: [0, 90]}
)"));
  EXPECT_EQ(spec.case_count(), 8u);
  EXPECT_EQ(spec.targets()[0].column, "stage_duration[3]");
  const Case a = BuildCase(spec, 0);  // 5 s, quasi-rigid, azimuth 0
  const Case b = BuildCase(spec, 7);  // 40 s, exact, azimuth 90
  EXPECT_EQ(a.profile().stages[3].t_end - a.profile().stages[3].t_begin, 5.0);
  EXPECT_EQ(b.profile().stages[3].t_end - b.profile().stages[3].t_begin, 40.0);
  EXPECT_EQ(a.profile().stages[4].t_end - a.profile().stages[4].t_begin, 440.0);  // hold kept
  EXPECT_EQ(a.profile().coupling, schedule::Coupling::kQuasiRigid);
  EXPECT_EQ(b.profile().coupling, schedule::Coupling::kExact);
  // Azimuth turns the transverse momentum about s by 90 deg, keeping the nutation.
  const math::Vec3 s = a.spin_axis_B;
  const math::Vec3 ta = *a.profile().initial.H_B - a.profile().initial.H_B->dot(s) * s;
  const math::Vec3 tb = *b.profile().initial.H_B - b.profile().initial.H_B->dot(s) * s;
  EXPECT_NEAR(ta.normalized().dot(tb.normalized()), 0.0, 1e-12);
  EXPECT_NEAR(ta.norm(), tb.norm(), 1e-12 * ta.norm());
}

TEST_F(SweepDirTest, LogspaceEndpointsAreExact) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", Header() + R"(
grid:
  - {parameter: deploy_duration_scale, logspace: [0.1, 3, 5]}
)"));
  ASSERT_EQ(spec.grid[0].values.size(), 5u);
  EXPECT_EQ(spec.grid[0].values.front(), 0.1);
  EXPECT_EQ(spec.grid[0].values.back(), 3.0);
  EXPECT_NEAR(spec.grid[0].values[2], std::sqrt(0.3), 1e-15);
}

TEST_F(SweepDirTest, TheExampleSweepLoads) {
  const SweepSpec spec =
      LoadSweep(std::string(DEPLOYSIM_SOURCE_DIR) + "/sweeps/smallsat_duration_spin.yaml");
  EXPECT_EQ(spec.case_count(), 480u);
  EXPECT_EQ(spec.grid.size(), 2u);
}

// ---- Hinge profiles ----

TEST_F(SweepDirTest, HingeParametersAreApplied) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", HingeHeader() + R"(
grid:
  - {parameter: spring_stiffness, values: [0.5, 2]}
  - {parameter: spin_rate_rpm, values: [2, 7]}
  - {parameter: damping, panel: wing_plus_x, values: [0.1]}
monte_carlo:
  samples: 3
  seed: 5
  parameters:
    - {parameter: latch_angle_deg, panel: wing_minus_x, uniform: [-1, 1]}
    - {parameter: friction_torque, uniform: [0, 0.05]}
    - {parameter: release_time, panel: wing_plus_x, uniform: [30, 90]}
    - {parameter: release_delay, panel: wing_minus_x, uniform: [0, 10]}
    - {parameter: stick_fraction, panel: wing_minus_x, uniform: [0.5, 0.9]}
    - {parameter: spring_stiffness_scale, panel: wing_minus_x, normal: {mean: 1, sigma: 0.1, min: 0.5, max: 1.5}}
    - {parameter: motor_torque, panel: wing_plus_x, uniform: [-0.1, 0]}
)"));
  EXPECT_EQ(spec.case_count(), 12u);
  std::vector<std::string> columns, units;
  for (const Target& t : spec.targets()) {
    columns.push_back(t.column);
    units.push_back(UnitsOf(t.parameter));
  }
  EXPECT_EQ(columns,
            (std::vector<std::string>{
                "spring_stiffness", "spin_rate", "damping[wing_plus_x]",
                "latch_angle[wing_minus_x]", "friction_torque", "release_time[wing_plus_x]",
                "release_delay[wing_minus_x]", "stick_fraction[wing_minus_x]",
                "spring_stiffness_scale[wing_minus_x]", "motor_torque[wing_plus_x]"}));
  EXPECT_EQ(units, (std::vector<std::string>{"N m/rad", "rad/s", "N m s/rad", "rad", "N m", "s",
                                             "s", "1", "1", "N m"}));
  const schedule::Profile& base = spec.base;
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const Case c = BuildCase(spec, i);
    SCOPED_TRACE(DescribeParameters(spec, c.parameters));
    const std::vector<double>& v = c.parameters.values;
    const schedule::FreeDrive& plus = c.profile().hinges[0].drive;
    const schedule::FreeDrive& minus = c.profile().hinges[1].drive;
    EXPECT_EQ(c.run->schedule(), nullptr);  // hinge profiles run without a DeploymentSchedule
    EXPECT_EQ(c.latches_expected, 2);
    EXPECT_EQ(plus.spring.stiffness, v[0]);
    EXPECT_EQ(minus.spring.stiffness, v[0] * v[8]);  // set, then scaled
    EXPECT_EQ(plus.spring.rest_angle, base.hinges[0].drive.spring.rest_angle);
    EXPECT_EQ(plus.damping, 0.1);
    EXPECT_EQ(minus.damping, base.hinges[1].drive.damping);
    EXPECT_EQ(plus.latch.angle, base.hinges[0].drive.latch.angle);
    EXPECT_EQ(minus.latch.angle, v[3]);
    EXPECT_GE(v[3], -kDeg);
    EXPECT_LT(v[3], kDeg);
    EXPECT_EQ(plus.friction.torque, v[4]);
    EXPECT_EQ(minus.friction.torque, v[4]);
    EXPECT_EQ(plus.friction.regularization_speed,
              base.hinges[0].drive.friction.regularization_speed);
    EXPECT_EQ(plus.release.kind, schedule::Release::Kind::kAtTime);
    EXPECT_EQ(plus.release.time, v[5]);
    EXPECT_EQ(minus.release.kind, schedule::Release::Kind::kAfterLatch);
    EXPECT_EQ(minus.release.panel, 0);
    EXPECT_EQ(minus.release.delay, v[6]);
    EXPECT_EQ(plus.latch.jam_fraction, 0.0);
    EXPECT_EQ(minus.latch.jam_fraction, v[7]);
    EXPECT_EQ(plus.motor.kind, schedule::Motor::Kind::kConstant);
    EXPECT_EQ(plus.motor.torque, v[9]);
    EXPECT_EQ(minus.motor.kind, schedule::Motor::Kind::kNone);
    // Initial state: the spin rate about s, with J_B(t0) and h_rel_B(t0) of the hinges.
    const dynamics::InertiaSample s0 = schedule::InitialInertia(c.profile());
    const math::Vec3 w = s0.J_inv_B * (*c.profile().initial.H_B - s0.h_rel_B);
    EXPECT_NEAR(w.dot(c.spin_axis_B), v[1], kTight * v[1]);
    EXPECT_NEAR(c.spin_axis_B.y(), 1.0, kTight);
  }
}

TEST_F(SweepDirTest, AFailedLatchNeverReleasesThePanelWaitingForIt) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", HingeHeader() + R"(
grid:
  - {parameter: latch_fails, panel: wing_plus_x, values: [no, yes]}
  - {parameter: stick_fraction, panel: wing_plus_x, values: [0, 0.8]}
)"));
  const schedule::Profile& base = spec.base;
  const Case ok = BuildCase(spec, 0);      // no, 0
  const Case failed = BuildCase(spec, 2);  // yes, 0
  const Case jammed = BuildCase(spec, 3);  // yes, 0.8: the jam comes first
  EXPECT_TRUE(ok.profile().hinges[0].drive.latch.enabled);
  EXPECT_EQ(ok.profile().hinges[1].drive.release.kind, schedule::Release::Kind::kAfterLatch);
  EXPECT_FALSE(failed.profile().hinges[0].drive.latch.enabled);
  const schedule::Release& never = failed.profile().hinges[1].drive.release;
  EXPECT_EQ(never.kind, schedule::Release::Kind::kAtTime);
  EXPECT_GT(never.time, base.t_end());
  EXPECT_TRUE(jammed.profile().hinges[0].drive.latch.enabled);
  EXPECT_EQ(jammed.profile().hinges[0].drive.latch.jam_fraction, 0.8);
  EXPECT_EQ(jammed.profile().hinges[1].drive.release.kind, schedule::Release::Kind::kAfterLatch);
  // Both cases still expect two latches: the failure shows as all_latched = 0.
  EXPECT_EQ(failed.latches_expected, 2);
  EXPECT_EQ(jammed.latches_expected, 2);
}

TEST_F(SweepDirTest, HingeParametersNeedAFreePanelWithWhatTheyAct) {
  // wing_minus_x locked (left out); wing_plus_x driven by a torque-speed motor.
  Write("p.yaml", "name: p\nmodel: " + std::string(DEPLOYSIM_SOURCE_DIR) + R"(/models/smallsat.yaml
initial: {configuration: closed, angular_velocity: [0, 0.3, 0]}
until: 100
hinges:
  wing_plus_x:
    free:
      motor: {stall_torque: -0.2, no_load_speed_deg_s: -30}
      stops: {min_deg: -2, max_deg: 92}
      latch: {angle_deg: 0}
)");
  const SweepSpec spec = LoadSweep(Write("s.yaml", R"(name: s
base: p.yaml
grid:
  - {parameter: motor_torque_scale, values: [0.5, 2]}
  - {parameter: damping, values: [0.1]}
)"));
  const Case c = BuildCase(spec, 1);
  EXPECT_EQ(c.profile().hinges[0].drive.motor.stall_torque, -0.4);
  EXPECT_EQ(c.profile().hinges[0].drive.motor.no_load_speed,
            spec.base.hinges[0].drive.motor.no_load_speed);
  EXPECT_EQ(c.profile().hinges[0].drive.damping, 0.1);
  EXPECT_EQ(c.profile().hinges[1].kind, schedule::HingePlan::Kind::kLocked);
  EXPECT_EQ(c.latches_expected, 1);
  auto message = [this](const std::string& grid) {
    try {
      (void)LoadSweep(Write("bad.yaml", "name: s\nbase: p.yaml\ngrid:\n" + grid));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(
      message("  - {parameter: damping, panel: wing_minus_x, values: [1]}\n")
          .find("bad.yaml: grid[0].panel = wing_minus_x: the panel is locked in " + Path("p.yaml") +
                ": damping applies to free hinges (free panels: wing_plus_x)"),
      std::string::npos)
      << message("  - {parameter: damping, panel: wing_minus_x, values: [1]}\n");
  EXPECT_NE(message("  - {parameter: motor_torque, values: [1]}\n")
                .find("grid[0].parameter = motor_torque: motor_torque applies to every free "
                      "panel without `panel:`, but free panel 'wing_plus_x' has a torque-speed "
                      "motor (vary it with motor_torque_scale)"),
            std::string::npos);
  EXPECT_NE(message("  - {parameter: spring_stiffness, values: [1]}\n").find("has no spring"),
            std::string::npos);
  // Friction applies to every free hinge: without a regularization speed it is exact Coulomb.
  EXPECT_EQ(message("  - {parameter: friction_torque, values: [1]}\n"), "accepted");
  EXPECT_NE(message("  - {parameter: motor_torque_scale, values: [1, 0]}\n")
                .find("grid[0].values[1] = 0: motor_torque_scale must be > 0"),
            std::string::npos);
  EXPECT_NE(message("  - {parameter: release_delay, values: [1]}\n")
                .find("is not released after another panel's latch"),
            std::string::npos);
}

TEST_F(SweepDirTest, WeightedChoicesFollowTheirWeights) {
  const SweepSpec spec = LoadSweep(Write("s.yaml", HingeHeader() + R"(
monte_carlo:
  samples: 4000
  seed: 11
  parameters:
    - {parameter: latch_fails, panel: wing_minus_x, choice: [no, yes], weights: [0.9, 0.1]}
    - {parameter: stick_fraction, panel: wing_minus_x, choice: [0, 0.75, 0.85], weights: [2, 0, 1]}
)"));
  ASSERT_EQ(spec.monte_carlo->parameters[1].distribution.cumulative.back(), 1.0);
  int yes = 0, jams = 0, impossible = 0;
  for (std::size_t i = 0; i < spec.case_count(); ++i) {
    const CaseParameters p = ParametersOf(spec, i);
    yes += p.values[0] == 1.0 ? 1 : 0;
    jams += p.values[1] == 0.85 ? 1 : 0;
    impossible += p.values[1] == 0.75 ? 1 : 0;
  }
  EXPECT_NEAR(yes, 400, 60);    // binomial sd 19
  EXPECT_NEAR(jams, 1333, 90);  // sd 30
  EXPECT_EQ(impossible, 0);
}

TEST_F(SweepDirTest, TheSpringSweepLoads) {
  const SweepSpec spec =
      LoadSweep(std::string(DEPLOYSIM_SOURCE_DIR) + "/sweeps/smallsat_spring_stiffness_spin.yaml");
  EXPECT_TRUE(spec.base.is_hinge_profile());
  EXPECT_EQ(spec.grid.size(), 2u);
  EXPECT_EQ(spec.case_count(), 11u * 10u * 32u);
  ASSERT_TRUE(spec.outcome.latch_shock_limit.has_value());
  EXPECT_NEAR(*spec.outcome.latch_shock_limit, 15.0 * kDeg, kTight);
}

struct BadSweep {
  const char* name;
  std::string body;      // appended to the header (or the whole file if `whole`)
  std::string expected;  // substring of the message after "<file>: "
  bool whole = false;
};

// Test names show the case's name, not its bytes.
void PrintTo(const BadSweep& bad, std::ostream* os) { *os << bad.name; }

class BadSweepTest : public SweepDirTest, public ::testing::WithParamInterface<BadSweep> {};

TEST_P(BadSweepTest, IsRejectedWithOneLine) {
  const BadSweep& bad = GetParam();
  const std::string path = Write("bad.yaml", bad.whole ? bad.body : Header() + bad.body);
  std::string message;
  try {
    (void)LoadSweep(path);
    FAIL() << "accepted: " << bad.name;
  } catch (const std::exception& e) {
    message = e.what();
  }
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_LT(message.size(), 600u) << message.substr(0, 700);  // long values are cut
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(bad.expected), std::string::npos)
      << "expected '" << bad.expected << "' in: " << message;
  // Nothing was written next to the file.
  EXPECT_EQ(Entries(), std::vector<std::string>{"bad.yaml"});
}

INSTANTIATE_TEST_SUITE_P(
    Corpus,
    BadSweepTest,
    ::testing::Values(
        BadSweep{"UnknownTopKey", "grids: []\n", "grids = []: unknown key (allowed: name,"},
        BadSweep{"MissingName", "base: " + SmallsatProfile() + "\ngrid: []\n",
                 "name: required key is missing", true},
        BadSweep{"MissingBase", "name: t\ngrid: []\n", "base: required key is missing", true},
        BadSweep{"BaseNotFound", "name: t\nbase: nope.yaml\n", "base = nope.yaml: cannot read",
                 true},
        BadSweep{"NoAxes", "", "grid: required key is missing: a sweep needs a grid, monte_carlo"},
        BadSweep{"UnknownParameter", "grid:\n  - {parameter: spin, values: [1]}\n",
                 "grid[0].parameter = spin: unknown parameter (valid: deploy_duration_scale"},
        BadSweep{"NegativeSpin", "grid:\n  - {parameter: spin_rate_rpm, values: [1, 2, -3]}\n",
                 "grid[0].values[2] = -3: spin_rate_rpm must be > 0 [rpm]"},
        BadSweep{"QuotedNumber", "grid:\n  - {parameter: spin_rate_rpm, values: [\"2\"]}\n",
                 "grid[0].values[0] = \"2\": expected a number, not a quoted string"},
        BadSweep{"LinspaceLength", "grid:\n  - {parameter: spin_rate_rpm, linspace: [1, 2]}\n",
                 "grid[0].linspace = [1, 2]: must be [first, last, count]"},
        BadSweep{"LinspaceCount", "grid:\n  - {parameter: spin_rate_rpm, linspace: [1, 2, 2.5]}\n",
                 "grid[0].linspace[2] = 2.5: must be an integer in [2, "},
        BadSweep{"ValuesAndLinspace",
                 "grid:\n  - {parameter: spin_rate_rpm, values: [1], linspace: [1, 2, 3]}\n",
                 "grid[0] = {parameter: spin_rate_rpm, values: [1], linspace: [1, 2, 3]}: exactly "
                 "one of values, linspace, logspace"},
        BadSweep{"LogspaceZero", "grid:\n  - {parameter: nutation_deg, logspace: [0, 2, 3]}\n",
                 "grid[0].logspace = [0, 2, 3]: logspace needs first and last > 0"},
        BadSweep{"StageDurationWithoutStage",
                 "grid:\n  - {parameter: stage_duration, values: [10]}\n",
                 "grid[0].stage: required key is missing"},
        BadSweep{"UnknownStage",
                 "grid:\n  - {parameter: stage_duration, stage: nope, values: [10]}\n",
                 "grid[0].stage = nope: no stage of that name"},
        BadSweep{"StageIndexOutOfRange",
                 "grid:\n  - {parameter: stage_duration, stage: 5, values: [10]}\n",
                 "grid[0].stage = 5: a stage index must be in [0, 5)"},
        BadSweep{"LawOnHold", "grid:\n  - {parameter: law, stage: 0, values: [linear]}\n",
                 "grid[0].stage = 0: stage 0 of"},
        BadSweep{"UnknownLaw", "grid:\n  - {parameter: law, values: [linear, cubic]}\n",
                 "grid[0].values[1] = cubic: unknown law (valid: step, linear, smoothstep, "
                 "minimum-jerk)"},
        BadSweep{"UnknownPanel",
                 "grid:\n  - {parameter: panel_mass_scale, panel: wing_z, values: [1]}\n",
                 "grid[0].panel = wing_z: no panel of that name (panels: wing_plus_x, "
                 "wing_minus_x)"},
        BadSweep{"QualifierNotUsed", "grid:\n  - {parameter: spin_rate, stage: 1, values: [1]}\n",
                 "grid[0].stage = 1: not used by parameter spin_rate"},
        BadSweep{"InertiaScaleOnHingedModel",
                 "grid:\n  - {parameter: inertia_scale, values: [1]}\n",
                 "grid[0].parameter = inertia_scale: inertia_scale needs a tensors model"},
        BadSweep{"SameColumnTwice",
                 "grid:\n  - {parameter: spin_rate, values: [1]}\n"
                 "  - {parameter: spin_rate_rpm, values: [5]}\n",
                 "grid[1].parameter = spin_rate_rpm: sets column spin_rate again (already set "
                 "by grid[0])"},
        BadSweep{"NutationTooLarge", "grid:\n  - {parameter: nutation_deg, values: [90]}\n",
                 "grid[0].values[0] = 90: nutation_deg must be in [0, 90) [deg]"},
        BadSweep{"ZeroSamples",
                 "monte_carlo: {samples: 0, seed: 1, parameters: [{parameter: nutation_deg, "
                 "uniform: [0, 1]}]}\n",
                 "monte_carlo.samples = 0: must be an integer in [1, "},
        BadSweep{"FractionalSeed",
                 "monte_carlo: {samples: 2, seed: 1.5, parameters: [{parameter: nutation_deg, "
                 "uniform: [0, 1]}]}\n",
                 "monte_carlo.seed = 1.5: must be an integer in [0, 2^53]"},
        BadSweep{"NormalWithoutMin",
                 "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: panel_mass_scale, "
                 "normal: {mean: 1, sigma: 0.1}}]}\n",
                 "monte_carlo.parameters[0].normal.min: required key is missing: a normal "
                 "distribution of panel_mass_scale needs a truncation bound min"},
        BadSweep{"UniformReversed",
                 "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: nutation_deg, "
                 "uniform: [2, 1]}]}\n",
                 "monte_carlo.parameters[0].uniform = [2, 1]: low must be < high"},
        BadSweep{"CategoricalUniform",
                 "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: coupling, "
                 "uniform: [0, 1]}]}\n",
                 "monte_carlo.parameters[0].uniform = [0, 1]: coupling is categorical: use "
                 "choice"},
        BadSweep{"InvalidCase", "grid:\n  - {parameter: law, values: [minimum-jerk, step]}\n",
                 "case 1 {law=step}: "},
        BadSweep{"UnknownMethod",
                 "name: t\nbase: " + SmallsatProfile() +
                     "\nintegrator: {method: rk5}\ngrid:\n  - {parameter: spin_rate, values: "
                     "[1]}\n",
                 "integrator.method = rk5: unknown integrator (valid: ", true},
        BadSweep{"TumbleAngle",
                 "grid:\n  - {parameter: spin_rate, values: [1]}\noutcome: {tumble_angle_deg: "
                 "0}\n",
                 "outcome.tumble_angle_deg = 0: must be in (0, 90) [deg]"},
        BadSweep{"YamlSyntax", "grid: [\n", "YAML syntax error"},
        // Hinge profiles: parameters that do not apply, values out of range.
        BadSweep{"StageParameterOnHingeBase",
                 HingeHeader() + "grid:\n  - {parameter: law, values: [linear]}\n",
                 "grid[0].parameter = law: law applies to stage profiles (`stages:`); the base ",
                 true},
        BadSweep{"DurationOnHingeBase",
                 HingeHeader() + "grid:\n  - {parameter: deploy_duration_scale, values: [2]}\n",
                 "is a hinge profile (`hinges:`)", true},
        BadSweep{"HingeParameterOnStageBase",
                 "grid:\n  - {parameter: spring_stiffness, values: [1]}\n",
                 "grid[0].parameter = spring_stiffness: spring_stiffness applies to the free "
                 "hinges of hinge profiles (`hinges:`); the base "},
        BadSweep{"NegativeDamping",
                 HingeHeader() + "grid:\n  - {parameter: damping, values: [0.2, -0.1]}\n",
                 "grid[0].values[1] = -0.1: damping must be in [0, 1e9] [N m s/rad]", true},
        // The profiles' own upper bound, refused at its line of the sweep file.
        BadSweep{"HugeDamping",
                 HingeHeader() + "grid:\n  - {parameter: damping, values: [0.2, 1e308]}\n",
                 "grid[0].values[1] = 1e308: damping must be in [0, 1e9] [N m s/rad]", true},
        BadSweep{"NegativeStiffness",
                 HingeHeader() + "grid:\n  - {parameter: spring_stiffness, linspace: [-1, 1, 3]}\n",
                 "grid[0].linspace[0] = -1: spring_stiffness must be in [0, 1e9] [N m/rad]", true},
        BadSweep{"StickFractionOne",
                 HingeHeader() + "grid:\n  - {parameter: stick_fraction, values: [0.5, 1]}\n",
                 "grid[0].values[1] = 1: stick_fraction must be in [0, 1) (0: no jam)", true},
        BadSweep{"NegativeSpringScale",
                 HingeHeader() + "grid:\n  - {parameter: spring_stiffness_scale, values: [-0.5]}\n",
                 "grid[0].values[0] = -0.5: spring_stiffness_scale must be >= 0", true},
        BadSweep{"ReleaseBeforeStart",
                 HingeHeader() +
                     "grid:\n  - {parameter: release_time, panel: wing_plus_x, values: [-5]}\n",
                 "grid[0].values[0] = -5: release_time must be >= the base profile's start (0 s)",
                 true},
        BadSweep{"ReleaseTimeOnAfterLatchPanel",
                 HingeHeader() + "grid:\n  - {parameter: release_time, values: [30]}\n",
                 "grid[0].parameter = release_time: release_time applies to every free panel "
                 "without `panel:`, but free panel 'wing_minus_x' is released after panel "
                 "'wing_plus_x' latches (vary that with release_delay)",
                 true},
        BadSweep{"ReleaseDelayOnTimedPanel",
                 HingeHeader() +
                     "grid:\n  - {parameter: release_delay, panel: wing_plus_x, values: [3]}\n",
                 "grid[0].panel = wing_plus_x: release_delay: the panel is not released after "
                 "another panel's latch (vary its release with release_time)",
                 true},
        BadSweep{"MotorScaleWithoutMotor",
                 HingeHeader() +
                     "grid:\n  - {parameter: motor_torque_scale, panel: wing_minus_x, values: "
                     "[2]}\n",
                 "grid[0].panel = wing_minus_x: motor_torque_scale: the panel has no motor", true},
        BadSweep{"UnknownHingePanel",
                 HingeHeader() + "grid:\n  - {parameter: damping, panel: wing_z, values: [1]}\n",
                 "grid[0].panel = wing_z: no panel of that name (panels: wing_plus_x, "
                 "wing_minus_x)",
                 true},
        BadSweep{"UnknownLatchFailure",
                 HingeHeader() + "grid:\n  - {parameter: latch_fails, values: [no, maybe]}\n",
                 "grid[0].values[1] = maybe: unknown latch_fails (valid: no, yes)", true},
        BadSweep{"LatchOutsideTheStops",
                 HingeHeader() +
                     "grid:\n  - {parameter: latch_angle_deg, panel: wing_plus_x, values: [0, 10, "
                     "-5]}\n",
                 ": case 2 {latch_angle[wing_plus_x]=-0.08726646259971647}: " + SpringProfile() +
                     ": hinges.wing_plus_x.free.latch.angle_deg = -5: the latch angle must lie "
                     "within the stops [-2, 92] deg",
                 true},
        BadSweep{"LatchAtTheInitialAngle",
                 HingeHeader() + "grid:\n  - {parameter: latch_angle_deg, values: [90]}\n",
                 "the latch angle must differ from the hinge's initial angle", true},
        BadSweep{"NutationPastTheNextAxis",
                 HingeHeader() + "grid:\n  - {parameter: nutation_deg, values: [10, 60]}\n",
                 ": case 1 {nutation=1.0471975511965976}: initial: H_B(t0) is nearer another "
                 "principal axis than the spin axis s",
                 true},
        BadSweep{"WeightsWithoutChoice",
                 HingeHeader() +
                     "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: damping, "
                     "uniform: [0, 1], weights: [1, 2]}]}\n",
                 "monte_carlo.parameters[0].weights = [1, 2]: weights go with choice", true},
        BadSweep{"WeightsOfAnotherLength",
                 HingeHeader() +
                     "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: latch_fails, "
                     "panel: wing_minus_x, choice: [no, yes], weights: [1]}]}\n",
                 "monte_carlo.parameters[0].weights = [1]: one weight per choice is required (2 "
                 "choices)",
                 true},
        BadSweep{"NegativeWeight",
                 HingeHeader() +
                     "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: latch_fails, "
                     "panel: wing_minus_x, choice: [no, yes], weights: [1, -1]}]}\n",
                 "monte_carlo.parameters[0].weights[1] = -1: a weight must be >= 0", true},
        BadSweep{"AllWeightsZero",
                 HingeHeader() +
                     "monte_carlo: {samples: 2, seed: 1, parameters: [{parameter: stick_fraction, "
                     "choice: [0, 0.5], weights: [0, 0]}]}\n",
                 "monte_carlo.parameters[0].weights = [0, 0]: at least one weight must be > 0",
                 true},
        BadSweep{"ShockLimitOnStageBase",
                 "grid:\n  - {parameter: spin_rate, values: [1]}\noutcome: "
                 "{latch_shock_limit_deg_s: 10}\n",
                 "outcome.latch_shock_limit_deg_s = 10: a latch shock limit needs a hinge profile "
                 "as the base"},
        BadSweep{"NonShapeMethodForFreeHinges",
                 "name: t\nbase: " + SpringProfile() +
                     "\nintegrator: {method: rkf78}\ngrid:\n  - {parameter: damping, values: "
                     "[1]}\n",
                 "integrator.method = rkf78: the base " + SpringProfile() +
                     " has free hinges: free hinges need a Lie-group method (rule: one of ",
                 true},
        // Hostile input.
        BadSweep{"BaseIsADevice", "name: t\nbase: /dev/zero\n",
                 "base = /dev/zero: cannot read /dev/zero: is a character device, not a regular "
                 "file",
                 true},
        BadSweep{"CommaLoop", ",\n", "line 1, column 1: YAML syntax error: unexpected ','", true},
        BadSweep{"CommaAfterAKey", "name: t\n,\n", "line 2, column 1: YAML syntax error", true},
        BadSweep{"RecursiveAlias", "grid: &g [{parameter: spin_rate, values: *g}]\n",
                 "an alias refers to a node that contains it"},
        BadSweep{"LongName", "name: " + std::string(1000000, 'n') + "\nbase: x.yaml\n",
                 "name = nnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnnn... (1000000 "
                 "bytes): a name has at most 200 bytes (this one has 1000000)",
                 true},
        BadSweep{"LongStageValue",
                 "grid:\n  - {parameter: stage_duration, stage: " + std::string(500000, 's') +
                     ", values: [10]}\n",
                 "grid[0].stage = ssssssssssssssssssssssssssssssssssssssssssssssssssssssssssss... "
                 "(500000 bytes): no stage of that name in "},
        // Refused at the axis, before its million values are made (with 200 such axes
        // loading took 1.6 GB).
        BadSweep{"AxisPastTheCaseLimit",
                 "grid:\n  - {parameter: spin_rate, linspace: [1, 2, 1000000]}\n"
                 "  - {parameter: deploy_duration_scale, linspace: [1, 2, 1000]}\n",
                 "grid[1].linspace = [1, 2, 1000]: gives 1e+09 cases with the axes before it "
                 "(at most 1e+08)"},
        BadSweep{"InvalidUtf8", "description: \"\xc3\x28\"\n", "line 4, byte offset ", false}),
    [](const ::testing::TestParamInfo<BadSweep>& param) { return std::string(param.param.name); });

// A base profile with many long stage names: the list of names in the message is cut.
TEST_F(SweepDirTest, ManyStageNamesAreCutInMessages) {
  std::string profile =
      "name: p\nmodel: " + std::string(DEPLOYSIM_SOURCE_DIR) +
      "/models/wing_nut.yaml\ninitial: {angular_momentum: [0, 2.1252e-5, 0]}\nstages:\n";
  for (int i = 1; i <= 500; ++i) {
    profile += "  - {name: " + std::string(190, 'q') + std::to_string(i) +
               ", hold: default, until: " + std::to_string(i) + "}\n";
  }
  const std::string base = Write("base.yaml", profile);
  const std::string sweep =
      Write("s.yaml", "name: s\nbase: " + base +
                          "\ngrid:\n  - {parameter: stage_duration, stage: nope, values: [1]}\n");
  try {
    (void)LoadSweep(sweep);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_LT(m.size(), 1500u) << m.substr(0, 2000);
    EXPECT_NE(m.find("no stage of that name in"), std::string::npos) << m.substr(0, 300);
    EXPECT_NE(m.find(", ... (500 in all))"), std::string::npos) << m.substr(0, 2000);
  }
}

// ReadSweep checks the file and the base but builds no case (LoadSweep builds every one:
// time proportional to the number of cases, up to kMaxCases).
TEST_F(SweepDirTest, ReadSweepBuildsNoCase) {
  const std::string path =
      Write("s.yaml", Header() + "grid:\n  - {parameter: law, values: [minimum-jerk, step]}\n");
  const SweepSpec spec = ReadSweep(path);
  EXPECT_EQ(spec.case_count(), 2u);
  EXPECT_THROW((void)LoadSweep(path), std::invalid_argument);  // case 1 {law=step}
  EXPECT_THROW(ValidateCases(spec), std::invalid_argument);
}

// The cases are validated without copying the base's texts each time (a base padded to
// 1 MiB made validating each case copy megabytes): the error is the same.
TEST_F(SweepDirTest, ValidationOfAPaddedBaseNamesTheCase) {
  std::ifstream in(SmallsatProfile());
  std::string profile((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  profile = std::regex_replace(profile, std::regex("model: \\.\\./models/"),
                               "model: " + std::string(DEPLOYSIM_SOURCE_DIR) + "/models/");
  while (profile.size() < 1000000) profile += "#" + std::string(99, 'p') + "\n";
  const std::string base = Write("base.yaml", profile);
  const std::string path =
      Write("s.yaml", "name: s\nbase: " + base +
                          "\ngrid:\n  - {parameter: law, values: [minimum-jerk, step]}\n");
  try {
    (void)LoadSweep(path);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml: case 1 {law=step}: "), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(ReadSweep(path).base.text.size(), profile.size());
}

// A FIFO as base: refused at once (opening it to probe would block).
TEST_F(SweepDirTest, BaseThatIsAFifoIsRefused) {
  ASSERT_EQ(::mkfifo(Path("fifo.yaml").c_str(), 0600), 0);
  const std::string sweep = Write("s.yaml", "name: s\nbase: fifo.yaml\ngrid: []\n");
  try {
    (void)LoadSweep(sweep);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml: base = fifo.yaml: cannot read "),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("is a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
