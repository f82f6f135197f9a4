#include "deploysim/schedule/profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "schedule_fixtures.h"

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using testing::HingedModel;
using testing::Hold;
using testing::MakeProfile;
using testing::Move;
using testing::TensorModel;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Profile ValidTensorProfile() {
  return MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kSmoothstep);
}

Profile ValidGeometryProfile() {
  return MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kMinimumJerk);
}

/// Expects ValidateProfile to throw std::invalid_argument whose message contains `expected`.
void ExpectRejected(const Profile& p, const std::string& expected) {
  try {
    ValidateProfile(p);
    ADD_FAILURE() << "accepted an invalid profile; expected: " << expected;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << expected;
  }
}

TEST(ProfileTest, ModeAndCouplingNames) {
  EXPECT_EQ(ToString(Mode::kTensor), "tensor");
  EXPECT_EQ(ToString(Mode::kGeometry), "geometry");
  EXPECT_EQ(ToString(Coupling::kQuasiRigid), "quasi-rigid");
  EXPECT_EQ(ToString(Coupling::kExact), "exact");
}

TEST(ProfileTest, AcceptsValidProfiles) {
  EXPECT_NO_THROW(ValidateProfile(ValidTensorProfile()));
  EXPECT_NO_THROW(ValidateProfile(ValidGeometryProfile()));
  // A hinged model may be used in tensor mode (its configuration tensors are interpolated).
  EXPECT_NO_THROW(ValidateProfile(
      MakeProfile(HingedModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kLinear)));
  // A single hold is a complete profile (a plain rigid body).
  Profile p = ValidTensorProfile();
  p.stages = {Hold("open", 0.0, 5.0)};
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsNoStages) {
  Profile p = ValidTensorProfile();
  p.stages.clear();
  ExpectRejected(p, "p.yaml: stages: at least one stage is required");
}

TEST(ProfileTest, RejectsFirstStageMovingFromNowhere) {
  Profile p = ValidTensorProfile();
  p.stages.front() = Move("", "closed", Law::kLinear, 0.0, 10.0);
  ExpectRejected(p,
                 "p.yaml: stages[0].to = 'closed': the first stage must be a hold or name "
                 "the configuration it starts from");
  // With `from` set the first stage may move.
  p.stages.front().from = "open";
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsNonContiguousStages) {
  Profile p = ValidTensorProfile();
  p.stages[2].t_begin = 26.0;
  ExpectRejected(p,
                 "p.yaml: stages[2].start = 26: stages must be contiguous (previous stage "
                 "ends at 25)");
}

TEST(ProfileTest, RejectsDecreasingEndTimes) {
  Profile p = ValidTensorProfile();
  p.stages[2].t_end = 20.0;
  ExpectRejected(p,
                 "p.yaml: stages[2].until = 20: stage end times must increase (previous "
                 "stage ends at 25)");
  // An empty stage is rejected too, also the first one.
  p = ValidTensorProfile();
  p.stages[0].t_end = 0.0;
  ExpectRejected(p,
                 "p.yaml: stages[0].until = 0: stage end times must increase (the first "
                 "stage starts at 0)");
}

TEST(ProfileTest, RejectsStagesShorterThanTheMinimumDuration) {
  // The time scale is 60 s, so the minimum is 1e-8 x 60 s = 6e-7 s. A first hold of
  // 1e-11 s lay within the scheduler's boundary tolerance (1e-12 x 60 s) of the start:
  // its end was dropped from the breakpoints (a 3.5e-8 error in H_B under exact coupling).
  const double min_duration = kMinStageDurationFraction * 60.0;
  Profile p = ValidGeometryProfile();
  p.stages[0].t_end = p.stages[1].t_begin = 1e-11;
  ExpectRejected(p,
                 "p.yaml: stages[0].until = 1e-11: stage 'hold closed' lasts 1e-11 s, less "
                 "than the minimum 6e-07 s = 1e-08 x max(|start|, |end|) of the profile (60 "
                 "s) (rule: minimum stage duration)");
  // Anywhere in the profile, and just below the minimum.
  p = ValidGeometryProfile();
  p.stages[2].t_end = p.stages[3].t_begin = 25.0 + 0.5 * min_duration;
  ExpectRejected(p, "stages[2].until = 25.0000003: stage 'hold half_open' lasts");
  p = ValidGeometryProfile();
  p.stages[4].t_begin = p.stages[3].t_end = 60.0 - 0.9 * min_duration;
  ExpectRejected(p, "stages[4].until = 60: stage 'hold open' lasts");
  // The scale is the largest |time|, also when the profile starts at a negative time.
  p = ValidGeometryProfile();
  p.stages[0].t_begin = -600.0;
  p.stages[1].t_begin = p.stages[0].t_end = -600.0 + 1e-6;
  ExpectRejected(p, "(rule: minimum stage duration)");
  // Twice the minimum is accepted, at the start, in the middle and at the end.
  p = ValidGeometryProfile();
  p.stages[0].t_end = p.stages[1].t_begin = 2.0 * min_duration;
  p.stages[2].t_end = p.stages[3].t_begin = 25.0 + 2.0 * min_duration;
  p.stages[4].t_begin = p.stages[3].t_end = 60.0 - 2.0 * min_duration;
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsNonFiniteTimes) {
  Profile p = ValidTensorProfile();
  p.stages[1].t_end = kInf;
  ExpectRejected(p, "p.yaml: stages[1].until = inf: must be finite");
  p = ValidTensorProfile();
  p.stages[0].t_begin = kNaN;
  ExpectRejected(p, "p.yaml: stages[0].start = nan: must be finite");
}

