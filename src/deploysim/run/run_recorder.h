#pragma once

/// The bookkeeping of a mission run, in one place. The run loop (run_loop.h) and its body
/// integrate; the recorder receives what they see and makes the result from it:
///   - samples on the output grid -> the trajectory, block by block, every field filled
///     here; the largest h_N drift; the danger windows (the spin axis is the
///     intermediate principal axis of J);
///   - located sign changes of the flip function, kept when the flip rule says so
///     (flip_rule.h), and crossings of 45 degrees between the spin axis and h_N;
///   - the largest spin-axis angle: the minimum of f = s . H_B / |H_B| over exact points
///     (the start, segment ends, located extrema) and inside accepted steps;
///   - phases (the profile's stages, or the hinge run's phases between changes of the
///     free and moving hinges), opened and closed -> one stage report each;
///   - progress, reported in steps of 1 % of the run;
///   - the outcome measured from the motion (motion_outcome.h): the nutation of each
///     phase about its own spin axis and its envelope, the final axis, the faults, with
///     the linear prediction the runner hands in for the final phase.
/// An outcome-only run (a sweep case) passes no sink: no samples, everything else.

#include <Eigen/Core>
#include <algorithm>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/types.h"
#include "deploysim/run/mission.h"

namespace deploysim::run {

/// One state of a run with what the outputs and the reports need of it.
struct RunSample {
  double t = 0.0;                            ///< [s]
  math::Vec3 H_B = math::Vec3::Zero();       ///< [kg m^2/s]
  math::Quat q_NB = math::Quat::Identity();  ///< unit
  math::Vec3 w = math::Vec3::Zero();         ///< [rad/s] hub angular velocity
  math::Mat3 J_B = math::Mat3::Zero();       ///< [kg m^2]
  math::Vec3 h_rel_B = math::Vec3::Zero();   ///< [kg m^2/s]
  double kinetic = 0.0;                      ///< [J] total kinetic energy
  double spring = 0.0;                       ///< [J] energy in the free hinges' springs
  Eigen::VectorXd theta, theta_dot;          ///< [rad], [rad/s]; empty in tensor mode
  WorkLedger work;                           ///< [J] since the run's start
};

/// What a phase is, for its stage report.
struct PhaseInfo {
  std::string name;
  std::string law;           ///< "hold", a law's name, "prescribed", "free"
  bool rigid = false;        ///< J constant and h_rel = 0 throughout
  bool dissipative = false;  ///< energy dissipated continuously (dampers, friction)
  /// A rotor turns in it (a free hinge that can turn without bound, a hinge held at a
  /// steady rate, a rigid stage's rotor momentum): |H|^2 / 2T has no separatrix to cross.
  bool rotor = false;
};

/// f = s . H_B / |H_B(0)| at the end of an accepted step, with its rate as the end of
/// that step (left limit) and as the start of the next (right limit) [1/s]; H_B and its
/// rate seen in B (H_B x w_NB_B) likewise, for the nutation of an outcome-only run.
struct AxisPoint {
  double t = 0.0;
  double f = 0.0;
  double rate_end = 0.0;
  double rate_start = 0.0;
  math::Vec3 H_B = math::Vec3::Zero();
  math::Vec3 Hdot_end = math::Vec3::Zero();
  math::Vec3 Hdot_start = math::Vec3::Zero();
};

/// The 45-degree rule: cos 45 deg - s . H_B / |H_B|, whose zeros are the times the spin
/// axis s passes 45 degrees from h_N (either way).
double SpinAxis45Gap(const math::Vec3& spin_axis_B, const math::Vec3& H_B);
/// Its rate, from the rate of H_B seen in B (H_B' = H_B x w_NB_B).
double SpinAxis45GapRate(const math::Vec3& spin_axis_B,
                         const math::Vec3& H_B,
                         const math::Vec3& Hdot_B);

/// The separatrix gap D / I_int - 1: D = |H_B|^2 / (H_B . J_B^-1 H_B) = |H|^2 / (2 T), T
/// the kinetic energy of the body frozen in its present shape (the sinks at rest), I_int
/// the intermediate principal moment of J_B. Below 0 the rigid body's polhode circles the
/// minor axis, above 0 the major one: an energy sink that drains T at constant |H| takes
/// a minor-axis spin across 0 into a flat spin (where the three moments are distinct).
double SeparatrixGap(const math::Mat3& J_B, const math::Vec3& H_B);

/// The spin-axis event functions of a run on the rigid-body path (no free hinge), with
/// their rates: the flip function (flip_rule.h) and the 45-degree gap.
/// `inertia(t)`: the inertia sample at t (J_B, its rate, h_rel_B).
std::vector<integrators::EventFunction> RigidSpinAxisEvents(
    const math::Vec3& spin_axis_B, const std::function<dynamics::InertiaSample(double)>& inertia);

/// A window [begin, end) of an output grid's indices (begin == end: no times).
class WindowTimes final : public integrators::OutputTimes {
 public:
  WindowTimes(const integrators::OutputTimes& grid, std::size_t begin, std::size_t end)
      : grid_(grid), begin_(begin), end_(end) {}
  std::size_t size() const override { return end_ - begin_; }
  double at(std::size_t i) const override { return grid_.at(begin_ + i); }

