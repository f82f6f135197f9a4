#include "deploysim/schedule/deployment_schedule.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/math/inertia.h"
#include "deploysim/math/so3.h"
#include "deploysim/model/mass_properties.h"
#include "schedule_fixtures.h"

namespace deploysim::schedule {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

using dynamics::InertiaSample;
using dynamics::Side;
using math::Mat3;
using math::Vec3;
using testing::HingedModel;
using testing::Hold;
using testing::MakeProfile;
using testing::Move;
using testing::MovingTimes;
using testing::TensorModel;

/// Finite-difference step as a fraction of the stage duration: central differences then
/// have truncation ~ (1e-5)^2 |s'''| / 6 and rounding ~ 1e-16 / 1e-5, both << kFdTolerance.
constexpr double kFdRelStep = 1e-5;
/// Agreement of an analytic derivative with central differences, relative to the scale
/// max|J| / duration of the quantity.
constexpr double kFdTolerance = 1e-8;
/// Two evaluations of the same formula (or of exact identities) in double precision.
constexpr double kRoundoff = 1e-13;
/// A rate that must be non-zero is larger than this fraction of its scale (small: near a
/// minimum-jerk stage end s' ~ 30 (1 - tau)^2).
constexpr double kNonZero = 1e-5;

constexpr std::array<Law, 3> kMovingLaws{Law::kLinear, Law::kSmoothstep, Law::kMinimumJerk};

struct Case {
  std::string label;
  model::Model model;
  Mode mode;
  Coupling coupling;
};

std::vector<Case> AllCases() {
  return {
      {"tensor model, tensor mode", TensorModel(), Mode::kTensor, Coupling::kQuasiRigid},
      {"hinged model, tensor mode", HingedModel(), Mode::kTensor, Coupling::kQuasiRigid},
      {"geometry, quasi-rigid", HingedModel(), Mode::kGeometry, Coupling::kQuasiRigid},
      {"geometry, exact", HingedModel(), Mode::kGeometry, Coupling::kExact},
  };
}

double MaxAbs(const Mat3& M) { return M.cwiseAbs().maxCoeff(); }

/// Geometry reference, independent of the schedule: theta(t), theta'(t) of stage st from
/// the law, then the model's mass properties.
model::MassProperties ReferenceGeometry(const model::Model& m, const Stage& st, double t) {
  const model::HingedBody body = model::ValidatedHingedBody(m.hinged, "test");
  const Eigen::VectorXd from = m.configuration(st.from).hinge_angles;
  const Eigen::VectorXd to = m.configuration(st.to).hinge_angles;
  const double duration = st.t_end - st.t_begin;
  const LawValue v = EvaluateLaw(st.law, (t - st.t_begin) / duration);
  const Eigen::VectorXd theta = from + v.s * (to - from);
  const Eigen::VectorXd theta_dot = v.ds / duration * (to - from);
  return model::ComputeMassProperties(body, theta, theta_dot);
}

TEST(DeploymentScheduleTest, JdotMatchesFiniteDifferencesOfJ) {
  for (const Case& c : AllCases()) {
    for (Law law : kMovingLaws) {
      SCOPED_TRACE(c.label + ", " + ToString(law));
      const DeploymentSchedule sched(MakeProfile(c.model, c.mode, c.coupling, law));
      for (double t : MovingTimes()) {
        const Stage& st = sched.stages()[static_cast<std::size_t>(sched.StageAt(t))];
        const double duration = st.t_end - st.t_begin;
        const double h = kFdRelStep * duration;
        const InertiaSample s = sched.Evaluate(t);
        const Mat3 fd = (sched.Evaluate(t + h).J_B - sched.Evaluate(t - h).J_B) / (2.0 * h);
        const double scale = MaxAbs(s.J_B) / duration;
        EXPECT_LT(MaxAbs(s.Jdot_B - fd), 1e-9 * scale) << "t = " << t;  // measured 2.3e-10
        EXPECT_GT(MaxAbs(s.Jdot_B), kNonZero * scale) << "t = " << t;
        EXPECT_LT(MaxAbs(s.J_inv_B * s.J_B - Mat3::Identity()), kRoundoff) << "t = " << t;
      }
    }
  }
}

TEST(DeploymentScheduleTest, HingeRatesAndAccelerationsMatchFiniteDifferences) {
  for (Law law : kMovingLaws) {
    SCOPED_TRACE(ToString(law));
    const DeploymentSchedule sched(
        MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, law));
    for (double t : MovingTimes()) {
      const Stage& st = sched.stages()[static_cast<std::size_t>(sched.StageAt(t))];
      const double duration = st.t_end - st.t_begin;
      const double h = kFdRelStep * duration;
      const Eigen::VectorXd rate = sched.HingeRates(t);
      const Eigen::VectorXd acc = sched.HingeAccelerations(t);
      const Eigen::VectorXd fd_rate =
          (sched.HingeAngles(t + h) - sched.HingeAngles(t - h)) / (2 * h);
      const Eigen::VectorXd fd_acc = (sched.HingeRates(t + h) - sched.HingeRates(t - h)) / (2 * h);
      ASSERT_EQ(rate.size(), 2);
      EXPECT_LT((rate - fd_rate).cwiseAbs().maxCoeff(), 3e-9 / duration)  // measured 5.1e-11
          << "t = " << t;
      EXPECT_LT((acc - fd_acc).cwiseAbs().maxCoeff(), kFdTolerance / (duration * duration))
          << "t = " << t;
      EXPECT_GT(rate.cwiseAbs().maxCoeff(), kNonZero / duration) << "t = " << t;
    }
  }
}

