#include "deploysim/run/stage_body.h"

#include <algorithm>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/dynamics/rigid_body.h"

namespace deploysim::run {

StageBody::StageBody(const CompiledRun& run)
    : run_(run),
      sched_(*run.schedule()),
      stages_(run.profile().stages),
      geometry_(run.profile().mode == schedule::Mode::kGeometry),
      cached_stage_(stages_.size()) {
  for (const schedule::Stage& st : stages_) {
    stage_rigid_.push_back(sched_.IsRigidOn(st.t_begin, st.t_end));
  }
}

void StageBody::Start(RunState& st) { st.y = InitialState(run_.profile(), sched_); }

RunSample StageBody::SampleWith(double t,
                                const math::Vec3& H_B,
                                const math::Quat& q_NB,
                                const dynamics::InertiaSample& js) const {
  RunSample o;
  o.t = t;
  o.H_B = H_B;
  o.q_NB = q_NB;
  o.w = dynamics::AngularVelocity(js, H_B);
  o.J_B = js.J_B;
  o.h_rel_B = js.h_rel_B;
  o.kinetic = dynamics::TotalKineticEnergy(js, H_B);
  if (geometry_) {
    o.theta = sched_.HingeAngles(t);
    o.theta_dot = sched_.HingeRates(t);
  }
  return o;
}

RunSample StageBody::SampleOf(double t,
                              const math::Vec3& H_B,
                              const math::Quat& q_NB,
                              const Eigen::VectorXd& /*x*/,
                              dynamics::Side side) const {
  return SampleWith(t, H_B, q_NB, sched_.Evaluate(t, side));
}

RunSample StageBody::GridSample(double t,
                                const math::Vec3& H_B,
                                const math::Quat& q_NB,
                                double /*t1*/) {
  while (stage_ + 1 < stages_.size() && t >= stages_[stage_].t_end) ++stage_;
  const bool interior = stage_ < stages_.size() && stage_rigid_[stage_] &&
                        t > stages_[stage_].t_begin && t < stages_[stage_].t_end;
  if (!interior) return SampleWith(t, H_B, q_NB, sched_.Evaluate(t));
  if (cached_stage_ != stage_) {
    stage_sample_ = sched_.Evaluate(t);
    cached_stage_ = stage_;
  }
  return SampleWith(t, H_B, q_NB, stage_sample_);
}

std::vector<double> StageBody::PhaseBoundaries(double t0, double t1) const {
  std::vector<double> out;
  for (const schedule::Stage& st : stages_) {
    if (st.t_end > t0 && st.t_end < t1) out.push_back(st.t_end);
  }
  return out;
}

PhaseInfo StageBody::Describe(double t) const {
  // The stage that begins at t (the last one whose start is at most t).
  const auto it =
      std::upper_bound(stages_.begin(), stages_.end(), t,
                       [](double x, const schedule::Stage& st) { return x < st.t_begin; });
  const std::size_t i =
      it == stages_.begin() ? 0 : static_cast<std::size_t>(it - stages_.begin()) - 1;
  const schedule::Stage& st = stages_[i];
  PhaseInfo info;
  info.name = st.name;
  info.law = st.is_hold() ? "hold" : schedule::ToString(st.law);
  info.rigid = stage_rigid_[i];
  info.rotor = sched_.Evaluate(t, dynamics::Side::kRight).h_rel_B.norm() > 0.0;
  return info;
}

analysis::SteadySpin StageBody::Steady(const RunSample& start, const PhaseInfo& info) const {
  if (!info.rigid) {
    analysis::SteadySpin steady;
    steady.reason = "the inertia changes in this stage";
    return steady;
  }
  return analysis::LinearizeSteadySpin(analysis::FlowOf(start.J_B, start.h_rel_B), start.H_B);
}

}  // namespace deploysim::run
