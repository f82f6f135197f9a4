#include "deploysim/sweep/outcome.h"

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/inertia.h"

namespace deploysim::sweep {

namespace {

// Rates of s . H_B / |H_B| below this fraction of |w| are rounding noise (a pure spin
// has a rate of exactly zero in exact arithmetic): they count as zero, so that noise
// does not look like an extremum.
constexpr double kRateNoise = 1e-12;
// Locating a minimum of s . H_B on a rigid segment: toms748 to this fraction of the step.
constexpr double kRootRelTolerance = 1e-12;
constexpr std::uintmax_t kMaxRootIterations = 100;
constexpr double kHalfPi = 1.5707963267948966;

double Angle(const math::Vec3& s, const math::Vec3& H_B) {
  return std::acos(std::clamp(s.dot(H_B) / H_B.norm(), -1.0, 1.0));
}

/// J_B(t) as the integrator's events see it, cached for the last time asked (the flip
/// and the extremum functions are evaluated at the same states).
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

/// The largest angle between the spin axis s and h_N, from the accepted steps: with
/// f(t) = s . H_B / |H_B| (|H_B| is constant) and its rate f' = s . (H_B x w) / |H_B|
/// known at both ends of every step, a minimum of f inside a step (f' from < 0 to > 0)
/// is located
///   - on rigid segments exactly, with the closed-form solution (FreeBodySolution) from
///     the step's start (toms748 on f', only H_B(t) and w(t) are evaluated);
///   - elsewhere on the cubic Hermite interpolant of f over the step (no extra
///     right-hand-side evaluations; the steps are short against the nutation period
///     because the error control keeps them so).
class AngleTracker {
 public:
  /// `cache` serves J_B(t) from the right (as the flip event asks for it);
  /// `breakpoints` are the schedule's breakpoints in (t0, t1), where J_B's rate and
  /// h_rel_B may jump: a step that ends there uses the left limit.
  AngleTracker(const schedule::DeploymentSchedule& sched,
               CachedSchedule& cache,
               std::vector<double> breakpoints,
               const math::Vec3& s,
               const integrators::State& y0)
      : sched_(sched),
        cache_(cache),
        breakpoints_(std::move(breakpoints)),
        s_(s),
        M_(y0.H_B.norm()) {
    prev_ = Point(y0);
    min_f_ = prev_.f;
  }

  void Step(const integrators::State& y) {
    const Sample next = Point(y);
    min_f_ = std::min(min_f_, next.f);
    if (prev_.rate_start < 0.0 && next.rate_end > 0.0) {
      min_f_ = std::min(min_f_, sched_.IsRigidOn(prev_.state.t, next.state.t)
                                    ? RigidMinimum(prev_, next)
                                    : HermiteMinimum(prev_, next));
    }
    prev_ = next;
  }

  double max_angle() const { return std::acos(std::clamp(min_f_, -1.0, 1.0)); }

 private:
  struct Sample {
    integrators::State state;
    double f = 0.0;           // s . H_B / M
    double rate_end = 0.0;    // df/dt [1/s] as the end of a step (left limit)
    double rate_start = 0.0;  // as the start of the next step (right limit)
  };

  double Rate(const math::Vec3& H_B, const math::Vec3& w) const {
    const double rate = s_.dot(H_B.cross(w)) / M_;
    return std::abs(rate) <= kRateNoise * w.norm() ? 0.0 : rate;
  }
  double Rate(const math::Vec3& H_B, const dynamics::InertiaSample& js) const {
    return Rate(H_B, math::Vec3(js.J_inv_B * (H_B - js.h_rel_B)));
  }

  Sample Point(const integrators::State& y) {
    Sample p;
    p.state = y;
    p.f = s_.dot(y.H_B) / M_;
    p.rate_start = Rate(y.H_B, cache_.At(y.t));
    p.rate_end = std::binary_search(breakpoints_.begin(), breakpoints_.end(), y.t)
                     ? Rate(y.H_B, sched_.Evaluate(y.t, dynamics::Side::kLeft))
                     : p.rate_start;
    return p;
  }

