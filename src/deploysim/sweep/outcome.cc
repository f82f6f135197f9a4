#include "deploysim/sweep/outcome.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/run/mission.h"
#include "deploysim/math/inertia.h"

namespace deploysim::sweep {

namespace {

constexpr double kHalfPi = 1.5707963267948966;

double Angle(const math::Vec3& s, const math::Vec3& H_B) {
  return std::acos(std::clamp(s.dot(H_B) / H_B.norm(), -1.0, 1.0));
}

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
  f.regime = sol.regime();
  f.one_minus_k2 = sol.complementary_parameter();
  f.separatrix_distance = analysis::SeparatrixDistance(sol, H_B);
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

std::string OutcomeName(const CaseOutcome& o) {
  return analysis::OutcomeName(static_cast<analysis::OutcomeClass>(o.outcome_class),
                               static_cast<analysis::AxisRole>(o.outcome_role_phase),
                               static_cast<analysis::AxisRole>(o.outcome_role_end));
}

namespace {

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

/// The outcome measured from the motion, as fixed-size fields.
void SetMotionOutcome(const analysis::MotionOutcome& mo, CaseOutcome& out) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out.outcome_class = static_cast<std::int32_t>(mo.outcome);
  out.outcome_role_phase = static_cast<std::int32_t>(mo.role_phase);
  out.outcome_role_end = static_cast<std::int32_t>(mo.role_end);
  out.outcome_phase_begin = mo.phase_begin;
  out.nutation_rate = mo.trend.valid ? mo.trend.rate : nan;
  out.nutation_rate_sigma = mo.trend.valid ? mo.trend.rate_sigma : nan;
  out.linear_growth_rate = mo.linear.found ? mo.linear.growth_rate : nan;
  out.transition_time = mo.transition_time;
  out.time_to_tumble = mo.time_to_tumble;
  out.time_to_tumble_measured = mo.time_to_tumble_measured ? 1 : 0;
}

/// The columns every case has, from its outcome-only mission run.
CaseOutcome CommonOutcome(const Case& c,
                          const run::MissionResult& m,
                          const OutcomeSettings& settings) {
  const math::Vec3& s = m.spin_axis_B;
  CaseOutcome out;
  out.end_time = c.profile().t_end();
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
  SetFinal(out, m.final_J_B, m.final_state.H_B, s, settings);
  SetMotionOutcome(m.outcome, out);
  return out;
}

/// The hinge events' columns: latches, shocks, and the deployment from the first release
/// to the last lock of a released panel (NaN if a released panel is still free at the
/// end); t0 and 0 when nothing was released.
void SetHingeColumns(const Case& c, const run::MissionResult& m, CaseOutcome& out) {
  using run::HingeEvent;
  double first_release = std::numeric_limits<double>::infinity();
  std::vector<char> released(c.profile().hinges.size(), 0);
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
      case HingeEvent::Kind::kStick:
        out.max_latch_w_jump = std::max(out.max_latch_w_jump, e.w_jump_B.norm());
        out.max_latch_impulse = std::max(out.max_latch_impulse, std::abs(e.impulse));
        out.energy_dissipated_events += e.energy_dissipated;
        break;
      case HingeEvent::Kind::kLiftOff:
      case HingeEvent::Kind::kSlip:
        break;
    }
  }
  out.all_latched = out.latched_count == c.latches_expected ? 1 : 0;
  out.deploy_end_time = c.profile().t_begin();
  if (!std::isfinite(first_release)) return;
  for (std::size_t k = 0; k < released.size(); ++k) {
    if (released[k]) out.deploy_end_time = std::max(out.deploy_end_time, m.latch_times[k]);
    if (released[k] && std::isnan(m.latch_times[k])) {
      out.deploy_end_time = std::numeric_limits<double>::quiet_NaN();
      break;
    }
  }
  out.deploy_duration = out.deploy_end_time - first_release;
}

/// The deployment of a stage profile: the stages that move the panels.
void SetStageColumns(const schedule::Profile& p, CaseOutcome& out) {
  out.deploy_end_time = p.t_begin();
  for (std::size_t i = 0; i < p.stages.size(); ++i) {
    const schedule::Stage& st = p.stages[i];
    const bool moves = !st.from.empty() ? st.from != st.to : i > 0 && st.to != p.stages[i - 1].to;
    if (moves) {
      out.deploy_end_time = std::max(out.deploy_end_time, st.t_end);
      out.deploy_duration += st.t_end - st.t_begin;
    }
  }
}

}  // namespace

FinalPrediction PredictFinal(const math::Mat3& J_B, const math::Vec3& H_B, const math::Vec3& s) {
  const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(J_B), H_B);
  return Predict(sol, J_B, H_B, s);
}

CaseOutcome SimulateOutcome(const Case& c, const OutcomeSettings& settings) {
  const auto wall0 = std::chrono::steady_clock::now();
  run::NullSink sink;
  run::RunOptions options;
  options.sample_trajectory = false;
  if (!c.profile().is_hinge_profile()) options.spin_axis_B = c.spin_axis_B;
  const run::MissionResult m = run::RunMission(*c.run, sink, {}, options);
  CaseOutcome out = CommonOutcome(c, m, settings);
  if (c.profile().is_hinge_profile()) {
    SetHingeColumns(c, m, out);
  } else {
    SetStageColumns(c.profile(), out);
  }
  out.run_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::sweep
