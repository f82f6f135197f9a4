#include "deploysim/crosscheck/spring_deployment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deploysim/analysis/exact_flow.h"
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

}  // namespace

SpringDeploymentResult RunSpringDeployment(const schedule::Profile& profile,
                                           const SpringDeploymentOptions& options) {
  schedule::Profile p = options.t_end ? TruncateProfile(profile, *options.t_end) : profile;
  if (p.mode != schedule::Mode::kGeometry) {
    throw std::invalid_argument(p.source + ": spring deployment needs geometry mode");
  }
  p.coupling = schedule::Coupling::kExact;
  if (options.output_dt) p.output.dt = *options.output_dt;
  schedule::ValidateProfile(p);
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

  // Replay with exact coupling.
  const auto wall0 = std::chrono::steady_clock::now();
  const HingeHistorySource source(body, r.simbody.history);
  integrators::State y0;
  y0.t = p.t_begin();
  y0.q_NB = p.initial.q_NB.normalized();
  y0.H_B = H_B0;
  const double M = H_B0.norm();
  const integrators::EventFunction flip{
      "flip", [&source, spin_axis_B](const integrators::State& s) {
        return analysis::FlipFunction(source.Evaluate(s.t).J_B, spin_axis_B, s.H_B);
      }};
  integrators::IntegratorSettings settings;
  settings.tolerances = {options.replay_rtol, options.replay_atol};
  const auto stepper = analysis::MakeStepper(options.replay_method);
  const integrators::IntegrationResult run =
      integrators::Integrate(*stepper, settings, source, y0, p.t_end(), grid, {flip});
  if (run.termination != integrators::Termination::kReachedEnd) {
    throw std::runtime_error(p.source + ": spring replay: integration " + run.message);
  }
  r.replay_stats = run.stats;
  for (const integrators::Event& e : run.events) {
    if (analysis::IsFlip(source.Evaluate(e.t).J_B, spin_axis_B, e.state.H_B)) {
      r.replay_flip_times.push_back(e.t);
    }
  }
  analysis::Trajectory& tr = r.replay;
  const math::Vec3 h_N0 = y0.q_NB * H_B0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const integrators::State& s = run.samples.at(i);
    const dynamics::InertiaSample js = source.Evaluate(grid[i]);
    tr.time.push_back(grid[i]);
    tr.H_B.push_back(s.H_B);
    tr.w_NB_B.push_back(dynamics::AngularVelocity(js, s.H_B));
    tr.q_NB.push_back(s.q_NB);
    tr.J_B.push_back(js.J_B);
    tr.h_rel_B.push_back(js.h_rel_B);
    tr.h_N.push_back(s.q_NB * s.H_B);
    tr.hinge_angles.push_back(source.Interpolate(grid[i]).angle);
    r.replay_max_h_N_drift = std::max(r.replay_max_h_N_drift, (tr.h_N.back() - h_N0).norm() / M);
  }
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