  double RigidMinimum(const Sample& a, const Sample& b) const {
    const dynamics::InertiaSample js = sched_.Evaluate(a.state.t, dynamics::Side::kRight);
    const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(js.J_B), a.state.H_B,
                                         a.state.q_NB.normalized(), a.state.t);
    auto g = [&](double t) { return Rate(sol.H_B(t), sol.w_NB_B(t)); };
    const double ga = g(a.state.t);
    const double gb = g(b.state.t);
    if (!(ga < 0.0 && gb > 0.0)) return std::min(a.f, b.f);
    std::uintmax_t iterations = kMaxRootIterations;
    const double tol = kRootRelTolerance * (b.state.t - a.state.t);
    const auto bracket = boost::math::tools::toms748_solve(
        g, a.state.t, b.state.t, ga, gb, [tol](double lo, double hi) { return hi - lo <= tol; },
        iterations);
    const double t = 0.5 * (bracket.first + bracket.second);
    return s_.dot(sol.H_B(t)) / M_;
  }

  static double HermiteMinimum(const Sample& a, const Sample& b) {
    return math::CubicHermiteMinimum(a.state.t, a.f, a.rate_start, b.state.t, b.f, b.rate_end);
  }

  const schedule::DeploymentSchedule& sched_;
  CachedSchedule& cache_;
  std::vector<double> breakpoints_;
  math::Vec3 s_;
  double M_;
  Sample prev_;
  double min_f_;
};

struct FinalMotion {
  MotionClass motion = MotionClass::kTumbling;
  std::int32_t axis = 0;
  std::int32_t regime = 0;
  double cone = 0.0;
  FinalPrediction prediction;
};

FinalPrediction Predict(const analysis::FreeBodySolution& sol,
                        const math::Mat3& J_B,
                        const math::Vec3& H_B,
                        const math::Vec3& s) {
  FinalPrediction f;
  const math::PrincipalAxes& pa = sol.principal_axes();
  const math::Vec3& I = pa.moments;
  const math::Vec3 h = pa.axes.transpose() * H_B;
  const double two_T = 2.0 * sol.energy();
  const double mc = sol.complementary_parameter();
  switch (sol.regime()) {
    case analysis::Regime::kMinorAxis: {
      // P3 = 2T I3 - M^2 (a sum of non-negative terms); P2 = 2T I2 - M^2 > 0.
      const double P3 = h[0] * h[0] * (I[2] - I[0]) / I[0] + h[1] * h[1] * (I[2] - I[1]) / I[1];
      const double P2 = mc * (I[1] - I[0]) * P3 / (I[2] - I[0]);
      f.separatrix_distance = -P2 / two_T / (I[2] - I[0]);
      break;
    }
    case analysis::Regime::kMajorAxis: {
      // P1 = M^2 - 2T I1 (non-negative terms); -P2 = M^2 - 2T I2 > 0.
      const double P1 = h[1] * h[1] * (I[1] - I[0]) / I[1] + h[2] * h[2] * (I[2] - I[0]) / I[2];
      const double minus_P2 = mc * (I[2] - I[1]) * P1 / (I[2] - I[0]);
      f.separatrix_distance = minus_P2 / two_T / (I[2] - I[0]);
      break;
    }
    case analysis::Regime::kSeparatrix:
    case analysis::Regime::kIntermediateAxisSpin:
      f.separatrix_distance = 0.0;
      break;
    case analysis::Regime::kAxisymmetric:
      f.separatrix_distance = (sol.D() - I[1]) / (I[2] - I[0]);
      break;
    case analysis::Regime::kSpherical:
    case analysis::Regime::kAtRest:
      f.separatrix_distance = std::numeric_limits<double>::quiet_NaN();
      break;
  }
  f.flip_half_period = analysis::LocateSpinAxis(J_B, s).role == analysis::AxisRole::kIntermediate
                           ? sol.flip_half_period()
                           : std::numeric_limits<double>::infinity();
  return f;
}

std::int32_t NearestBodyAxis(const math::Vec3& a) {
  Eigen::Index i = 0;
  a.cwiseAbs().maxCoeff(&i);
  return static_cast<std::int32_t>(i) + (a[i] < 0.0 ? 3 : 0);
}

FinalMotion ClassifyFinal(const math::Mat3& J_B,
                          const math::Vec3& H_B,
                          const math::Vec3& s,
                          double tumble_angle) {
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(J_B), H_B);
  const math::PrincipalAxes& pa = sol.principal_axes();
  const math::Vec3& I = pa.moments;
  const math::Vec3 h = pa.axes.transpose() * H_B;
  const double M = H_B.norm();
  FinalMotion f;
  f.regime = static_cast<std::int32_t>(sol.regime());
  int circulation = 1;  // principal index the momentum circulates about
  switch (sol.regime()) {
    case analysis::Regime::kMinorAxis: {
      circulation = 0;
      const double h1min2 =
          h[0] * h[0] - h[2] * h[2] * I[0] * (I[2] - I[1]) / (I[2] * (I[1] - I[0]));
      f.cone = std::acos(std::clamp(std::sqrt(std::max(h1min2, 0.0)) / M, 0.0, 1.0));
      break;
    }
    case analysis::Regime::kMajorAxis: {
      circulation = 2;
      const double h3min2 =
          h[2] * h[2] - h[0] * h[0] * I[2] * (I[1] - I[0]) / (I[0] * (I[2] - I[1]));
      f.cone = std::acos(std::clamp(std::sqrt(std::max(h3min2, 0.0)) / M, 0.0, 1.0));
      break;
    }
    case analysis::Regime::kAxisymmetric:
      // Equal moments are merged: the symmetry axis is the one that differs.
      circulation = I[0] == I[1] ? 2 : 0;
      f.cone = std::acos(std::clamp(std::abs(h[circulation]) / M, 0.0, 1.0));
      break;
    case analysis::Regime::kIntermediateAxisSpin:
      circulation = 1;
      f.cone = 0.0;
      break;
    case analysis::Regime::kSeparatrix:
    case analysis::Regime::kSpherical:
    case analysis::Regime::kAtRest: {
      Eigen::Index i = 0;
      h.cwiseAbs().maxCoeff(&i);
      circulation = static_cast<int>(i);
      f.cone = sol.regime() == analysis::Regime::kSeparatrix ? kHalfPi : 0.0;
      break;
    }
  }
  math::Vec3 axis = pa.axes.col(circulation);
  if (h[circulation] < 0.0) axis = -axis;
  f.axis = NearestBodyAxis(axis);
  if (sol.regime() == analysis::Regime::kSeparatrix || f.cone > tumble_angle) {
    f.motion = MotionClass::kTumbling;
  } else if (sol.regime() == analysis::Regime::kIntermediateAxisSpin) {
    f.motion = MotionClass::kSpinIntermediate;
  } else {
    f.motion = circulation == 0 ? MotionClass::kSpinMinor : MotionClass::kSpinMajor;
  }
  f.prediction = Predict(sol, J_B, H_B, s);
  return f;
}

