#include "deploysim/analysis/mission.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/dynamics/rigid_body.h"
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

void Clear(Trajectory& t) {
  for (std::vector<math::Vec3>* v :
       {&t.H_B, &t.w_NB_B, &t.principal_moments, &t.h_rel_B, &t.h_N, &t.euler_313}) {
    v->clear();
  }
  t.time.clear();
  t.q_NB.clear();
  t.J_B.clear();
  t.energy.clear();
  t.energy_rigid.clear();
  t.energy_spring.clear();
  t.spin_axis_angle.clear();
  t.hinge_angles.clear();
  t.hinge_rates.clear();
}

void Reserve(Trajectory& t, std::size_t n) {
  for (std::vector<math::Vec3>* v :
       {&t.H_B, &t.w_NB_B, &t.principal_moments, &t.h_rel_B, &t.h_N, &t.euler_313}) {
    v->reserve(n);
  }
  t.time.reserve(n);
  t.q_NB.reserve(n);
  t.J_B.reserve(n);
  t.energy.reserve(n);
  t.energy_rigid.reserve(n);
  t.energy_spring.reserve(n);
  t.spin_axis_angle.reserve(n);
}

/// Number of times of `grid` below x (a binary search; the grid is ascending).
std::size_t CountBelow(const integrators::OutputTimes& grid, double x) {
  std::size_t lo = 0, hi = grid.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (grid.at(mid) < x) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

/// The output grid merged with `extra` times not on it (ascending, few): the merged,
/// sorted list of the times, unstored.
class GridWithExtras final : public integrators::OutputTimes {
 public:
  GridWithExtras(const integrators::OutputTimes& grid, std::vector<double> extra)
      : grid_(grid), extra_(std::move(extra)) {
    for (std::size_t e = 0; e < extra_.size(); ++e) {
      position_.push_back(CountBelow(grid_, extra_[e]) + e);
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
  void Append(const Trajectory& b) override {
    auto add = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
    add(t_.time, b.time);
    add(t_.H_B, b.H_B);
    add(t_.w_NB_B, b.w_NB_B);
    add(t_.q_NB, b.q_NB);
    add(t_.J_B, b.J_B);
    add(t_.principal_moments, b.principal_moments);
    add(t_.h_rel_B, b.h_rel_B);
    add(t_.h_N, b.h_N);
    add(t_.energy, b.energy);
    add(t_.energy_rigid, b.energy_rigid);
    add(t_.energy_spring, b.energy_spring);
    add(t_.hinge_rates, b.hinge_rates);
    add(t_.euler_313, b.euler_313);
    add(t_.spin_axis_angle, b.spin_axis_angle);
    add(t_.hinge_angles, b.hinge_angles);
  }

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

MissionResult RunMission(const schedule::Profile& profile,
                         SampleSink& sink,
                         const std::function<void(double)>& progress) {
  if (profile.is_hinge_profile()) return RunHingeMission(profile, sink, progress, {});
  const auto wall0 = std::chrono::steady_clock::now();
  const schedule::DeploymentSchedule sched(profile);
  const double t0 = profile.t_begin();
  const double t1 = profile.t_end();

  MissionResult out;
  out.profile = profile;

  // Initial state.
  integrators::State y0;
  y0.t = t0;
  y0.q_NB =
      math::ValidateUnitQuaternion(profile.initial.q_NB, profile.source + ": initial attitude");
  const dynamics::InertiaSample s0 = sched.Evaluate(t0);
  y0.H_B = profile.initial.H_B ? *profile.initial.H_B
                               : math::Vec3(s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B);
  const math::Vec3 h_N0 = y0.q_NB * y0.H_B;
  const double M = h_N0.norm();
  if (!(M > 0.0)) throw std::invalid_argument(profile.source + ": initial: zero angular momentum");

  // The body spin axis; flips are sign changes of the momentum along it while it is the
  // intermediate principal axis of J(t).
  const math::Vec3 spin_axis_B = InitialSpinAxis(s0.J_B, y0.H_B);
  out.spin_axis_B = spin_axis_B;
  integrators::EventFunction flip{"flip", [&sched, spin_axis_B](const integrators::State& s) {
                                    return FlipFunction(sched.Evaluate(s.t).J_B, spin_axis_B,
                                                        s.H_B);
                                  }};

  // Output grid plus the stage boundaries (kept apart for the stage reports), computed
  // on demand (GridWithExtras): a sample is a grid sample unless its time is one of the
  // boundaries that are not on the grid (`extra`).
  const integrators::UniformGridTimes grid(t0, t1, profile.output.dt);
  std::vector<double> boundaries;
  for (const schedule::Stage& st : profile.stages) {
    boundaries.push_back(st.t_begin);
    boundaries.push_back(st.t_end);
  }
  std::sort(boundaries.begin(), boundaries.end());
  boundaries.erase(std::unique(boundaries.begin(), boundaries.end()), boundaries.end());
  std::vector<double> extra;
  for (double b : boundaries) {
    const std::size_t i = CountBelow(grid, b);
    if (!(i < grid.size() && grid.at(i) == b)) extra.push_back(b);
  }
  const GridWithExtras times(grid, extra);

  const auto stepper = MakeStepper(profile.integrator.method);
  integrators::IntegratorSettings settings;
  settings.step = profile.integrator.step;
  settings.tolerances = {profile.integrator.rtol, profile.integrator.atol};
  settings.max_step = profile.integrator.max_step;
  double last_reported = -1.0;
  integrators::StepObserver observer;
  if (progress) {
    observer = [&](const integrators::State& s) {
      const double f = (s.t - t0) / (t1 - t0);
      if (f - last_reported >= 0.01 || f >= 1.0) {
        last_reported = f;
        progress(f);
      }
    };
  }

  // The trajectory on the output grid, computed sample by sample as the integrator
  // delivers them and passed on in blocks.
  const bool geometry = profile.mode == schedule::Mode::kGeometry;
  Trajectory block;
  Reserve(block, kSampleBlock);
  // Inside a rigid stage the inertia sample is the same at every time: evaluate it once
  // per stage. The principal decomposition is cached on the exact bits of J_B.
  std::vector<bool> stage_rigid;
  for (const schedule::Stage& st : profile.stages) {
    stage_rigid.push_back(sched.IsRigidOn(st.t_begin, st.t_end));
  }
  std::size_t stage = 0;
  std::size_t cached_stage = profile.stages.size();
  dynamics::InertiaSample stage_sample{};
  bool have_principal = false;
  math::Mat3 principal_J = math::Mat3::Zero();
  math::PrincipalAxes principal{};
  std::vector<integrators::State> boundary_states;  // at `boundaries`, as they pass
  integrators::State last_sample = y0;
  std::size_t next_extra = 0;
  std::size_t next_boundary = 0;
  bool in_window = false;
  auto add_sample = [&](const integrators::State& s, double t) {
    while (stage + 1 < profile.stages.size() && t >= profile.stages[stage].t_end) ++stage;
    const bool interior = stage < profile.stages.size() && stage_rigid[stage] &&
                          t > profile.stages[stage].t_begin && t < profile.stages[stage].t_end;
    dynamics::InertiaSample js;
    if (interior) {
      if (cached_stage != stage) {
        stage_sample = sched.Evaluate(t);
        cached_stage = stage;
      }
      js = stage_sample;
    } else {
      js = sched.Evaluate(t);
    }
    if (!have_principal || js.J_B != principal_J) {
      principal = math::PrincipalDecomposition(js.J_B);
      principal_J = js.J_B;
      have_principal = true;
    }
    const math::Vec3 w = dynamics::AngularVelocity(js, s.H_B);
    const math::Vec3 h_N = s.q_NB * s.H_B;
    block.time.push_back(t);
    block.H_B.push_back(s.H_B);
    block.w_NB_B.push_back(w);
    block.q_NB.push_back(s.q_NB);
    block.J_B.push_back(js.J_B);
    block.principal_moments.push_back(principal.moments);
    block.h_rel_B.push_back(js.h_rel_B);
    block.h_N.push_back(h_N);
    block.energy.push_back(dynamics::TotalKineticEnergy(js, s.H_B));
    block.energy_rigid.push_back(dynamics::KineticEnergy(js, s.H_B));
    block.energy_spring.push_back(0.0);
    block.euler_313.push_back(Euler313RelativeToMomentum(s.q_NB, h_N));
    block.spin_axis_angle.push_back(
        std::acos(std::clamp(spin_axis_B.dot(s.H_B) / s.H_B.norm(), -1.0, 1.0)));
    if (geometry) {
      block.hinge_angles.push_back(sched.HingeAngles(t));
      block.hinge_rates.push_back(sched.HingeRates(t));
    }
    out.max_h_N_drift = std::max(out.max_h_N_drift, (h_N - h_N0).norm() / M);
    // Danger windows: the body spin axis is the intermediate principal axis of J(t).
    const bool danger = LocateSpinAxis(principal, spin_axis_B).role == AxisRole::kIntermediate;
    if (danger && !in_window) out.danger_windows.push_back({t, t});
    if (danger) out.danger_windows.back().t_end = t;
    in_window = danger;
    if (block.size() == kSampleBlock) {
      sink.Append(block);
      Clear(block);
    }
  };
  // Sample number k of `times` (the integrator delivers them in order).
  std::size_t delivered = 0;
  auto on_sample = [&](const integrators::State& s) {
    const double t = times.at(delivered++);
    last_sample = s;
    if (next_boundary < boundaries.size() && boundaries[next_boundary] == t) {
      boundary_states.push_back(s);
      ++next_boundary;
    }
    if (next_extra < extra.size() && extra[next_extra] == t) {
      ++next_extra;
      return;
    }
    add_sample(s, t);
  };
  // The spin axis passing 45 degrees from h_N (either way).
  const double M0 = y0.H_B.norm();
  integrators::EventFunction cross45{"spin axis 45 deg",
                                     [spin_axis_B, M0](const integrators::State& s) {
                                       return 0.70710678118654752440 - spin_axis_B.dot(s.H_B) / M0;
                                     }};
  const integrators::IntegrationResult run = integrators::Integrate(
      *stepper, settings, sched, y0, t1, times, {flip, cross45}, observer, on_sample);
  out.stats = run.stats;
  out.termination = run.termination;
  out.message = run.message;
  // A run that stopped early: the remaining times get its last sample (as before
  // streaming: the trajectory always has one sample per grid time).
  while (delivered < times.size()) on_sample(integrators::State(last_sample));
  out.final_state = run.final_state;
  {
    const dynamics::InertiaSample s1 = sched.Evaluate(run.final_state.t, dynamics::Side::kLeft);
    out.final_J_B = s1.J_B;
    out.energy_initial = dynamics::TotalKineticEnergy(s0, y0.H_B);
    out.energy_final = dynamics::TotalKineticEnergy(s1, run.final_state.H_B);
  }
  out.max_spin_axis_angle = std::numeric_limits<double>::quiet_NaN();
  if (!block.time.empty()) sink.Append(block);
  Clear(block);

  // Flip events: the rule of flip_rule.h.
  for (const integrators::Event& e : run.events) {
    if (e.index == 1) {
      out.spin_axis_45_crossings.push_back(e.t);
    } else if (IsFlip(sched.Evaluate(e.t).J_B, spin_axis_B, e.state.H_B)) {
      out.flip_times.push_back(e.t);
    }
  }

  // States at the stage boundaries.
  auto state_at = [&](double t) -> const integrators::State& {
    const auto it = std::lower_bound(boundaries.begin(), boundaries.end(), t);
    const std::size_t i = static_cast<std::size_t>(it - boundaries.begin());
    return boundary_states.at(std::min(i, boundary_states.size() - 1));
  };

  // Stage reports.
  for (std::size_t k = 0; k < profile.stages.size(); ++k) {
    const schedule::Stage& st = profile.stages[k];
    StageReport rep;
    rep.index = static_cast<int>(k);
    rep.name = st.name;
    rep.law = st.is_hold() ? "hold" : schedule::ToString(st.law);
    rep.t_begin = st.t_begin;
    rep.t_end = st.t_end;
    rep.rigid = sched.IsRigidOn(st.t_begin, st.t_end);
    const integrators::State& end = state_at(st.t_end);
    const dynamics::InertiaSample js = sched.Evaluate(st.t_end, dynamics::Side::kLeft);
    const math::PrincipalAxes p = math::PrincipalDecomposition(js.J_B);
    rep.moments_end = p.moments;
    rep.spin_axis_end = LocateSpinAxis(js.J_B, spin_axis_B).role;
    const math::Vec3 w = js.J_inv_B * (end.H_B - js.h_rel_B);
    const double two_T = w.dot(js.J_B * w);
    const double D = end.H_B.squaredNorm() / two_T;
    rep.separatrix_distance = (D - p.moments[1]) / (p.moments[2] - p.moments[0]);
    for (double tf : out.flip_times) {
      if (tf >= st.t_begin && tf < st.t_end) rep.observed_flips.push_back(tf);
    }
    rep.predicted_flip_half_period = std::numeric_limits<double>::infinity();
    if (rep.rigid) {
      // The first stage starts from the given initial state itself (the classification
      // is a function of the inputs, the same for every method).
      const integrators::State& start = st.t_begin == t0 ? y0 : state_at(st.t_begin);
      // Right after the switch of a step-law stage.
      const dynamics::InertiaSample jr = sched.Evaluate(st.t_begin, dynamics::Side::kRight);
      SetRigidPrediction(rep, jr.J_B, start.H_B, start.q_NB, spin_axis_B);
    }
    SetRigidBodyCaveat(rep, /*dissipative=*/false);
    out.stages.push_back(rep);
  }

  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::analysis