 private:
  const integrators::OutputTimes& grid_;
  std::size_t begin_, end_;
};

/// The number of times of the ascending `grid` below x (`inclusive`: at most x).
std::size_t CountTimes(const integrators::OutputTimes& grid, double x, bool inclusive);

class RunRecorder {
 public:
  /// `sink` null: no samples. `h_N0`: the initial momentum in N.
  RunRecorder(const math::Vec3& spin_axis_B,
              const math::Vec3& h_N0,
              SampleSink* sink,
              const std::function<void(double)>& progress,
              double t0,
              double t1);

  bool sampling() const { return sink_ != nullptr; }
  /// The next sample on the output grid (in time order).
  void Sample(const RunSample& s);
  /// The fraction of the run done at time t, if at least 1 % more than last reported.
  void Progress(double t);

  /// A located sign change of the flip function at t (J_B, H_B there): a flip if the
  /// flip rule says so.
  void CandidateFlip(double t, const math::Mat3& J_B, const math::Vec3& H_B);
  /// A located zero of SpinAxis45Gap.
  void Crossing45(double t) { crossings_45_.push_back(t); }
  /// A located zero of SeparatrixGap, rising (+1) or falling (-1).
  void SeparatrixCrossing(double t, int direction) { separatrix_.push_back({t, direction}); }

  /// An exact value of f = s . H_B / |H| (a start, a segment end, a located extremum).
  void SpinAxisCos(double f) { min_cos_ = std::min(min_cos_, f); }
  /// An accepted step from a to b: f at b, and a minimum of f inside the step when its
  /// rate goes from < 0 to > 0: `exact_minimum()` if given, else the cubic Hermite
  /// interpolant's. An outcome-only run measures the phase's nutation here (no samples):
  /// at the step's end, and its largest value inside the step from the cubic Hermite
  /// interpolant of sin^2 nu (free of the cancellation in cos nu at small nu).
  void SpinAxisStep(const AxisPoint& a,
                    const AxisPoint& b,
                    const std::function<double()>& exact_minimum = {});

  /// The nutation part of SpinAxisStep alone (outcome-only runs; for a runner that
  /// locates the extrema of f as events).
  void NutationStep(const AxisPoint& a, const AxisPoint& b);

  /// Opens a phase at `start` (J_B its right limit). A phase opened at the start time of
  /// the open phase replaces it (zero length).
  void OpenPhase(const PhaseInfo& info, const RunSample& start);
  /// Closes the open phase at `end` (J_B its left limit).
  void ClosePhase(const RunSample& end);

  /// The linear stability of the open phase's steady spin (linear_stability.h), given
  /// right after OpenPhase: the phase's nutation is then measured from the steady spin's
  /// axis (the direction of H_B there) instead of the nearest principal axis.
  void SetSteadySpin(const analysis::SteadySpin& s);

  /// Hands the last samples to the sink and fills `out`: the last sample, flip times (sorted),
  /// 45-degree crossings, danger windows, max_h_N_drift (outcome-only runs: from out.final_state),
  /// max_spin_axis_angle, one stage report per phase and the outcome.
  void Finish(MissionResult& out);

 private:
  struct Phase {
    PhaseInfo info;
    RunSample start;
  };
  StageReport Report(std::size_t i, const std::vector<double>& flips) const;
  /// Hands the block to the sink (keeping its last sample) and empties it.
  void Flush();
  /// The outcome of the run (after the flips, crossings and reports are in `out`).
  analysis::MotionOutcome Outcome(const MissionResult& out) const;
  /// The rigid-body rule's verdict on the final phase and why the linearization differs.
  static void TimeToTumble(analysis::MotionOutcome& o, const std::vector<double>& crossings_45);
  /// A flat spin by the energy: the final phase began about the minor axis, ends with the
  /// separatrix gap above 0 and crossed it rising: its time, the axis from the polhode (the
  /// major axis, signed by H_B). False otherwise.
  bool FlatSpin(analysis::MotionOutcome& o, const RunSample& end) const;
  void Predictions(analysis::MotionOutcome& o) const;

  math::Vec3 s_;
  math::Vec3 h_N0_;
  double M_;
  SampleSink* sink_;
  std::function<void(double)> progress_;
  double t0_, t1_;
  double last_reported_ = -1.0;

  Trajectory block_;
  Trajectory last_sample_;
  bool have_principal_ = false;
  math::Mat3 principal_J_ = math::Mat3::Zero();
  math::PrincipalAxes principal_{};
  bool in_window_ = false;
  std::vector<DangerWindow> danger_windows_;
  double max_h_N_drift_ = 0.0;

  std::vector<double> flips_;
  std::vector<double> crossings_45_;
  struct Crossing {
    double t;
    int direction;
  };
  std::vector<Crossing> separatrix_;
  double min_cos_ = std::numeric_limits<double>::infinity();

  std::vector<Phase> phases_;
  std::vector<RunSample> phase_ends_;

  // The nutation of the open phase about its spin axis (the principal axis of J_B
  // nearest H_B at its start).
  math::Vec3 phase_axis_ = math::Vec3::UnitZ();
  void NutationValue(double nu);
  /// [rad] the nutation at (t, H_B, every hinge's angle or none): the angle from the
  /// phase's axis, or from a periodic orbit's H_B at the same phase (its clock the time,
  /// or a free rotor's angle where the sample has it).
  double Nutation(double t, const math::Vec3& H_B, const Eigen::VectorXd& theta) const;
  void StartNutation();
  analysis::EnvelopeTracker envelope_;
  int nutation_samples_ = 0;
  double nutation_begin_ = 0.0, nutation_end_ = 0.0, nutation_max_ = 0.0;
  analysis::SteadySpin steady_;
};

}  // namespace deploysim::run
