#include "deploysim/crosscheck/spring_deployment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deploysim/run/compiled_run.h"
#include "deploysim/run/run_loop.h"
#include "deploysim/run/trajectory_schema.h"
#include "deploysim/crosscheck/hinge_history.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::crosscheck {

namespace {

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) { return math::FormatSignificant(x); }

/// First time hinge k reaches `open` (moving from `closed`), linear between knots.
double LatchTime(const HingeHistory& h, Eigen::Index k, double closed, double open) {
  const double direction = open >= closed ? 1.0 : -1.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double past = (h.angle[i][k] - open) * direction;
    if (past >= 0.0) {
      if (i == 0) return h.time[0];
      const double before = (h.angle[i - 1][k] - open) * direction;
      return h.time[i - 1] + (h.time[i] - h.time[i - 1]) * (-before) / (past - before);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// The reduced model driven by Simbody's hinge history, for the run loop: one phase, the
/// hinge angles and rates interpolated from the history.
class ReplayBody final : public run::RunBody {
 public:
  ReplayBody(const HingeHistorySource& source, const integrators::State& y0)
      : source_(source), y0_(y0) {}
  const dynamics::InertiaSource& source() const override { return source_; }
  void Start(run::RunState& st) override { st.y = y0_; }
  run::RunSample SampleOf(double t,
                               const math::Vec3& H_B,
                               const math::Quat& q_NB,
                               const Eigen::VectorXd& /*x*/,
                               dynamics::Side side) const override {
    const dynamics::InertiaSample js = source_.Evaluate(t, side);
    const HingeState hinges = source_.Interpolate(t, side);
    run::RunSample o;
    o.t = t;
    o.H_B = H_B;
    o.q_NB = q_NB;
    o.w = dynamics::AngularVelocity(js, H_B);
    o.J_B = js.J_B;
    o.h_rel_B = js.h_rel_B;
    o.kinetic = dynamics::TotalKineticEnergy(js, H_B);
    o.theta = hinges.angle;
    o.theta_dot = hinges.rate;
    return o;
  }
  std::vector<double> PhaseBoundaries(double /*t0*/, double /*t1*/) const override { return {}; }
  run::PhaseInfo Describe(double /*t*/) const override {
    run::PhaseInfo info;
    info.name = "replay of Simbody's hinge history";
    info.law = "replayed";
    return info;
  }
  analysis::SteadySpin Steady(const run::RunSample& /*start*/,
                              const run::PhaseInfo& /*info*/) const override {
    analysis::SteadySpin none;
    none.reason = "the inertia follows the replayed hinge history";
    return none;
  }

 private:
  const HingeHistorySource& source_;
  integrators::State y0_;
};

class CollectSink final : public run::SampleSink {
 public:
  void Append(const run::Trajectory& b) override {
    run::TrajectorySchema::Standard().Append(all, b);
  }
  run::Trajectory all;
};

}  // namespace

SpringDeploymentResult RunSpringDeployment(const schedule::Profile& profile,
                                           const SpringDeploymentOptions& options) {
  schedule::Profile p = options.t_end ? TruncateProfile(profile, *options.t_end) : profile;
  if (p.mode != schedule::Mode::kGeometry) {
    throw std::invalid_argument(p.source + ": spring deployment needs geometry mode");
  }
  p.coupling = schedule::Coupling::kExact;
  if (options.output_dt) p.output.dt = *options.output_dt;
  // The replay runs with the options' integrator: compiled (and validated) once.
  schedule::Profile replay = p;
  replay.integrator = schedule::IntegratorSpec{};
  replay.integrator.method = options.replay_method;
  replay.integrator.rtol = options.replay_rtol;
  replay.integrator.atol = options.replay_atol;
  const std::shared_ptr<const run::CompiledRun> compiled =
      run::CompiledRun::Compile(replay);
  (void)p.model.configuration(options.drive.open);  // throws listing the valid names

  SpringDeploymentResult r;
  const std::vector<double> grid = integrators::UniformGrid(p.t_begin(), p.t_end(), p.output.dt);
  const math::Vec3 H_B0 = InitialMomentum(p);
  const model::HingedBody body = model::ValidatedHingedBody(p.model.hinged, p.model.source);
  const Eigen::VectorXd closed = p.model.configuration(p.stages.front().from).hinge_angles;
  const math::Mat3 J0 =
      model::ComputeMassProperties(body, closed, Eigen::VectorXd::Zero(closed.size())).J_B;
  const math::Vec3 spin_axis_B = analysis::InitialSpinAxis(J0, H_B0);

  SimbodyOptions so;
  so.accuracy = options.accuracy;
  r.simbody = RunSimbodySpring(p, options.drive, grid, spin_axis_B, so);

  // Replay with exact coupling, in the run loop (its flips, samples and drift).
  const auto wall0 = std::chrono::steady_clock::now();
  const HingeHistorySource source(body, r.simbody.history);
  integrators::State y0;
  y0.t = p.t_begin();
  y0.q_NB = p.initial.q_NB.normalized();
  y0.H_B = H_B0;
  ReplayBody replay_body(source, y0);
  CollectSink sink;
  run::RunOptions run_options;
  run_options.spin_axis_B = spin_axis_B;
  const run::MissionResult run =
      run::RunLoop(*compiled, replay_body, &sink, {}, run_options);
  if (run.termination != integrators::Termination::kReachedEnd) {
    throw std::runtime_error(p.source + ": spring replay: integration " + run.message);
  }
  r.replay_stats = run.stats;
  r.replay_flip_times = run.flip_times;
  r.replay = std::move(sink.all);
  r.replay_max_h_N_drift = run.max_h_N_drift;
  r.replay_wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  r.difference = CompareTrajectories(r.replay, r.simbody.trajectory);
  r.max_flip_difference = MaxFlipDifference(r.replay_flip_times, r.simbody.flip_times);
  const Eigen::VectorXd open = p.model.configuration(options.drive.open).hinge_angles;
  for (Eigen::Index k = 0; k < closed.size(); ++k) {
    r.latch_times.push_back(LatchTime(r.simbody.history, k, closed[k], open[k]));
  }
  r.profile = std::move(p);
  return r;
}

std::string FormatSpringDeploymentTable(const SpringDeploymentResult& r) {
  std::ostringstream o;
  o << "Spring-driven deployment: " << r.profile.name << ", t = " << Num(r.profile.t_begin())
    << " .. " << Num(r.profile.t_end()) << " s; Simbody accuracy " << Num(r.simbody.accuracy)
    << "; " << r.simbody.history.size() << " recorded hinge knots\n";
  for (std::size_t k = 0; k < r.latch_times.size(); ++k) {
    o << "  panel " << k << " (" << r.profile.model.hinged.panels[k].name
      << ") latched at t = " << Num(r.latch_times[k]) << " s\n";
  }
  o << "  replay (exact coupling) vs Simbody: H_B " << Num(r.difference.max_H_B_relative)
    << " relative, attitude " << Num(r.difference.max_attitude) << " rad, w "
    << Num(r.difference.max_w) << " rad/s, flips " << r.replay_flip_times.size() << " / "
    << r.simbody.flip_times.size() << " (max difference " << Num(r.max_flip_difference) << " s)\n";
  o << "  momentum drift: Simbody " << Num(r.simbody.max_momentum_drift) << ", replay "
    << Num(r.replay_max_h_N_drift) << "; wall time: Simbody " << Num(r.simbody.stats.wall_seconds)
    << " s, replay " << Num(r.replay_wall_seconds) << " s\n";
  return o.str();
}

}  // namespace deploysim::crosscheck