TEST(DeploymentScheduleTest, GeometryMatchesModelMassProperties) {
  const model::Model m = HingedModel();
  for (Law law : kMovingLaws) {
    SCOPED_TRACE(ToString(law));
    const DeploymentSchedule exact(MakeProfile(m, Mode::kGeometry, Coupling::kExact, law));
    const DeploymentSchedule quasi(MakeProfile(m, Mode::kGeometry, Coupling::kQuasiRigid, law));
    for (double t : MovingTimes()) {
      const Stage& st = exact.stages()[static_cast<std::size_t>(exact.StageAt(t))];
      const model::MassProperties ref = ReferenceGeometry(m, st, t);
      const InertiaSample e = exact.Evaluate(t);
      const InertiaSample q = quasi.Evaluate(t);
      const double J_scale = MaxAbs(ref.J_B);
      EXPECT_LT(MaxAbs(e.J_B - ref.J_B), kRoundoff * J_scale) << "t = " << t;
      EXPECT_LT(MaxAbs(e.Jdot_B - ref.Jdot_B), kRoundoff * J_scale) << "t = " << t;
      EXPECT_LT((e.h_rel_B - ref.h_rel_B).norm(), kRoundoff * J_scale) << "t = " << t;
      EXPECT_GT(e.h_rel_B.norm(), kNonZero * J_scale / (st.t_end - st.t_begin)) << "t = " << t;
      // Quasi-rigid: the same J and Jdot, no relative momentum.
      EXPECT_EQ(q.J_B, e.J_B) << "t = " << t;
      EXPECT_EQ(q.Jdot_B, e.Jdot_B) << "t = " << t;
      EXPECT_EQ(q.h_rel_B, Vec3::Zero()) << "t = " << t;
      // The relative kinetic energy likewise: the model's under exact coupling, none for
      // the instantaneously rigid body of the quasi-rigid coupling.
      EXPECT_NEAR(e.relative_kinetic_energy, ref.relative_kinetic_energy,
                  kRoundoff * ref.relative_kinetic_energy)
          << "t = " << t;
      EXPECT_GT(e.relative_kinetic_energy, 0.0) << "t = " << t;
      EXPECT_EQ(q.relative_kinetic_energy, 0.0) << "t = " << t;
      // The full mass properties agree with what the dynamics sees.
      const model::MassProperties mp_e = exact.MassPropertiesAt(t);
      const model::MassProperties mp_q = quasi.MassPropertiesAt(t);
      EXPECT_EQ(mp_e.h_rel_B, e.h_rel_B);
      EXPECT_EQ(mp_q.h_rel_B, Vec3::Zero());
      EXPECT_EQ(mp_e.relative_kinetic_energy, e.relative_kinetic_energy);
      EXPECT_EQ(mp_q.relative_kinetic_energy, 0.0);
      EXPECT_LT((mp_e.com_B - ref.com_B).norm(), kRoundoff);
      EXPECT_GT(mp_e.com_rate_B.norm(), 0.0);
      EXPECT_DOUBLE_EQ(mp_e.mass, 90.0);
    }
  }
}

