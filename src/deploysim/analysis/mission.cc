#include "deploysim/analysis/mission.h"

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/analysis/run_recorder.h"
#include "deploysim/analysis/trajectory_schema.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::analysis {

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

/// The output grid merged with `extra` times not on it (ascending, few): the merged,
/// sorted list of the times, unstored.
class GridWithExtras final : public integrators::OutputTimes {
 public:
  GridWithExtras(const integrators::OutputTimes& grid, std::vector<double> extra)
      : grid_(grid), extra_(std::move(extra)) {
    for (std::size_t e = 0; e < extra_.size(); ++e) {
      position_.push_back(CountTimes(grid_, extra_[e], false) + e);
    }
  }
  std::size_t size() const override { return grid_.size() + extra_.size(); }
  double at(std::size_t k) const override {
    const auto it = std::lower_bound(position_.begin(), position_.end(), k);
    const std::size_t e = static_cast<std::size_t>(it - position_.begin());  // extras before k
    if (it != position_.end() && *it == k) return extra_[e];
    return grid_.at(k - e);
  }

 private:
  const integrators::OutputTimes& grid_;
  std::vector<double> extra_;
  std::vector<std::size_t> position_;  // index of extra_[e] in the merged list
};

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
  const FreeBodySolution sol(math::InertiaTensor::FromMatrix(J_B), H_B, q_NB, rep.t_begin);
  rep.regime = ToString(sol.regime());
  rep.one_minus_k2 = sol.complementary_parameter();
  rep.predicted_flip_half_period = sol.flip_half_period();
  if (LocateSpinAxis(J_B, spin_axis_B).role == AxisRole::kIntermediate) {
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
    case AxisRole::kMinor:
      report.rigid_body_only = true;
      report.caveat =
          dissipative
              ? "minor-axis spin with energy dissipation in this stage: not stable, the spin "
                "drifts towards the major axis (major-axis rule)"
              : "minor-axis spin: stable only for a perfectly rigid body; any energy "
                "dissipation (flexible panels, dampers, fuel) drives it into a flat spin about "
                "the major axis (Explorer 1, 1958)";
      break;
    case AxisRole::kMajor:
      report.rigid_body_only = false;
      report.caveat = "major-axis spin: stable, also with energy dissipation";
      break;
    case AxisRole::kIntermediate:
      report.rigid_body_only = false;
      report.caveat = "intermediate-axis spin: unstable (flips), with or without dissipation";
      break;
    case AxisRole::kDegenerate:
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

namespace {

// Rates of s . H_B / |H_B| below this fraction of |w| are rounding noise (a pure spin
// has a rate of exactly zero in exact arithmetic): they count as zero, so that noise
// does not look like an extremum.
constexpr double kRateNoise = 1e-12;
// Locating a minimum of s . H_B on a rigid segment: toms748 to this fraction of the step.
constexpr double kRootRelTolerance = 1e-12;
constexpr std::uintmax_t kMaxRootIterations = 100;

/// J_B(t) as the events and the step observer see it, cached for the last time asked
/// (the flip function and the spin-axis rate are evaluated at the same states).
class CachedSchedule {
 public:
  explicit CachedSchedule(const dynamics::InertiaSource& source) : source_(source) {}
  const dynamics::InertiaSample& At(double t) {
    if (!valid_ || t != t_) {
      sample_ = source_.Evaluate(t);
      t_ = t;
      valid_ = true;
    }
    return sample_;
  }

 private:
  const dynamics::InertiaSource& source_;
  dynamics::InertiaSample sample_{};
  double t_ = 0.0;
  bool valid_ = false;
};

/// The run of a stage profile: the schedule's J_B(t) and h_rel_B(t) drive the rigid-body
/// equations; the phases are the profile's stages. Samples come on the output grid merged
/// with the stage boundaries (kept apart for the stage reports). The spin-axis extrema
/// inside a step are located exactly (closed form, toms748 on the rate) on rigid
/// segments and on the cubic Hermite interpolant of f elsewhere: the error control keeps
/// the steps short against the nutation.
class StageRun {
 public:
  StageRun(const CompiledRun& run,
           SampleSink* sink,
           const std::function<void(double)>& progress,
           const std::optional<math::Vec3>& spin_axis_B);
  MissionResult Run();

 private:
  RunSample SampleOf(const integrators::State& s,
                     double t,
                     const dynamics::InertiaSample& js) const;
  void OnSample(const integrators::State& s);
  void OnBoundary(const integrators::State& s, double t);
  void OnStep(const integrators::State& s);
  AxisPoint PointOf(const integrators::State& y);
  double RigidMinimum(const integrators::State& a, const integrators::State& b) const;
  double Rate(const math::Vec3& H_B, const dynamics::InertiaSample& js) const;

  const CompiledRun& run_;
  const schedule::Profile& profile_;
  const schedule::DeploymentSchedule& sched_;
  double t0_, t1_;
  integrators::State y0_;
  dynamics::InertiaSample s0_;
  double kinetic0_;  // [J] at t0
  math::Vec3 s_;
  double M0_;  // |H_B(t0)|
  RunRecorder rec_;
  CachedSchedule cache_;
  std::vector<double> breakpoints_;
  bool geometry_;

  std::vector<double> boundaries_, extra_;
  std::vector<bool> stage_rigid_;
  std::size_t stage_ = 0;  // the stage of the last grid sample
  std::size_t cached_stage_;
  dynamics::InertiaSample stage_sample_{};
  std::size_t next_extra_ = 0, next_boundary_ = 0, open_stage_ = 0;
  std::size_t delivered_ = 0;
  const integrators::OutputTimes* times_ = nullptr;
  integrators::State last_sample_;
  integrators::State prev_step_;
  AxisPoint prev_point_;
};

StageRun::StageRun(const CompiledRun& run,
                   SampleSink* sink,
                   const std::function<void(double)>& progress,
                   const std::optional<math::Vec3>& spin_axis_B)
    : run_(run),
      profile_(run.profile()),
      sched_(*run.schedule()),
      t0_(profile_.t_begin()),
      t1_(profile_.t_end()),
      y0_(InitialState(profile_, sched_)),
      s0_(sched_.Evaluate(t0_)),
      kinetic0_(dynamics::TotalKineticEnergy(s0_, y0_.H_B)),
      s_(spin_axis_B ? *spin_axis_B : InitialSpinAxis(s0_.J_B, y0_.H_B)),
      M0_(y0_.H_B.norm()),
      rec_(s_, y0_.q_NB * y0_.H_B, sink, progress, t0_, t1_),
      cache_(sched_),
      breakpoints_(sched_.Breakpoints(t0_, t1_)),
      geometry_(profile_.mode == schedule::Mode::kGeometry),
      cached_stage_(profile_.stages.size()) {
  for (const schedule::Stage& st : profile_.stages) {
    boundaries_.push_back(st.t_begin);
    boundaries_.push_back(st.t_end);
    stage_rigid_.push_back(sched_.IsRigidOn(st.t_begin, st.t_end));
  }
  std::sort(boundaries_.begin(), boundaries_.end());
  boundaries_.erase(std::unique(boundaries_.begin(), boundaries_.end()), boundaries_.end());
  prev_step_ = y0_;
  prev_point_ = PointOf(y0_);
  rec_.SpinAxisCos(prev_point_.f);
}

RunSample StageRun::SampleOf(const integrators::State& s,
                             double t,
                             const dynamics::InertiaSample& js) const {
  RunSample o;
  o.t = t;
  o.H_B = s.H_B;
  o.q_NB = s.q_NB;
  o.w = dynamics::AngularVelocity(js, s.H_B);
  o.J_B = js.J_B;
  o.h_rel_B = js.h_rel_B;
  o.kinetic = dynamics::TotalKineticEnergy(js, s.H_B);
  if (geometry_) {
    o.theta = sched_.HingeAngles(t);
    o.theta_dot = sched_.HingeRates(t);
  }
  // The stage laws' drives are the only source of work: theirs is the kinetic energy's
  // change.
  o.work.drive = o.kinetic - kinetic0_;
  return o;
}

// A stage boundary: the open stage ends here (J_B from the left), the next one starts
// (from the right; the first from the given initial state itself, so that its
// classification is a function of the inputs, the same for every method).
void StageRun::OnBoundary(const integrators::State& s, double t) {
  const std::vector<schedule::Stage>& stages = profile_.stages;
  if (open_stage_ < stages.size() && stages[open_stage_].t_end == t && t != t0_) {
    rec_.ClosePhase(SampleOf(s, t, sched_.Evaluate(t, dynamics::Side::kLeft)));
    ++open_stage_;
  }
  if (open_stage_ < stages.size() && stages[open_stage_].t_begin == t) {
    const schedule::Stage& st = stages[open_stage_];
    PhaseInfo info;
    info.name = st.name;
    info.law = st.is_hold() ? "hold" : schedule::ToString(st.law);
    info.rigid = stage_rigid_[open_stage_];
    const integrators::State& start = t == t0_ ? y0_ : s;
    const dynamics::InertiaSample js = sched_.Evaluate(t, dynamics::Side::kRight);
    info.rotor = js.h_rel_B.norm() > 0.0;
    rec_.OpenPhase(info, SampleOf(start, t, js));
    SteadySpin steady;
    steady.reason = "the inertia changes in this stage";
    if (info.rigid) steady = LinearizeSteadySpin(FlowOf(js.J_B, js.h_rel_B), start.H_B);
    rec_.SetSteadySpin(steady);
  }
}

// Sample number k of the merged times (the integrator delivers them in order).
void StageRun::OnSample(const integrators::State& s) {
  const double t = times_->at(delivered_++);
  last_sample_ = s;
  if (next_boundary_ < boundaries_.size() && boundaries_[next_boundary_] == t) {
    OnBoundary(s, t);
    ++next_boundary_;
  }
  if (next_extra_ < extra_.size() && extra_[next_extra_] == t) {
    ++next_extra_;
    return;
  }
  const std::vector<schedule::Stage>& stages = profile_.stages;
  while (stage_ + 1 < stages.size() && t >= stages[stage_].t_end) ++stage_;
  // Inside a rigid stage the inertia sample is the same at every time: evaluated once.
  const bool interior = stage_ < stages.size() && stage_rigid_[stage_] &&
                        t > stages[stage_].t_begin && t < stages[stage_].t_end;
  if (interior && cached_stage_ != stage_) {
    stage_sample_ = sched_.Evaluate(t);
    cached_stage_ = stage_;
  }
  rec_.Sample(SampleOf(s, t, interior ? stage_sample_ : sched_.Evaluate(t)));
}

double StageRun::Rate(const math::Vec3& H_B, const dynamics::InertiaSample& js) const {
  const math::Vec3 w = js.J_inv_B * (H_B - js.h_rel_B);
  const double rate = s_.dot(H_B.cross(w)) / M0_;
  return std::abs(rate) <= kRateNoise * w.norm() ? 0.0 : rate;
}

AxisPoint StageRun::PointOf(const integrators::State& y) {
  AxisPoint p;
  p.t = y.t;
  p.f = s_.dot(y.H_B) / M0_;
  p.H_B = y.H_B;
  const dynamics::InertiaSample& right = cache_.At(y.t);
  p.rate_start = Rate(y.H_B, right);
  p.Hdot_start = y.H_B.cross(right.J_inv_B * (y.H_B - right.h_rel_B));
  p.rate_end = p.rate_start;
  p.Hdot_end = p.Hdot_start;
  if (std::binary_search(breakpoints_.begin(), breakpoints_.end(), y.t)) {
    const dynamics::InertiaSample left = sched_.Evaluate(y.t, dynamics::Side::kLeft);
    p.rate_end = Rate(y.H_B, left);
    p.Hdot_end = y.H_B.cross(left.J_inv_B * (y.H_B - left.h_rel_B));
  }
  return p;
}

double StageRun::RigidMinimum(const integrators::State& a, const integrators::State& b) const {
  const dynamics::InertiaSample js = sched_.Evaluate(a.t, dynamics::Side::kRight);
  const FreeBodySolution sol(math::InertiaTensor::FromMatrix(js.J_B), a.H_B, a.q_NB.normalized(),
                             a.t);
  auto g = [&](double t) {
    const math::Vec3 H = sol.H_B(t);
    const math::Vec3 w = sol.w_NB_B(t);
    const double rate = s_.dot(H.cross(w)) / M0_;
    return std::abs(rate) <= kRateNoise * w.norm() ? 0.0 : rate;
  };
  const double ga = g(a.t);
  const double gb = g(b.t);
  if (!(ga < 0.0 && gb > 0.0)) return std::min(s_.dot(a.H_B), s_.dot(b.H_B)) / M0_;
  std::uintmax_t iterations = kMaxRootIterations;
  const double tol = kRootRelTolerance * (b.t - a.t);
  const auto bracket = boost::math::tools::toms748_solve(
      g, a.t, b.t, ga, gb, [tol](double lo, double hi) { return hi - lo <= tol; }, iterations);
  return s_.dot(sol.H_B(0.5 * (bracket.first + bracket.second))) / M0_;
}

void StageRun::OnStep(const integrators::State& y) {
  rec_.Progress(y.t);
  const AxisPoint next = PointOf(y);
  const integrators::State& a = prev_step_;
  rec_.SpinAxisStep(prev_point_, next, [&]() -> double {
    return sched_.IsRigidOn(a.t, y.t)
               ? RigidMinimum(a, y)
               : math::CubicHermiteMinimum(prev_point_.t, prev_point_.f, prev_point_.rate_start,
                                           next.t, next.f, next.rate_end);
  });
  prev_step_ = y;
  prev_point_ = next;
}

MissionResult StageRun::Run() {
  MissionResult out;
  out.run = run_.handle();
  out.spin_axis_B = s_;
  // The output grid plus the stage boundaries not on it, computed on demand.
  const integrators::UniformGridTimes full(t0_, t1_, profile_.output.dt);
  const WindowTimes grid(full, 0, rec_.sampling() ? full.size() : 0);
  // The stage boundaries open and close the phases (an outcome-only run has no grid).
  for (double b : boundaries_) {
    const std::size_t i = CountTimes(grid, b, false);
    if (!(i < grid.size() && grid.at(i) == b)) extra_.push_back(b);
  }
  const GridWithExtras times(grid, extra_);
  times_ = &times;
  CachedSchedule& cache = cache_;
  const auto stepper = MakeStepper(profile_.integrator.method);
  last_sample_ = y0_;
  const std::vector<integrators::EventFunction> events =
      RigidSpinAxisEvents(s_, [&cache](double t) { return cache.At(t); });
  const integrators::IntegrationResult run = integrators::Integrate(
      *stepper, run_.settings(), sched_, y0_, t1_, times, events,
      [this](const integrators::State& y) { OnStep(y); },
      [this](const integrators::State& y) { OnSample(y); });
  out.stats = run.stats;
  out.termination = run.termination;
  out.message = run.message;
  // A run that stopped early: the remaining times get its last sample (the trajectory
  // has one sample per grid time, and every stage is closed).
  while (delivered_ < times.size()) OnSample(integrators::State(last_sample_));
  out.final_state = run.final_state;
  const dynamics::InertiaSample s1 = sched_.Evaluate(run.final_state.t, dynamics::Side::kLeft);
  out.final_J_B = s1.J_B;
  out.energy_initial = kinetic0_;
  out.energy_final = dynamics::TotalKineticEnergy(s1, run.final_state.H_B);
  out.work.drive = out.energy_final - out.energy_initial;
  for (const integrators::Event& e : run.events) {
    if (e.index == 1) {
      rec_.Crossing45(e.t);
    } else {
      rec_.CandidateFlip(e.t, sched_.Evaluate(e.t).J_B, e.state.H_B);
    }
  }
  rec_.Finish(out);
  return out;
}

}  // namespace

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

MissionResult RunMission(const CompiledRun& compiled,
                         SampleSink& sink,
                         const std::function<void(double)>& progress,
                         const RunOptions& options) {
  if (compiled.profile().is_hinge_profile()) {
    return RunHingeMission(compiled, sink, progress, options);
  }
  const auto wall0 = std::chrono::steady_clock::now();
  StageRun run(compiled, options.sample_trajectory ? &sink : nullptr, progress,
               options.spin_axis_B);
  MissionResult out = run.Run();
  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

MissionResult RunMission(const schedule::Profile& profile,
                         SampleSink& sink,
                         const std::function<void(double)>& progress,
                         const RunOptions& options) {
  return RunMission(*CompiledRun::Compile(profile), sink, progress, options);
}

}  // namespace deploysim::analysis
