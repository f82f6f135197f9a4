#include "deploysim/run/mission.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/run/run_recorder.h"
#include "deploysim/run/trajectory_schema.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::run {

math::Vec3 Euler313RelativeToMomentum(const math::Quat& q_NB, const math::Vec3& h_N) {
  const math::Vec3 e3 = h_N.normalized();
  // e1: the inertial x axis made perpendicular to e3 (y if x is nearly parallel).
  math::Vec3 ref = std::abs(e3.x()) < 0.9 ? math::Vec3::UnitX() : math::Vec3::UnitY();
  const math::Vec3 e1 = (ref - ref.dot(e3) * e3).normalized();
  const math::Vec3 e2 = e3.cross(e1);
  math::Mat3 R_PN;
  R_PN.row(0) = e1.transpose();
  R_PN.row(1) = e2.transpose();
  R_PN.row(2) = e3.transpose();
  const math::Mat3 R = R_PN * q_NB.toRotationMatrix();
  // R = Rz(phi) Rx(theta) Rz(psi): R(2,2) = cos(theta), R(0,2) = sin(phi) sin(theta),
  // R(1,2) = -cos(phi) sin(theta), R(2,0) = sin(theta) sin(psi), R(2,1) = sin(theta) cos(psi).
  const double s = std::hypot(R(0, 2), R(1, 2));
  const double theta = std::atan2(s, R(2, 2));
  double phi;
  double psi;
  if (s < 1e-12) {
    // Nutation 0 or pi: only phi +- psi is defined; put it all in the precession.
    psi = 0.0;
    phi = std::atan2(R(1, 0), R(0, 0));
  } else {
    phi = std::atan2(R(0, 2), -R(1, 2));
    psi = std::atan2(R(2, 0), R(2, 1));
  }
  return math::Vec3(phi, theta, psi);
}

namespace {

/// The in-memory RunMission: appends every block to a trajectory.
class CollectSink final : public SampleSink {
 public:
  explicit CollectSink(Trajectory& t) : t_(t) {}
  void Append(const Trajectory& b) override { TrajectorySchema::Standard().Append(t_, b); }

 private:
  Trajectory& t_;
};

}  // namespace

MissionResult RunMission(const schedule::Profile& profile,
                         const std::function<void(double)>& progress) {
  Trajectory collected;
  CollectSink sink(collected);
  MissionResult out = RunMission(profile, sink, progress);
  out.trajectory = std::move(collected);
  return out;
}

void SetRigidPrediction(StageReport& rep,
                        const math::Mat3& J_B,
                        const math::Vec3& H_B,
                        const math::Quat& q_NB,
                        const math::Vec3& spin_axis_B) {
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(J_B), H_B, q_NB,
                                       rep.t_begin);
  rep.regime = analysis::ToString(sol.regime());
  rep.one_minus_k2 = sol.complementary_parameter();
  rep.predicted_flip_half_period = sol.flip_half_period();
  if (analysis::LocateSpinAxis(J_B, spin_axis_B).role == analysis::AxisRole::kIntermediate) {
    rep.predicted_flips = sol.FlipTimes(rep.t_begin, rep.t_end);
  } else {
    rep.predicted_flip_half_period = std::numeric_limits<double>::infinity();
  }
  for (double tf : rep.observed_flips) {
    double nearest = std::numeric_limits<double>::infinity();
    for (double tp : rep.predicted_flips) nearest = std::min(nearest, std::abs(tf - tp));
    if (std::isfinite(nearest)) {
      rep.max_flip_time_difference = std::max(rep.max_flip_time_difference, nearest);
    }
  }
}

void SetRigidBodyCaveat(StageReport& report, bool dissipative) {
  switch (report.spin_axis_end) {
    case analysis::AxisRole::kMinor:
      report.rigid_body_only = true;
      report.caveat =
          dissipative
              ? "minor-axis spin with energy dissipation in this stage: not stable, the spin "
                "drifts towards the major axis (major-axis rule)"
              : "minor-axis spin: stable only for a perfectly rigid body; any energy "
                "dissipation (flexible panels, dampers, fuel) drives it into a flat spin about "
                "the major axis (Explorer 1, 1958)";
      break;
    case analysis::AxisRole::kMajor:
      report.rigid_body_only = false;
      report.caveat = "major-axis spin: stable, also with energy dissipation";
      break;
    case analysis::AxisRole::kIntermediate:
      report.rigid_body_only = false;
      report.caveat = "intermediate-axis spin: unstable (flips), with or without dissipation";
      break;
    case analysis::AxisRole::kDegenerate:
      report.rigid_body_only = true;
      report.caveat =
          "two principal moments are equal: neutral for a rigid body; small asymmetries and "
          "energy dissipation decide where the spin goes";
      break;
  }
}

math::Vec3 InitialMomentum(const schedule::Profile& profile, const dynamics::InertiaSample& s0) {
  return profile.initial.H_B ? *profile.initial.H_B
                             : math::Vec3(s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B);
}

integrators::IntegratorSettings SettingsOf(const schedule::Profile& profile) {
  integrators::IntegratorSettings settings;
  settings.step = profile.integrator.step;
  settings.tolerances = {profile.integrator.rtol, profile.integrator.atol};
  settings.max_step = profile.integrator.max_step;
  return settings;
}

integrators::State InitialState(const schedule::Profile& profile,
                                const dynamics::InertiaSource& source) {
  const std::string where = profile.source.empty() ? profile.name : profile.source;
  integrators::State y0;
  y0.t = profile.t_begin();
  y0.q_NB = math::ValidateUnitQuaternion(profile.initial.q_NB, where + ": initial attitude");
  y0.H_B = InitialMomentum(profile, source.Evaluate(y0.t));
  if (!((y0.q_NB * y0.H_B).norm() > 0.0)) {
    throw std::invalid_argument(where + ": initial: zero angular momentum");
  }
  return y0;
}

MissionResult RunMission(const schedule::Profile& profile,
                         SampleSink& sink,
                         const std::function<void(double)>& progress,
                         const RunOptions& options) {
  return RunMission(*CompiledRun::Compile(profile), sink, progress, options);
}

}  // namespace deploysim::run