TEST(DeploymentScheduleTest, TotalKineticEnergyAddsTheRelativeMotion) {
  // dynamics::TotalKineticEnergy = 1/2 w.J w + w.h_rel + T_rel with w = J^-1 (H - h_rel);
  // without relative motion (holds, quasi-rigid coupling, tensor mode) it is 1/2 w.J w.
  const Vec3 H_B(0.3, 6.0, -0.2);
  for (const Case& c : AllCases()) {
    SCOPED_TRACE(c.label);
    const DeploymentSchedule sched(MakeProfile(c.model, c.mode, c.coupling, Law::kSmoothstep));
    for (double t : MovingTimes()) {
      const InertiaSample s = sched.Evaluate(t);
      const Vec3 w = s.J_inv_B * (H_B - s.h_rel_B);
      const double rigid = 0.5 * w.dot(s.J_B * w);
      const double T = dynamics::TotalKineticEnergy(s, H_B);
      EXPECT_NEAR(T, rigid + w.dot(s.h_rel_B) + s.relative_kinetic_energy, kRoundoff * rigid);
      if (c.coupling == Coupling::kExact) {
        EXPECT_GT(std::abs(T - rigid), 1e3 * kRoundoff * rigid) << "t = " << t;
      } else {
        EXPECT_EQ(s.relative_kinetic_energy, 0.0) << "t = " << t;
        EXPECT_NEAR(T, rigid, kRoundoff * rigid) << "t = " << t;
      }
    }
    const InertiaSample hold = sched.Evaluate(5.0);
    EXPECT_EQ(hold.relative_kinetic_energy, 0.0);
  }
}

TEST(DeploymentScheduleTest, HingedModelInTensorModeInterpolatesConfigurationTensors) {
  const model::Model m = HingedModel();
  const model::HingedBody body = model::ValidatedHingedBody(m.hinged, "test");
  auto config_J = [&](const std::string& name) -> Mat3 {
    const Eigen::VectorXd theta = m.configuration(name).hinge_angles;
    return model::ComputeMassProperties(body, theta, Eigen::VectorXd::Zero(theta.size())).J_B;
  };
  const DeploymentSchedule tensor(
      MakeProfile(m, Mode::kTensor, Coupling::kQuasiRigid, Law::kLinear));
  const DeploymentSchedule geometry(
      MakeProfile(m, Mode::kGeometry, Coupling::kQuasiRigid, Law::kLinear));
  const Mat3 closed = config_J("closed");
  const Mat3 half_open = config_J("half_open");
  EXPECT_LT(MaxAbs(tensor.Evaluate(5.0).J_B - closed), kRoundoff * MaxAbs(closed));
  EXPECT_LT(MaxAbs(tensor.Evaluate(27.0).J_B - half_open), kRoundoff * MaxAbs(closed));
  // Halfway through the first move (linear law): the mean of the tensors, which is not
  // the tensor at the mean angles.
  const Mat3 mid = tensor.Evaluate(17.5).J_B;
  EXPECT_LT(MaxAbs(mid - 0.5 * (closed + half_open)), kRoundoff * MaxAbs(closed));
  EXPECT_GT(MaxAbs(mid - geometry.Evaluate(17.5).J_B), 1e-2 * MaxAbs(closed));
  EXPECT_EQ(tensor.Evaluate(17.5).h_rel_B, Vec3::Zero());
  EXPECT_EQ(tensor.HingeAngles(17.5).size(), 0);
  EXPECT_EQ(tensor.HingeRates(17.5).size(), 0);
  EXPECT_EQ(tensor.HingeAccelerations(17.5).size(), 0);
}

TEST(DeploymentScheduleTest, NormalizesHingeAxes) {
  model::Model scaled = HingedModel();
  scaled.hinged.panels[0].hinge_axis_B = Vec3(0.0, 2.5, 0.0);
  const DeploymentSchedule a(
      MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kSmoothstep));
  const DeploymentSchedule b(
      MakeProfile(scaled, Mode::kGeometry, Coupling::kExact, Law::kSmoothstep));
  const InertiaSample sa = a.Evaluate(17.0);
  const InertiaSample sb = b.Evaluate(17.0);
  EXPECT_LT(MaxAbs(sa.J_B - sb.J_B), kRoundoff * MaxAbs(sa.J_B));
  EXPECT_LT((sa.h_rel_B - sb.h_rel_B).norm(), kRoundoff * MaxAbs(sa.J_B));
}