TEST(ProfileTest, RejectsUnknownConfiguration) {
  Profile p = ValidTensorProfile();
  p.stages[1].to = "ajar";
  ExpectRejected(p,
                 "p.yaml: stages[1].to = 'ajar': no configuration of that name in model "
                 "'three_tensors' (valid: closed, half_open, open)");
  p = ValidTensorProfile();
  p.stages[0] = Hold("shut", 0.0, 10.0);
  ExpectRejected(p, "p.yaml: stages[0].hold = 'shut': no configuration of that name");
  p = ValidTensorProfile();
  p.stages[0].from = "shut";  // a first stage moving from an unknown configuration
  ExpectRejected(p, "p.yaml: stages[0].from = 'shut': no configuration of that name");
}

TEST(ProfileTest, RejectsStageStartingElsewhereThanThePreviousEnded) {
  Profile p = ValidTensorProfile();
  p.stages[1].from = "open";
  ExpectRejected(p,
                 "p.yaml: stages[1].from = 'open': a stage starts in the configuration the "
                 "previous stage ends in ('closed')");
  // An empty `from` means "where the previous stage ended".
  p.stages[1].from.clear();
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsGeometryModeWithTensorModel) {
  Profile p = ValidTensorProfile();
  p.mode = Mode::kGeometry;
  ExpectRejected(p,
                 "p.yaml: mode = geometry: geometry mode needs a hinged model (model "
                 "'three_tensors' is kind tensors)");
}

TEST(ProfileTest, RejectsExactCouplingOutsideGeometryMode) {
  Profile p = MakeProfile(HingedModel(), Mode::kTensor, Coupling::kExact, Law::kLinear);
  ExpectRejected(p,
                 "p.yaml: coupling = exact: exact coupling needs mode geometry (mode is "
                 "tensor)");
}

TEST(ProfileTest, RejectsStepLawWithExactCoupling) {
  Profile p = ValidGeometryProfile();
  p.stages[3].law = Law::kStep;
  ExpectRejected(p,
                 "p.yaml: stages[3].law = step: the step law is not allowed with coupling "
                 "exact");
  // Quasi-rigid coupling allows it.
  p.coupling = Coupling::kQuasiRigid;
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, HoldsIgnoreTheirLawUnderExactCoupling) {
  // Hold stages keep the default law (step); that is not an instantaneous motion.
  Profile p = ValidGeometryProfile();
  ASSERT_EQ(p.stages[0].law, Law::kStep);
  ASSERT_TRUE(p.stages[0].is_hold());
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsBothOrNeitherInitialVelocityAndMomentum) {
  Profile p = ValidTensorProfile();
  p.initial.H_B = math::Vec3(0.0, 3.0, 0.0);
  ExpectRejected(p,
                 "p.yaml: initial: exactly one of angular_velocity, angular_momentum is "
                 "required (both are given)");
  p.initial.w_NB_B.reset();
  p.initial.H_B.reset();
  ExpectRejected(p, "(neither is given)");
}

TEST(ProfileTest, RejectsNonFiniteInitialState) {
  Profile p = ValidTensorProfile();
  p.initial.w_NB_B = math::Vec3(0.0, kNaN, 0.0);
  ExpectRejected(p, "p.yaml: initial.angular_velocity = [0, nan, 0]: must be finite");
  p.initial.w_NB_B.reset();
  p.initial.H_B = math::Vec3(kInf, 1.0, 0.0);
  ExpectRejected(p, "p.yaml: initial.angular_momentum = [inf, 1, 0]: must be finite");
  p.initial.H_B = math::Vec3(0.0, 1.0, 0.0);
  p.initial.q_NB = math::Quat(kNaN, 0.0, 0.0, 0.0);
  ExpectRejected(p,
                 "p.yaml: initial.attitude_wxyz = [nan, 0, 0, 0]: must be finite and "
                 "non-zero");
}

TEST(ProfileTest, RejectsZeroInitialState) {
  Profile p = ValidTensorProfile();
  p.initial.w_NB_B = math::Vec3::Zero();
  ExpectRejected(p, "p.yaml: initial.angular_velocity = [0, 0, 0]: must be non-zero");
}

TEST(ProfileTest, RejectsHingeAnglesNotOnePerPanel) {
  Profile p = ValidGeometryProfile();
  p.model.configurations[2].hinge_angles = Eigen::VectorXd::Zero(1);
  ExpectRejected(p,
                 "models/smallsat.yaml: configurations.open.hinge_angles_deg has 1 entries: "
                 "one hinge angle per panel is required (the model has 2 panels)");
  p.model.configurations[2].hinge_angles = Eigen::Vector2d(0.0, kInf);
  ExpectRejected(p,
                 "models/smallsat.yaml: configurations.open.hinge_angles_deg = [0, inf] "
                 "[rad]: must be finite");
}