double Energy(const dynamics::InertiaSample& s, const math::Vec3& H_B) {
  return dynamics::TotalKineticEnergy(s, H_B);
}

}  // namespace

std::string ToString(MotionClass c) {
  switch (c) {
    case MotionClass::kSpinMinor:
      return "spin-minor";
    case MotionClass::kSpinMajor:
      return "spin-major";
    case MotionClass::kSpinIntermediate:
      return "spin-intermediate";
    case MotionClass::kTumbling:
      return "tumbling";
    case MotionClass::kFailed:
      return "failed";
  }
  return "?";
}

bool WillFlip(const CaseOutcome& o) {
  return o.final_class != MotionClass::kFailed && std::isfinite(o.predicted_flip_half_period);
}

std::string AxisName(std::int32_t final_axis) {
  static const char* const kNames[] = {"+x", "+y", "+z", "-x", "-y", "-z"};
  return final_axis >= 0 && final_axis < 6 ? kNames[final_axis] : "?";
}

namespace {

/// Discards the samples of a mission run (none come when sample_trajectory is false).
class NoSamples final : public analysis::SampleSink {
 public:
  void Append(const analysis::Trajectory& /*block*/) override {}
};

/// The final motion's columns of `out` from the end state (a run that reached the end).
void SetFinal(CaseOutcome& out,
              const math::Mat3& J_B,
              const math::Vec3& H_B,
              const math::Vec3& s,
              const OutcomeSettings& settings) {
  if (out.termination == integrators::Termination::kReachedEnd) {
    const FinalMotion f = ClassifyFinal(J_B, H_B, s, settings.tumble_angle);
    out.final_class = f.motion;
    out.final_axis = f.axis;
    out.final_regime = f.regime;
    out.final_cone_angle = f.cone;
    out.final_separatrix_distance = f.prediction.separatrix_distance;
    out.predicted_flip_half_period = f.prediction.flip_half_period;
  } else {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.final_class = MotionClass::kFailed;
    out.final_cone_angle = nan;
    out.final_separatrix_distance = nan;
    out.predicted_flip_half_period = nan;
  }
}

CaseOutcome SimulateHingeOutcome(const Case& c, const OutcomeSettings& settings) {
  using analysis::HingeEvent;
  const schedule::Profile& p = c.profile;
  NoSamples sink;
  analysis::HingeRunOptions options;
  options.sample_trajectory = false;
  const analysis::MissionResult m = analysis::RunHingeMission(p, sink, {}, options);
  const math::Vec3& s = m.spin_axis_B;

  CaseOutcome out;
  out.end_time = p.t_end();
  out.termination = m.termination;
  out.steps = m.stats.steps;
  out.rejected = m.stats.rejected;
  out.flip_count = static_cast<std::int64_t>(m.flip_times.size());
  out.first_flip_time =
      m.flip_times.empty() ? std::numeric_limits<double>::quiet_NaN() : m.flip_times.front();
  out.max_spin_axis_angle = m.max_spin_axis_angle;
  out.final_spin_axis_angle = Angle(s, m.final_state.H_B);
  out.energy_initial = m.energy_initial;
  out.energy_final = m.energy_final;

  // The deployment: from the first release to the last lock of a released panel (NaN if
  // a released panel is still free at the end); t0 and 0 when nothing was released.
  double first_release = std::numeric_limits<double>::infinity();
  std::vector<char> released(p.hinges.size(), 0);
  for (const HingeEvent& e : m.hinge_events) {
    switch (e.kind) {
      case HingeEvent::Kind::kRelease:
        first_release = std::min(first_release, e.t);
        released[static_cast<std::size_t>(e.panel)] = 1;
        break;
      case HingeEvent::Kind::kLatch:
        ++out.latched_count;
        [[fallthrough]];
      case HingeEvent::Kind::kJam:
      case HingeEvent::Kind::kStop:
      case HingeEvent::Kind::kRest:
        out.max_latch_w_jump = std::max(out.max_latch_w_jump, e.w_jump_B.norm());
        out.max_latch_impulse = std::max(out.max_latch_impulse, std::abs(e.impulse));
        out.energy_dissipated_events += e.energy_dissipated;
        break;
    }
  }
  out.all_latched = out.latched_count == c.latches_expected ? 1 : 0;
  out.deploy_end_time = p.t_begin();
  if (std::isfinite(first_release)) {
    for (std::size_t k = 0; k < released.size(); ++k) {
      if (released[k]) out.deploy_end_time = std::max(out.deploy_end_time, m.latch_times[k]);
      if (released[k] && std::isnan(m.latch_times[k])) {
        out.deploy_end_time = std::numeric_limits<double>::quiet_NaN();
        break;
      }
    }
    out.deploy_duration = out.deploy_end_time - first_release;
  }
  SetFinal(out, m.final_J_B, m.final_state.H_B, s, settings);
  return out;
}

CaseOutcome SimulateStageOutcome(const Case& c, const OutcomeSettings& settings) {
  const schedule::Profile& p = c.profile;
  const schedule::DeploymentSchedule& sched = *c.schedule;
  const double t0 = p.t_begin();
  const double t1 = p.t_end();
  const math::Vec3 s = c.spin_axis_B;

  CaseOutcome out;
  out.end_time = t1;
  out.deploy_end_time = t0;
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    const schedule::Stage& st = p.stages[i];
    const bool moves = !st.from.empty() ? st.from != st.to : i > 0 && st.to != p.stages[i - 1].to;
    if (moves) {
      out.deploy_end_time = std::max(out.deploy_end_time, st.t_end);
      out.deploy_duration += st.t_end - st.t_begin;
    }
  }