TEST(DeploymentScheduleTest, BreakpointsAreStageBoundariesStrictlyInside) {
  const DeploymentSchedule sched(
      MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kLinear));
  EXPECT_EQ(sched.Breakpoints(0.0, 60.0), (std::vector<double>{10.0, 25.0, 30.0, 50.0}));
  EXPECT_EQ(sched.Breakpoints(10.0, 50.0), (std::vector<double>{25.0, 30.0}));
  EXPECT_EQ(sched.Breakpoints(-5.0, 70.0),
            (std::vector<double>{0.0, 10.0, 25.0, 30.0, 50.0, 60.0}));
  EXPECT_EQ(sched.Breakpoints(11.0, 24.0), std::vector<double>{});
  // An interval ending an ulp away from a boundary does not get a sliver segment.
  EXPECT_EQ(sched.Breakpoints(10.0 * (1.0 - 1e-15), 50.0 * (1.0 + 1e-15)),
            (std::vector<double>{25.0, 30.0}));
}

TEST(DeploymentScheduleTest, TheShortestStagesKeepTheirBoundariesAsBreakpoints) {
  // Stages of 1.01 x the minimum duration (ValidateProfile) at the start, in the middle
  // and at the end: every boundary is a breakpoint, and each side of it sees its own stage
  // (the linear law's rate jump at the end of a short first hold is where a dropped
  // boundary used to give an error in H_B that no integrator tolerance removed).
  Profile p = MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kLinear);
  const double d = 1.01 * kMinStageDurationFraction * 60.0;
  p.stages[0].t_end = p.stages[1].t_begin = d;
  p.stages[2].t_end = p.stages[3].t_begin = 25.0 + d;
  p.stages[4].t_begin = p.stages[3].t_end = 60.0 - d;
  const DeploymentSchedule sched(p);
  EXPECT_EQ(sched.Breakpoints(0.0, 60.0), (std::vector<double>{d, 25.0, 25.0 + d, 60.0 - d}));
  for (double t : {d, 25.0 + d}) {
    SCOPED_TRACE("move starts at t = " + std::to_string(t));
    EXPECT_EQ(sched.Evaluate(t, Side::kLeft).h_rel_B, Vec3::Zero());
    EXPECT_NE(sched.Evaluate(t, Side::kRight).h_rel_B, Vec3::Zero());
    EXPECT_EQ(sched.StageAt(t, Side::kLeft) + 1, sched.StageAt(t, Side::kRight));
  }
  EXPECT_NE(sched.Evaluate(60.0 - d, Side::kLeft).h_rel_B, Vec3::Zero());
  EXPECT_EQ(sched.Evaluate(60.0 - d, Side::kRight).h_rel_B, Vec3::Zero());
  EXPECT_EQ(sched.StageAt(0.5 * d), 0);
  EXPECT_EQ(sched.StageAt(25.0 + 0.5 * d), 2);
  EXPECT_EQ(sched.StageAt(60.0 - 0.5 * d), 4);
  EXPECT_FALSE(sched.IsRigidOn(0.0, 2.0 * d));
  EXPECT_TRUE(sched.IsRigidOn(0.0, d));
}

TEST(DeploymentScheduleTest, StageAtIsOneSidedAtBoundaries) {
  const DeploymentSchedule sched(
      MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kLinear));
  EXPECT_EQ(sched.StageAt(5.0), 0);
  EXPECT_EQ(sched.StageAt(10.0), 1);
  EXPECT_EQ(sched.StageAt(10.0, Side::kRight), 1);
  EXPECT_EQ(sched.StageAt(10.0, Side::kLeft), 0);
  EXPECT_EQ(sched.StageAt(50.0, Side::kLeft), 3);
  EXPECT_EQ(sched.StageAt(50.0, Side::kRight), 4);
  EXPECT_EQ(sched.StageAt(-1.0), 0);
  EXPECT_EQ(sched.StageAt(0.0, Side::kLeft), 0);
  EXPECT_EQ(sched.StageAt(60.0), 4);
  EXPECT_EQ(sched.StageAt(1e6), 4);
}

