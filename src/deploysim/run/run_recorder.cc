#include "deploysim/run/run_recorder.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/number_format.h"
#include "deploysim/run/trajectory_schema.h"

namespace deploysim::run {

namespace {

using analysis::kCosTumbleAngle;

/// The principal axis of J_B nearest H_B, signed along it, and its role.
analysis::SpinAxisRole NearestAxis(const math::Mat3& J_B, const math::Vec3& H_B) {
  return analysis::LocateSpinAxis(J_B, H_B.normalized());
}

double AngleBetween(const math::Vec3& a, const math::Vec3& H_B) {
  return std::acos(std::clamp(a.dot(H_B) / (a.norm() * H_B.norm()), -1.0, 1.0));
}

}  // namespace

std::size_t CountTimes(const integrators::OutputTimes& grid, double x, bool inclusive) {
  std::size_t lo = 0, hi = grid.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    const double t = grid.at(mid);
    if (t < x || (inclusive && t == x)) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

double SpinAxis45Gap(const math::Vec3& spin_axis_B, const math::Vec3& H_B) {
  return kCosTumbleAngle - spin_axis_B.dot(H_B) / H_B.norm();
}

double SpinAxis45GapRate(const math::Vec3& spin_axis_B,
                         const math::Vec3& H_B,
                         const math::Vec3& Hdot_B) {
  return -spin_axis_B.dot(Hdot_B) / H_B.norm();
}

double SeparatrixGap(const math::Mat3& J_B, const math::Vec3& H_B) {
  // An event function, evaluated several times per step: the 3x3 closed-form eigenvalues
  // (~1e-15 relative here, far below what locates the crossing).
  Eigen::SelfAdjointEigenSolver<math::Mat3> es;
  es.computeDirect(J_B, Eigen::EigenvaluesOnly);
  // The sorted moments are continuous in J_B, and so is the gap, also where two moments
  // meet (a flat spin is named only where they are distinct: RunRecorder::FlatSpin).
  const math::Vec3 I = es.eigenvalues();  // ascending
  const double D = H_B.squaredNorm() / H_B.dot(J_B.llt().solve(H_B));
  return D / I[1] - 1.0;
}

std::vector<integrators::EventFunction> RigidSpinAxisEvents(
    const math::Vec3& spin_axis_B, const std::function<dynamics::InertiaSample(double)>& inertia) {
  const math::Vec3 s = spin_axis_B;
  auto h_dot = [](const dynamics::InertiaSample& js, const math::Vec3& H_B) {
    return math::Vec3(H_B.cross(js.J_inv_B * (H_B - js.h_rel_B)));
  };
  std::vector<integrators::EventFunction> events;
  events.push_back({"flip",
                    [inertia, s](const integrators::State& y) {
                      return analysis::FlipFunction(inertia(y.t).J_B, s, y.H_B);
                    },
                    [inertia, s, h_dot](const integrators::State& y) {
                      const dynamics::InertiaSample js = inertia(y.t);
                      return analysis::FlipFunctionRate(js.J_B, js.Jdot_B, s, y.H_B,
                                                        h_dot(js, y.H_B));
                    }});
  events.push_back({"spin axis 45 deg",
                    [s](const integrators::State& y) { return SpinAxis45Gap(s, y.H_B); },
                    [inertia, s, h_dot](const integrators::State& y) {
                      return SpinAxis45GapRate(s, y.H_B, h_dot(inertia(y.t), y.H_B));
                    }});
  return events;
}

RunRecorder::RunRecorder(const math::Vec3& spin_axis_B,
                         const math::Vec3& h_N0,
                         SampleSink* sink,
                         const std::function<void(double)>& progress,
                         double t0,
                         double t1)
    : s_(spin_axis_B),
      h_N0_(h_N0),
      M_(h_N0.norm()),
      sink_(sink),
      progress_(progress),
      t0_(t0),
      t1_(t1) {}

void RunRecorder::Sample(const RunSample& s) {
  if (!have_principal_ || s.J_B != principal_J_) {
    principal_ = math::PrincipalDecomposition(s.J_B);
    principal_J_ = s.J_B;
    have_principal_ = true;
  }
  const math::Vec3 h_N = s.q_NB * s.H_B;
  Trajectory& b = block_;
  b.time.push_back(s.t);
  b.H_B.push_back(s.H_B);
  b.w_NB_B.push_back(s.w);
  b.q_NB.push_back(s.q_NB);
  b.J_B.push_back(s.J_B);
  b.principal_moments.push_back(principal_.moments);
  b.h_rel_B.push_back(s.h_rel_B);
  b.h_N.push_back(h_N);
  b.energy.push_back(s.kinetic);
  b.energy_rigid.push_back(0.5 * s.w.dot(s.J_B * s.w));
  b.energy_spring.push_back(s.spring);
  b.euler_313.push_back(Euler313RelativeToMomentum(s.q_NB, h_N));
  b.spin_axis_angle.push_back(std::acos(std::clamp(s_.dot(s.H_B) / s.H_B.norm(), -1.0, 1.0)));
  if (s.theta.size() > 0) {
    b.hinge_angles.push_back(s.theta);
    b.hinge_rates.push_back(s.theta_dot);
  }
  b.work_damper.push_back(s.work.damper);
  b.work_friction.push_back(s.work.friction);
  b.work_motor.push_back(s.work.motor);
  b.work_drive.push_back(s.work.drive);
  b.work_impacts.push_back(s.work.impacts);
  max_h_N_drift_ = std::max(max_h_N_drift_, (h_N - h_N0_).norm() / M_);
  const double nu = Nutation(s.t, s.H_B, s.theta);
  envelope_.Add(s.t, nu);
  NutationValue(nu);
  const bool danger =
      analysis::LocateSpinAxis(principal_, s_).role == analysis::AxisRole::kIntermediate;
  if (danger && !in_window_) danger_windows_.push_back({s.t, s.t});
  if (danger) danger_windows_.back().t_end = s.t;
  in_window_ = danger;
  if (b.size() == kSampleBlock) Flush();
}

void RunRecorder::Flush() {
  const TrajectorySchema& schema = TrajectorySchema::Standard();
  last_sample_ = schema.Row(block_, block_.size() - 1);
  sink_->Append(block_);
  schema.Clear(block_);
}

void RunRecorder::Progress(double t) {
  if (!progress_) return;
  const double f = (t - t0_) / (t1_ - t0_);
  if (f - last_reported_ >= 0.01 || f >= 1.0) {
    last_reported_ = f;
    progress_(f);
  }
}

void RunRecorder::CandidateFlip(double t, const math::Mat3& J_B, const math::Vec3& H_B) {
  if (analysis::IsFlip(J_B, s_, H_B)) flips_.push_back(t);
}

void RunRecorder::SpinAxisStep(const AxisPoint& a,
                               const AxisPoint& b,
                               const std::function<double()>& exact_minimum) {
  SpinAxisCos(b.f);
  if (a.rate_start < 0.0 && b.rate_end > 0.0) {
    SpinAxisCos(exact_minimum
                    ? exact_minimum()
                    : math::CubicHermiteMinimum(a.t, a.f, a.rate_start, b.t, b.f, b.rate_end));
  }
  if (!sampling()) NutationStep(a, b);
}

void RunRecorder::NutationValue(double nu) {
  if (nutation_samples_++ == 0) nutation_begin_ = nu;
  nutation_end_ = nu;
  nutation_max_ = std::max(nutation_max_, nu);
}

// The largest nutation inside a step about the phase's axis e, from a cubic Hermite
// interpolant (H' = H x w seen in B): below 45 deg of g = -sin^2 nu = -|e x H|^2 / |H|^2,
// g' = -2 (e x H).(e x H') / |H|^2 (free of the cancellation in cos nu at small nu);
// beyond, of g = cos nu = e.H / |H|, g' = e.H' / |H|. A peak of nu is a minimum of g.
double RunRecorder::Nutation(double t, const math::Vec3& H_B, const Eigen::VectorXd& theta) const {
  if (steady_.orbit_axes.empty()) return AngleBetween(phase_axis_, H_B);
  const int k = steady_.orbit_rotor_panel;
  if (k >= 0 && k < theta.size()) {
    // A free rotor's orbit: the rotor's angle is the clock (exact, where time drifts).
    const double turns = (theta[k] - steady_.orbit_rotor_angle) / steady_.orbit_rotor_advance;
    return AngleFromOrbit(steady_, (turns - std::floor(turns)) * steady_.period, H_B, 0.0);
  }
  return AngleFromOrbit(steady_, t - phases_.back().start.t, H_B, steady_.orbit_slack);
}

void RunRecorder::NutationStep(const AxisPoint& a, const AxisPoint& b) {
  if (!steady_.orbit_axes.empty()) {
    // About a periodic orbit: the steps' ends (no interpolant of the angle from a curve).
    const double nu = Nutation(b.t, b.H_B, Eigen::VectorXd());
    envelope_.Add(b.t, nu);
    nutation_max_ = std::max(nutation_max_, nu);
    NutationValue(nu);
    return;
  }
  const double nu_b = AngleBetween(phase_axis_, b.H_B);
  const double nu45 = std::acos(kCosTumbleAngle);
  const bool small = nu_b < nu45 && AngleBetween(phase_axis_, a.H_B) < nu45;
  const math::Vec3& e = phase_axis_;
  auto g = [&e, small](const math::Vec3& H, const math::Vec3& Hdot, double& rate) {
    if (!small) {
      rate = e.dot(Hdot) / H.norm();
      return e.dot(H) / H.norm();
    }
    const math::Vec3 eh = e.cross(H);
    const double h2 = H.squaredNorm();
    rate = -2.0 * eh.dot(e.cross(Hdot)) / h2;
    return -eh.squaredNorm() / h2;
  };
  double ra = 0.0, rb = 0.0;
  const double ga = g(a.H_B, a.Hdot_start, ra);
  const double gb = g(b.H_B, b.Hdot_end, rb);
  if (ra < 0.0 && rb > 0.0) {
    const math::HermitePoint m = math::CubicHermiteMinimumAt(a.t, ga, ra, b.t, gb, rb);
    const double nu = small ? std::asin(std::sqrt(std::clamp(-m.value, 0.0, 1.0)))
                            : std::acos(std::clamp(m.value, -1.0, 1.0));
    envelope_.AddPeak(m.t, nu);
    nutation_max_ = std::max(nutation_max_, nu);
  }
  // The step's end too: a nutation that grows or decays with no local maximum (an
  // oscillation smaller than the trend) has its windows' ends as the envelope.
  envelope_.AddPeak(b.t, nu_b);
  NutationValue(nu_b);
}

void RunRecorder::OpenPhase(const PhaseInfo& info, const RunSample& start) {
  phase_axis_ = NearestAxis(start.J_B, start.H_B).axis_B;
  // Windows of one nutation period, at most 1/64 of the run (a nutation that hardly turns
  // in the body, as near a dual-spin stability boundary, still gives an envelope).
  const double rate = analysis::HeldNutationRate(start.J_B, start.h_rel_B, start.H_B);
  const double longest = (t1_ - t0_) / 64.0;
  envelope_.Reset(rate * longest > math::kTwoPi ? math::kTwoPi / rate : longest);
  steady_ = analysis::SteadySpin();
  if (!phases_.empty() && phases_.back().start.t == start.t) {
    phases_.back() = {info, start};  // zero-length phase: replaced
    phase_ends_.resize(phases_.size() - 1);
  } else {
    phases_.push_back({info, start});
  }
  StartNutation();
}

void RunRecorder::SetSteadySpin(const analysis::SteadySpin& s) {
  steady_ = s;
  if (s.found) phase_axis_ = s.y.head<3>().normalized();
  // The envelope's windows at the nutation's own period where the linearization has it: a
  // sink coupled to the nutation detunes it from the held body's (OpenPhase), and windows
  // shorter than the period would take their ends, not a peak.
  // About a periodic orbit the nutation's frequency is known modulo 2 pi / T, and its
  // principal value (at most pi / T) gives windows of at least two periods; the envelope
  // is the windows' mean square (EnvelopeTracker): one nutation period each, where it is
  // at most 1/6 of the run (they overlap by half: at least 11 points; a shorter window
  // leaves the nutation's 2 omega term in, measured 0.7 % of the rate).
  if (s.found && s.motion == "periodic") {
    constexpr double pi = 3.14159265358979323846;
    const double f = s.frequency > 0.0 ? s.frequency : pi / s.period;
    envelope_.ResetMeanSquare(std::min(2.0 * pi / f, (t1_ - t0_) / 6.0));
  } else if (s.found && s.frequency > 0.0) {
    envelope_.Reset(std::min(math::kTwoPi / s.frequency, (t1_ - t0_) / 64.0));
  }
  StartNutation();
}

// The open phase's nutation starts at the phase's start (a sample there, if any, repeats
// it), so that a run with samples and one without begin alike.
void RunRecorder::StartNutation() {
  nutation_samples_ = 0;
  nutation_max_ = 0.0;
  NutationValue(
      Nutation(phases_.back().start.t, phases_.back().start.H_B, phases_.back().start.theta));
}

void RunRecorder::ClosePhase(const RunSample& end) { phase_ends_.push_back(end); }

StageReport RunRecorder::Report(std::size_t i, const std::vector<double>& flips) const {
  const Phase& ph = phases_[i];
  const RunSample& end = phase_ends_[std::min(i, phase_ends_.size() - 1)];
  StageReport rep;
  rep.index = static_cast<int>(i);
  rep.name = ph.info.name;
  rep.law = ph.info.law;
  rep.t_begin = ph.start.t;
  rep.t_end = i + 1 < phases_.size() ? phases_[i + 1].start.t : end.t;
  rep.rigid = ph.info.rigid;
  const analysis::FreeBodySolution after(math::InertiaTensor::FromMatrix(end.J_B), end.H_B);
  rep.moments_end = math::PrincipalDecomposition(end.J_B).moments;
  rep.spin_axis_end = analysis::LocateSpinAxis(end.J_B, s_).role;
  rep.separatrix_distance = analysis::SeparatrixDistance(after, end.H_B);
  for (double tf : flips) {
    if (tf >= rep.t_begin && tf < rep.t_end) rep.observed_flips.push_back(tf);
  }
  rep.predicted_flip_half_period = std::numeric_limits<double>::infinity();
  if (rep.rigid) SetRigidPrediction(rep, ph.start.J_B, ph.start.H_B, ph.start.q_NB, s_);
  SetRigidBodyCaveat(rep, ph.info.dissipative);
  return rep;
}

void RunRecorder::Finish(MissionResult& out) {
  if (sink_ != nullptr && !block_.time.empty()) Flush();
  out.last_sample = last_sample_;
  std::sort(flips_.begin(), flips_.end());
  out.flip_times = flips_;
  out.spin_axis_45_crossings = crossings_45_;
  out.danger_windows = danger_windows_;
  out.max_h_N_drift = sink_ != nullptr
                          ? max_h_N_drift_
                          : ((out.final_state.q_NB * out.final_state.H_B) - h_N0_).norm() / M_;
  out.max_spin_axis_angle = std::acos(std::clamp(min_cos_, -1.0, 1.0));
  out.stages.clear();
  if (sink_ != nullptr) {  // an outcome-only run: no stage reports
    for (std::size_t i = 0; i < phases_.size(); ++i) {
      out.stages.push_back(Report(i, out.flip_times));
    }
  }
  if (!phases_.empty()) out.outcome = Outcome(out);
}

analysis::MotionOutcome RunRecorder::Outcome(const MissionResult& out) const {
  analysis::MotionOutcome o;
  const RunSample& first = phases_.front().start;
  const RunSample& end = phase_ends_.empty() ? phases_.back().start : phase_ends_.back();
  o.axis_start = analysis::BodyAxisName(s_);
  o.role_start = analysis::LocateSpinAxis(first.J_B, s_).role;
  o.role_phase = analysis::LocateSpinAxis(phases_.back().start.J_B, s_).role;
  const analysis::SpinAxisRole final_axis = NearestAxis(end.J_B, end.H_B);
  o.axis_end = analysis::BodyAxisName(final_axis.axis_B);
  o.role_end = final_axis.role;
  o.phase_begin = phases_.back().start.t;
  o.t_end = end.t;
  o.nutation_begin = nutation_begin_;
  o.nutation_end = nutation_end_;
  o.nutation_max = nutation_max_;
  o.trend = analysis::FitEnvelope(envelope_.peaks(), analysis::kFitFloor, analysis::kFitCeiling,
                                  analysis::FitStart(steady_, phases_.back().start.t));
  // A phase that starts with a large nutation (a deployment's own kick) has no peaks in
  // the small band: its trend up to 45 deg still tells growing from bounded.
  if (!o.trend.valid)
    o.trend =
        analysis::FitEnvelope(envelope_.peaks(), analysis::kFitFloor, std::acos(kCosTumbleAngle));
  std::vector<double> flips;
  for (double t : out.flip_times) {
    if (t >= o.phase_begin) flips.push_back(t);
  }
  o.flips = static_cast<int>(flips.size());
  if (flips.size() >= 2)
    o.flip_interval = (flips.back() - flips.front()) / static_cast<double>(flips.size() - 1);
  o.max_excursion = out.max_spin_axis_angle;
  o.faults = DeploymentFaults(out.profile(), out.hinge_events, end.t);
  o.linear = steady_;
  const double nu45 = std::acos(kCosTumbleAngle);
  if (o.linear.found && o.linear.growth_rate > 0.0 && o.nutation_begin > 0.0 &&
      o.nutation_begin < nu45) {
    o.predicted_45_time = o.phase_begin + std::log(nu45 / o.nutation_begin) / o.linear.growth_rate;
  }
  const bool moved = AngleBetween(s_, end.H_B) > std::acos(kCosTumbleAngle) &&
                     AngleBetween(s_, final_axis.axis_B) > std::acos(kCosTumbleAngle);
  for (double t : out.spin_axis_45_crossings) {
    if (t < o.phase_begin) continue;
    if (!std::isfinite(o.first_45_time)) o.first_45_time = t;
    o.last_45_time = t;
  }
  if (out.termination != integrators::Termination::kReachedEnd) {
    o.outcome = analysis::OutcomeClass::kIncomplete;
  } else if (o.flips >= 2) {
    o.outcome = analysis::OutcomeClass::kFlipping;
  } else if (FlatSpin(o, end)) {
    o.outcome = analysis::OutcomeClass::kTransition;
    o.transition_time = o.separatrix_time;
  } else if (moved) {
    o.outcome = analysis::OutcomeClass::kTransition;
    if (!out.spin_axis_45_crossings.empty()) o.transition_time = out.spin_axis_45_crossings.back();
  } else if (o.trend.significant() &&
             (o.trend.rate > 0.0 || !(o.linear.found && o.linear.verdict == "unstable"))) {
    // A nutation that shrinks about an unstable steady spin is on its way along the stable
    // direction of a saddle (about an intermediate axis): not a decay; bounded within the
    // run, with the linear prediction beside it in the headline.
    o.outcome =
        o.trend.rate > 0.0 ? analysis::OutcomeClass::kGrowing : analysis::OutcomeClass::kDecaying;
  } else if (o.nutation_max >= nu45) {
    o.outcome = analysis::OutcomeClass::kTumbling;
  } else {
    o.outcome = analysis::OutcomeClass::kBounded;
  }
  o.outcome_name = analysis::OutcomeName(o.outcome, o.role_phase, o.role_end);
  TimeToTumble(o, out.spin_axis_45_crossings);
  Predictions(o);
  o.headline = analysis::Headline(o);
  return o;
}

bool RunRecorder::FlatSpin(analysis::MotionOutcome& o, const RunSample& end) const {
  if (o.role_phase != analysis::AxisRole::kMinor) return false;
  // A rotor: D means another thing. (A damper's swing is no rotor: after the crossing it
  // still swings, so the momentum relative to the hub at the end says nothing.)
  if (phases_.back().info.rotor) return false;
  if (!(SeparatrixGap(end.J_B, end.H_B) > 0.0)) return false;
  const math::Vec3 I = math::PrincipalDecomposition(end.J_B).moments;
  const double tol = analysis::kDegenerateMoments * I[2];
  if (I[1] - I[0] <= tol || I[2] - I[1] <= tol) return false;  // no separatrix
  double t = std::numeric_limits<double>::quiet_NaN();
  for (const Crossing& c : separatrix_) {
    if (c.t >= o.phase_begin && c.direction > 0) t = c.t;
  }
  if (!std::isfinite(t)) return false;
  o.separatrix_time = t;
  const math::PrincipalAxes pa = math::PrincipalDecomposition(end.J_B);
  const math::Vec3 major = pa.axes.col(2);
  o.axis_end = analysis::BodyAxisName(major.dot(end.H_B) >= 0.0 ? major : math::Vec3(-major));
  o.role_end = analysis::AxisRole::kMajor;
  return true;
}

void RunRecorder::TimeToTumble(analysis::MotionOutcome& o,
                               const std::vector<double>& crossings_45) {
  double first = std::numeric_limits<double>::infinity();
  for (double t : crossings_45) {
    if (t >= o.phase_begin) first = std::min(first, t);
  }
  o.time_to_tumble_measured = std::isfinite(first);
  if (o.time_to_tumble_measured) {
    o.time_to_tumble = first - o.phase_begin;
  } else if (std::isfinite(o.predicted_45_time)) {
    o.time_to_tumble = o.predicted_45_time - o.phase_begin;
  } else if (o.linear.found && !(o.linear.growth_rate > 0.0)) {
    o.time_to_tumble = std::numeric_limits<double>::infinity();
  }
}

void RunRecorder::Predictions(analysis::MotionOutcome& o) const {
  const Phase& ph = phases_.back();
  const analysis::AxisRole role = NearestAxis(ph.start.J_B, ph.start.H_B).role;
  // The rigid-body rule with the major-axis rule: a minor-axis spin is stable only without
  // dissipation.
  if (role == analysis::AxisRole::kMajor ||
      (role == analysis::AxisRole::kMinor && !ph.info.dissipative)) {
    o.rigid_rule = "stable";
  } else if (role != analysis::AxisRole::kDegenerate) {
    o.rigid_rule = "unstable";
  }
  if (!o.linear.found || o.rigid_rule.empty()) return;
  const bool linear_unstable = o.linear.verdict == "unstable";
  if (linear_unstable == (o.rigid_rule == "unstable")) return;
  const math::Vec3 h_r = ph.start.h_rel_B;
  const std::string rule = "the rigid-body rule says " + o.rigid_rule + " for a " +
                           analysis::ToString(role) + "-axis spin" +
                           (ph.info.dissipative ? " with dissipation" : "");
  std::string why;
  if (h_r.norm() > 1e-6 * ph.start.H_B.norm()) {
    why = "a rotor carries " +
          math::FormatSignificant(100.0 * h_r.norm() / ph.start.H_B.norm(), 3) +
          " % of the momentum";
  } else if (ph.info.dissipative) {
    why = "dissipation";
  } else {
    why = "the hinges flex";
  }
  o.disagreement = rule + "; the linearization says " + o.linear.verdict + ": " + why;
}

}  // namespace deploysim::run