  integrators::State y0;
  y0.t = t0;
  y0.q_NB = p.initial.q_NB.normalized();
  const dynamics::InertiaSample s0 = sched.Evaluate(t0);
  y0.H_B = *p.initial.H_B;
  out.energy_initial = Energy(s0, y0.H_B);

  CachedSchedule cache(sched);
  integrators::EventFunction flip{"flip", [&cache, s](const integrators::State& y) {
                                    return analysis::FlipFunction(cache.At(y.t).J_B, s, y.H_B);
                                  }};
  const auto stepper = analysis::MakeStepper(p.integrator.method);
  integrators::IntegratorSettings is;
  is.step = p.integrator.step;
  is.tolerances = {p.integrator.rtol, p.integrator.atol};
  is.max_step = p.integrator.max_step;
  AngleTracker tracker(sched, cache, sched.Breakpoints(t0, t1), s, y0);
  const integrators::IntegrationResult run =
      integrators::Integrate(*stepper, is, sched, y0, t1, {}, {flip},
                             [&tracker](const integrators::State& y) { tracker.Step(y); });

  out.termination = run.termination;
  out.steps = run.stats.steps;
  out.rejected = run.stats.rejected;
  out.first_flip_time = std::numeric_limits<double>::quiet_NaN();
  for (const integrators::Event& e : run.events) {
    if (analysis::IsFlip(sched.Evaluate(e.t).J_B, s, e.state.H_B)) {
      if (out.flip_count == 0) out.first_flip_time = e.t;
      ++out.flip_count;
    }
  }
  out.max_spin_axis_angle = tracker.max_angle();
  const math::Vec3& H1 = run.final_state.H_B;
  out.final_spin_axis_angle = Angle(s, H1);
  const dynamics::InertiaSample s1 = sched.Evaluate(run.final_state.t, dynamics::Side::kLeft);
  out.energy_final = Energy(s1, H1);
  SetFinal(out, s1.J_B, H1, s, settings);
  return out;
}

}  // namespace

FinalPrediction PredictFinal(const math::Mat3& J_B, const math::Vec3& H_B, const math::Vec3& s) {
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(J_B), H_B);
  return Predict(sol, J_B, H_B, s);
}

CaseOutcome SimulateOutcome(const Case& c, const OutcomeSettings& settings) {
  const auto wall0 = std::chrono::steady_clock::now();
  CaseOutcome out = c.profile.is_hinge_profile() ? SimulateHingeOutcome(c, settings)
                                                 : SimulateStageOutcome(c, settings);
  out.run_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::sweep