TEST(DeploymentScheduleTest, LinearLawJumpsRatesButNotInertiaAtBoundaries) {
  // Exact coupling: theta' jumps at both ends of a linear move, so h_rel jumps; J does not.
  const DeploymentSchedule sched(
      MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kLinear));
  for (double t : {10.0, 25.0, 30.0, 50.0}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    const InertiaSample left = sched.Evaluate(t, Side::kLeft);
    const InertiaSample right = sched.Evaluate(t, Side::kRight);
    const double scale = MaxAbs(left.J_B);
    EXPECT_LT(MaxAbs(left.J_B - right.J_B), kRoundoff * scale);
    EXPECT_GT((left.h_rel_B - right.h_rel_B).norm(), kNonZero * scale / 20.0);
    EXPECT_GT(MaxAbs(left.Jdot_B - right.Jdot_B), kNonZero * scale / 20.0);
    // One side is a hold: no relative motion there.
    const bool move_starts = t == 10.0 || t == 30.0;
    EXPECT_EQ((move_starts ? left : right).h_rel_B, Vec3::Zero());
    EXPECT_EQ((move_starts ? left : right).Jdot_B, Mat3::Zero());
  }
}

TEST(DeploymentScheduleTest, SmoothLawsHaveContinuousRatesAtBoundaries) {
  for (Law law : {Law::kSmoothstep, Law::kMinimumJerk}) {
    SCOPED_TRACE(ToString(law));
    const DeploymentSchedule sched(
        MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, law));
    for (double t : {10.0, 25.0, 30.0, 50.0}) {
      const InertiaSample left = sched.Evaluate(t, Side::kLeft);
      const InertiaSample right = sched.Evaluate(t, Side::kRight);
      EXPECT_EQ(left.J_B, right.J_B) << "t = " << t;
      EXPECT_EQ(left.Jdot_B, Mat3::Zero()) << "t = " << t;
      EXPECT_EQ(right.Jdot_B, Mat3::Zero()) << "t = " << t;
      EXPECT_EQ(left.h_rel_B, right.h_rel_B) << "t = " << t;
      EXPECT_EQ(sched.HingeRates(t, Side::kLeft), sched.HingeRates(t, Side::kRight));
    }
    // Accelerations: minimum-jerk is C2 (zero at the ends), smoothstep jumps.
    const double acc_end = sched.HingeAccelerations(10.0, Side::kRight).cwiseAbs().maxCoeff();
    if (law == Law::kMinimumJerk) {
      EXPECT_EQ(acc_end, 0.0);
    } else {
      EXPECT_GT(acc_end, 0.0);
    }
  }
}

TEST(DeploymentScheduleTest, TimesWithinRoundingOfABoundaryTakeTheRequestedSide) {
  // An integrator's last stage time t + h may miss the breakpoint by an ulp.
  const DeploymentSchedule sched(
      MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kLinear));
  const double past = 25.0 * (1.0 + 4e-16);
  const double before = 25.0 * (1.0 - 4e-16);
  ASSERT_GT(past, 25.0);
  ASSERT_LT(before, 25.0);
  EXPECT_EQ(sched.Evaluate(past, Side::kLeft).h_rel_B, sched.Evaluate(25.0, Side::kLeft).h_rel_B);
  EXPECT_NE(sched.Evaluate(past, Side::kLeft).h_rel_B, Vec3::Zero());
  EXPECT_EQ(sched.Evaluate(before, Side::kRight).h_rel_B, Vec3::Zero());
  EXPECT_EQ(sched.StageAt(past, Side::kLeft), 1);
  EXPECT_EQ(sched.StageAt(before, Side::kRight), 2);
  // Away from the boundary the side does not matter.
  EXPECT_EQ(sched.Evaluate(24.9, Side::kLeft).h_rel_B, sched.Evaluate(24.9, Side::kRight).h_rel_B);
}

