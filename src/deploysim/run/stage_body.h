#pragma once

/// The body of a stage profile for the run loop (run_loop.h, docs/design.md 2.6): a body
/// whose shape follows the deployment schedule, J_B(t) and h_rel_B(t) given for every
/// time; its phases are the profile's stages. Nothing is ever free: the loop runs one
/// rigid-path segment from the first stage's start to the last one's end.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "deploysim/run/run_loop.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::run {

class StageBody final : public RunBody {
 public:
  /// `run`: a compiled stage profile (its schedule built).
  explicit StageBody(const CompiledRun& run);

  const dynamics::InertiaSource& source() const override { return sched_; }
  void Start(RunState& st) override;
  /// The hinge angles and rates (geometry mode) are continuous across a stage boundary:
  /// a sample's are the schedule's right limits whatever the side of J_B.
  RunSample SampleOf(double t,
                     const math::Vec3& H_B,
                     const math::Quat& q_NB,
                     const Eigen::VectorXd& x,
                     dynamics::Side side) const override;
  /// Inside a rigid stage the inertia sample is the same at every time: evaluated once
  /// per stage. Elsewhere J_B's right limit (the last stage's end included).
  RunSample GridSample(double t, const math::Vec3& H_B, const math::Quat& q_NB, double t1) override;
  /// The stage ends but the last.
  std::vector<double> PhaseBoundaries(double t0, double t1) const override;
  PhaseInfo Describe(double t) const override;
  analysis::SteadySpin Steady(const RunSample& start, const PhaseInfo& info) const override;

 private:
  RunSample SampleWith(double t,
                       const math::Vec3& H_B,
                       const math::Quat& q_NB,
                       const dynamics::InertiaSample& js) const;

  const CompiledRun& run_;
  const schedule::DeploymentSchedule& sched_;
  const std::vector<schedule::Stage>& stages_;
  const bool geometry_;
  std::vector<bool> stage_rigid_;
  std::size_t stage_ = 0;  // the stage of the last grid sample
  std::size_t cached_stage_;
  dynamics::InertiaSample stage_sample_{};
};

}  // namespace deploysim::run