TEST(ProfileTest, RejectsInvalidModel) {
  // Tensor configurations must be physically valid inertias.
  Profile p = ValidTensorProfile();
  p.model.configurations[1].J_B = math::Vec3(1.0, 1.0, 3.0).asDiagonal();
  ExpectRejected(p, "models/three_tensors.yaml: configurations.half_open");
  ExpectRejected(p, "rule: triangle inequality");
  // The hinged body is validated by the model module.
  p = ValidGeometryProfile();
  p.model.hinged.panels[1].body.mass = 0.0;
  ExpectRejected(p, "models/smallsat.yaml: panels[1] (wing_minus_x).mass = 0");
}

TEST(ProfileTest, RejectsRelativeToleranceOutOfRange) {
  Profile p = ValidTensorProfile();
  p.integrator.rtol = 1.0;
  ExpectRejected(p, "p.yaml: integrator.rtol = 1: must be in [1e-14, 0.001]");
  p.integrator.rtol = 1e-15;
  ExpectRejected(p, "p.yaml: integrator.rtol = 1e-15: must be in [1e-14, 0.001]");
  p.integrator.rtol = kNaN;
  ExpectRejected(p, "p.yaml: integrator.rtol = nan: must be finite");
  p.integrator.rtol = 1e-14;  // the bounds themselves are allowed
  EXPECT_NO_THROW(ValidateProfile(p));
  p.integrator.rtol = 1e-3;
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsNonPositiveAbsoluteTolerance) {
  Profile p = ValidTensorProfile();
  p.integrator.atol = 0.0;
  ExpectRejected(p, "p.yaml: integrator.atol = 0: must be in (0, 0.001]");
  // A tolerance that cannot mean anything: at 1e12 a wing passed its stop by 130 deg.
  p.integrator.atol = 1e12;
  ExpectRejected(p, "p.yaml: integrator.atol = 1e+12: must be in (0, 0.001]");
  p.integrator.atol = kInf;
  ExpectRejected(p, "p.yaml: integrator.atol = inf: must be finite");
}

TEST(ProfileTest, RejectsNegativeStep) {
  Profile p = ValidTensorProfile();
  p.integrator.step = -0.1;
  ExpectRejected(p, "p.yaml: integrator.step = -0.1: must be >= 0");
  p.integrator.step = 0.0;  // automatic
  EXPECT_NO_THROW(ValidateProfile(p));
}

TEST(ProfileTest, RejectsNonPositiveMaxStep) {
  Profile p = ValidTensorProfile();
  p.integrator.max_step = 0.0;
  ExpectRejected(p, "p.yaml: integrator.max_step = 0: must be > 0");
  p.integrator.max_step = kInf;
  ExpectRejected(p, "p.yaml: integrator.max_step = inf: must be finite");
}

TEST(ProfileTest, RejectsBadOutputInterval) {
  Profile p = ValidTensorProfile();
  p.output.dt = 0.0;
  ExpectRejected(p, "p.yaml: output.dt = 0: must be > 0");
  p.output.dt = kInf;
  ExpectRejected(p, "p.yaml: output.dt = inf: must be finite");
}

TEST(ProfileTest, NamesTheProfileWhenItHasNoSource) {
  Profile p = ValidTensorProfile();
  p.source.clear();
  p.output.dt = -1.0;
  ExpectRejected(p, "profile 'three_stage': output.dt = -1: must be > 0");
}

// The one statement of the integrator ranges (profiles, sweeps and Python use it).
TEST(IntegratorRulesTest, EachKeyHasOneRange) {
  EXPECT_EQ(IntegratorRuleViolated("rtol", 1e-14), "");
  EXPECT_EQ(IntegratorRuleViolated("rtol", 1e-3), "");
  EXPECT_EQ(IntegratorRuleViolated("rtol", 1.0), "must be in [1e-14, 0.001]");
  EXPECT_EQ(IntegratorRuleViolated("rtol", 9e-15), "must be in [1e-14, 0.001]");
  EXPECT_EQ(IntegratorRuleViolated("atol", 0.0), "must be in (0, 0.001]");
  EXPECT_EQ(IntegratorRuleViolated("atol", 1e-3), "");
  EXPECT_EQ(IntegratorRuleViolated("atol", 2e-3), "must be in (0, 0.001]");
  EXPECT_EQ(IntegratorRuleViolated("step", 0.0), "");
  EXPECT_EQ(IntegratorRuleViolated("step", -1e-300), "must be >= 0 (0: automatic)");
  EXPECT_EQ(IntegratorRuleViolated("max_step", 0.0), "must be > 0");
  EXPECT_EQ(IntegratorRuleViolated("max_step", std::nan("")), "must be > 0");
  EXPECT_THROW(IntegratorRuleViolated("method", 1.0), std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