TEST(DeploymentScheduleTest, StepLawSwitchesAtStageStart) {
  for (Mode mode : {Mode::kTensor, Mode::kGeometry}) {
    SCOPED_TRACE(ToString(mode));
    const model::Model m = mode == Mode::kTensor ? TensorModel() : HingedModel();
    const DeploymentSchedule sched(MakeProfile(m, mode, Coupling::kQuasiRigid, Law::kStep));
    const Mat3 closed = sched.Evaluate(5.0).J_B;
    const Mat3 half_open = sched.Evaluate(27.0).J_B;
    ASSERT_GT(MaxAbs(closed - half_open), kNonZero * MaxAbs(closed));
    EXPECT_EQ(sched.Evaluate(10.0, Side::kLeft).J_B, closed);
    EXPECT_EQ(sched.Evaluate(10.0, Side::kRight).J_B, half_open);
    for (double t : {10.001, 17.5, 25.0}) {
      const InertiaSample s = sched.Evaluate(t, Side::kLeft);
      EXPECT_EQ(s.J_B, half_open) << "t = " << t;
      EXPECT_EQ(s.Jdot_B, Mat3::Zero()) << "t = " << t;
      EXPECT_EQ(s.h_rel_B, Vec3::Zero()) << "t = " << t;
    }
    if (mode == Mode::kGeometry) {
      EXPECT_EQ(sched.HingeAngles(10.0, Side::kLeft),
                HingedModel().configuration("closed").hinge_angles);
      EXPECT_EQ(sched.HingeAngles(10.0, Side::kRight),
                HingedModel().configuration("half_open").hinge_angles);
      EXPECT_EQ(sched.HingeRates(17.5), Eigen::VectorXd::Zero(2));
    }
  }
}

TEST(DeploymentScheduleTest, IsRigidOnHoldsAndAfterStepSwitch) {
  for (Coupling coupling : {Coupling::kQuasiRigid, Coupling::kExact}) {
    SCOPED_TRACE(ToString(coupling));
    const DeploymentSchedule sched(
        MakeProfile(HingedModel(), Mode::kGeometry, coupling, Law::kSmoothstep));
    EXPECT_TRUE(sched.IsRigidOn(0.0, 10.0));
    EXPECT_TRUE(sched.IsRigidOn(2.0, 3.0));
    EXPECT_TRUE(sched.IsRigidOn(25.0, 30.0));
    EXPECT_TRUE(sched.IsRigidOn(50.0, 60.0));
    EXPECT_FALSE(sched.IsRigidOn(5.0, 12.0));   // spans the start of a move
    EXPECT_FALSE(sched.IsRigidOn(11.0, 12.0));  // inside a move
    EXPECT_FALSE(sched.IsRigidOn(10.0, 25.0));  // exactly a move
    EXPECT_FALSE(sched.IsRigidOn(24.0, 26.0));
    EXPECT_FALSE(sched.IsRigidOn(0.0, 60.0));
    // Bounds within rounding of the stage bounds.
    EXPECT_TRUE(sched.IsRigidOn(25.0 * (1.0 - 1e-14), 30.0 * (1.0 + 1e-14)));
    // Outside the stages the schedule holds the end configurations.
    EXPECT_TRUE(sched.IsRigidOn(60.0, 100.0));
    EXPECT_TRUE(sched.IsRigidOn(-10.0, 0.0));
  }
  // Step law (quasi-rigid only): rigid from the switch on, including the stage start.
  const DeploymentSchedule step(
      MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kQuasiRigid, Law::kStep));
  EXPECT_TRUE(step.IsRigidOn(10.0, 25.0));
  EXPECT_TRUE(step.IsRigidOn(12.0, 13.0));
  EXPECT_FALSE(step.IsRigidOn(9.0, 11.0));  // across the switch
  EXPECT_FALSE(step.IsRigidOn(20.0, 27.0));
  const DeploymentSchedule tensor_step(
      MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kStep));
  EXPECT_TRUE(tensor_step.IsRigidOn(30.0, 50.0));
  EXPECT_FALSE(tensor_step.IsRigidOn(29.0, 50.0));
}

TEST(DeploymentScheduleTest, ClampsOutsideTheStages) {
  // Stages: a move from `from` at t = 0 and a linear move ending at the profile's end.
  Profile p = MakeProfile(HingedModel(), Mode::kGeometry, Coupling::kExact, Law::kLinear);
  p.stages = {Move("closed", "half_open", Law::kLinear, 0.0, 10.0),
              Move("half_open", "open", Law::kLinear, 10.0, 20.0)};
  const DeploymentSchedule sched(p);
  const model::Model m = HingedModel();
  const model::HingedBody body = model::ValidatedHingedBody(m.hinged, "test");
  const Mat3 closed = model::ComputeMassProperties(body, m.configuration("closed").hinge_angles,
                                                   Eigen::VectorXd::Zero(2))
                          .J_B;
  const Mat3 open = model::ComputeMassProperties(body, m.configuration("open").hinge_angles,
                                                 Eigen::VectorXd::Zero(2))
                        .J_B;
  const double scale = MaxAbs(closed);
  for (const InertiaSample& s : {sched.Evaluate(-5.0), sched.Evaluate(0.0, Side::kLeft)}) {
    EXPECT_LT(MaxAbs(s.J_B - closed), kRoundoff * scale);
    EXPECT_EQ(s.Jdot_B, Mat3::Zero());
    EXPECT_EQ(s.h_rel_B, Vec3::Zero());
  }
  for (const InertiaSample& s : {sched.Evaluate(25.0), sched.Evaluate(20.0, Side::kRight)}) {
    EXPECT_LT(MaxAbs(s.J_B - open), kRoundoff * scale);
    EXPECT_EQ(s.Jdot_B, Mat3::Zero());
    EXPECT_EQ(s.h_rel_B, Vec3::Zero());
  }
  // Inside the first and last stage the rates are on.
  EXPECT_NE(sched.Evaluate(0.0, Side::kRight).h_rel_B, Vec3::Zero());
  EXPECT_NE(sched.Evaluate(20.0, Side::kLeft).h_rel_B, Vec3::Zero());
  EXPECT_EQ(sched.HingeAngles(-5.0), m.configuration("closed").hinge_angles);
  EXPECT_EQ(sched.HingeAngles(99.0), m.configuration("open").hinge_angles);
  EXPECT_EQ(sched.HingeRates(99.0), Eigen::VectorXd::Zero(2));
  EXPECT_EQ(sched.Breakpoints(-1.0, 21.0), (std::vector<double>{0.0, 10.0, 20.0}));
}

TEST(DeploymentScheduleTest, TensorInterpolationStaysPhysicallyValid) {
  // Both ends on the triangle-inequality boundary (flat plates), with different principal
  // axes: every convex combination is still a valid inertia.
  model::Model m;
  m.name = "plates";
  m.kind = model::ModelKind::kTensors;
  const Mat3 R = math::ExpSO3(Vec3(0.4, -0.7, 1.1));
  const Mat3 b = R * Vec3(3.0, 1.0, 2.0).asDiagonal() * R.transpose();
  m.configurations = {testing::TensorConfiguration("a", Vec3(1.0, 2.0, 3.0).asDiagonal()),
                      testing::TensorConfiguration("b", 0.5 * (b + b.transpose()))};
  for (Law law : kMovingLaws) {
    SCOPED_TRACE(ToString(law));
    Profile p = MakeProfile(m, Mode::kTensor, Coupling::kQuasiRigid, law);
    p.stages = {Hold("a", 0.0, 1.0), Move("a", "b", law, 1.0, 2.0), Hold("b", 2.0, 3.0)};
    const DeploymentSchedule sched(p);
    for (int i = 0; i <= 3000; ++i) {
      const double t = i / 1000.0;
      const InertiaSample s = sched.Evaluate(t);
      EXPECT_EQ(math::InertiaTensor::Check(s.J_B), "") << "t = " << t;
      EXPECT_LT(MaxAbs(s.J_inv_B * s.J_B - Mat3::Identity()), kRoundoff) << "t = " << t;
      EXPECT_EQ(s.J_inv_B, s.J_inv_B.transpose()) << "t = " << t;
    }
  }
}

TEST(DeploymentScheduleTest, ResolvesImplicitFromAndWorksThroughTheInterface) {
  Profile p = MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kSmoothstep);
  p.stages[1].from.clear();
  p.stages[3].from.clear();
  const std::unique_ptr<dynamics::InertiaSource> source = std::make_unique<DeploymentSchedule>(p);
  const auto& sched = static_cast<const DeploymentSchedule&>(*source);
  EXPECT_EQ(sched.stages()[1].from, "closed");
  EXPECT_EQ(sched.stages()[3].from, "half_open");
  EXPECT_EQ(source->Evaluate(27.0).J_B, Mat3(Vec3(10.0, 7.0, 7.0).asDiagonal()));
  EXPECT_EQ(source->Breakpoints(0.0, 60.0).size(), 4u);
  EXPECT_TRUE(source->IsRigidOn(0.0, 10.0));
}

TEST(DeploymentScheduleTest, ConstructorValidatesTheProfile) {
  Profile p = MakeProfile(TensorModel(), Mode::kTensor, Coupling::kQuasiRigid, Law::kLinear);
  p.stages[2].t_end = 20.0;
  EXPECT_THROW(DeploymentSchedule{p}, std::invalid_argument);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::schedule
