#pragma once

/// The outcome of a run, measured from the motion (docs/design.md 2.8): one record that
/// `analyze` (table and JSON), the HDF5 file (root attribute `outcome`), the report's
/// headline, the viewer and the sweep read, so that they cannot disagree.
///
/// What it measures, on the final phase (after the last release, latch or stage change)
/// unless said otherwise:
///  - the nutation nu(t): the angle between H_B and the axis of the phase's steady spin
///    (the linearization's; else the principal axis of J_B nearest H_B at the phase's
///    start), and its envelope: the largest value per window of about one nutation
///    period, from the output samples (a local maximum refined by the parabola through
///    its neighbours) or, in an outcome-only run, from the accepted steps (run_recorder.h);
///  - the envelope's trend: ln(nu_peak) = a + sigma t fitted by least squares over the
///    peaks in the small-nutation band (kFitFloor..kFitCeiling, where the motion is
///    linear; the first quarter of the band's longest stretch is left out: the sink's own
///    transient), with the slope's standard error. sigma > 0 grows, < 0 decays, and a
///    slope within 3 standard errors of 0 or changing nu by less than 5 % over the fit is
///    "bounded" (with no peaks in the band, the band reaches 45 deg: the trend only; a
///    shrinking nutation about a spin the linearization calls unstable is "bounded" too);
///  - the flips (the flip rule, flip_rule.h) and their mean interval;
///  - a transition: the run ends spinning about another body axis than it started about
///    (H_B nearer another principal axis of J_B, and more than 45 deg from the initial
///    spin axis), at the time of its last 45-degree crossing; minor -> major is a flat
///    spin;
///  - the largest excursion (the largest angle between the initial spin axis and h_N);
///  - the deployment's faults: a jam, a latch that never happens (and whether the panel
///    rests on a stop short of it), a release that never comes.
/// Beside the measurement, the predictions (linear_stability.h): the linear stability of
/// the final phase's steady spin, the quasi-rigid estimate, and the rigid-body rule (minor
/// or major axis stable, intermediate unstable), with the reason where the rule and the
/// linearization disagree (a rotor, dissipation).

#include <limits>
#include <string>
#include <vector>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/math/types.h"
#include "deploysim/math/units.h"

namespace deploysim::schedule {
struct Profile;
}  // namespace deploysim::schedule

namespace deploysim::analysis {

/// [rad] the small-nutation band of the envelope fit: where the linear rate holds to
/// ~nu^2 (1e-3 at 1.8 deg), above the rounding floor.
inline constexpr double kFitFloor = 1e-7;
inline constexpr double kFitCeiling = 0.0314159265358979;  // 1.8 deg

/// [rad] Tumbling, the project's one definition: the body axis the motion turns about
/// (the spin axis; a final motion's circulation axis) more than 45 deg from h_N. The
/// outcome's time to tumble and 45-degree crossings, its tumbling class and the sweep's
/// motion class (by default) all use it.
inline constexpr double kTumbleAngle = math::kPi / 4.0;
/// cos kTumbleAngle (the 45-degree rule's comparisons are of cosines).
inline constexpr double kCosTumbleAngle = 0.70710678118654752440;

/// A point of the nutation's envelope.
struct EnvelopePeak {
  double t = 0.0;   ///< [s]
  double nu = 0.0;  ///< [rad]
  /// A local maximum of the samples (refined by its parabola), not a window's end.
  bool local_max = false;
};

/// The envelope of a sampled nutation, fed one sample at a time: the largest sample of
/// each window of the given length (about one nutation period), refined by the parabola
/// through it and its neighbours when it is a local maximum. A nutation that grows or
/// decays without oscillating (an axisymmetric body) gives the window ends.
///
/// About a periodic orbit (ResetMeanSquare) the magnitude of the nutation is modulated at
/// the orbit's frequency, and the largest sample of a window jitters with the beat of the
/// two (measured: 1-3 % of the fitted rate). There the envelope is the root of the
/// Hann-weighted mean of nu^2 over windows overlapping by half, each at its centre: the
/// weight removes the nutation's own 2 omega term exactly when the window is 2 pi / omega
/// long, and a term of frequency f to O((f L)^-3); an exponential factor exp(2 sigma t)
/// scales every window's mean alike, so the slope is sigma.
class EnvelopeTracker {
 public:
  /// Starts over with windows of `window` seconds (> 0).
  void Reset(double window);
  /// Starts over with the Hann-weighted mean square over windows of `window` seconds.
  void ResetMeanSquare(double window);
  void Add(double t, double nu);
  /// A located local maximum (not refined): the envelope of an outcome-only run, whose
  /// peaks come from the steps' interpolants. Not to be mixed with Add in one window.
  void AddPeak(double t, double nu);
  const std::vector<EnvelopePeak>& peaks() const { return peaks_; }

 private:
  void Emit();
  void AddMeanSquare(double t, double nu);
  bool mean_square_ = false;
  std::vector<EnvelopePeak> window_samples_;  // mean square: since the open window's start
  double window_start_ = 0.0;
  double window_ = 1.0, window_end_ = 0.0;
  bool open_ = false, need_right_ = false, have_prev_ = false;
  EnvelopePeak prev_, best_, left_, right_;
  bool have_left_ = false, have_right_ = false;
  std::vector<EnvelopePeak> peaks_;
};

/// [s] the time constant 1 / |rate| of an exponential rate (+inf for 0, NaN for NaN).
double TimeConstant(double rate);

/// An exponential fit of an envelope: nu ~ exp(rate t).
struct ExponentialFit {
  bool valid = false;       ///< at least 4 peaks in the band
  double rate = 0.0;        ///< [1/s]
  double rate_sigma = 0.0;  ///< [1/s] standard error of the slope
  /// [1/s] what the rate is known to: rate_sigma plus the difference of the rates fitted
  /// on the two halves of the stretch (a bias that the standard error does not show: a
  /// mode not yet decayed, the nutation leaving the linear band).
  double rate_uncertainty = 0.0;
  double t_begin = 0.0, t_end = 0.0;    ///< [s] the fitted stretch
  double nu_begin = 0.0, nu_end = 0.0;  ///< [rad] the fit's values there
  int points = 0;
  /// [rad] the band's upper end: kFitCeiling (the linear rate), or 45 deg where no peaks
  /// lie below kFitCeiling (a trend only: the rate of a large nutation is not the linear
  /// one).
  double ceiling = 0.0;
  /// Growing or decaying beyond doubt (|rate| > 3 rate_sigma and nu changing by more
  /// than 5 % over the fit); otherwise bounded.
  bool significant() const;
  /// [s] 1 / |rate| (+inf when 0).
  double time_constant() const;
};

/// The fit over `peaks` within [floor, ceiling] (see the file comment), from `t_start` on:
/// the time from which the other modes of the linearization have decayed below the
/// nutation mode (FitStart); -inf where it is not known, and then the first quarter of
/// the stretch is left out instead (or where fewer than 4 peaks lie after t_start). Where
/// the stretch holds at least 4 local maxima and they are at least half its points, the
/// fit takes them only: a window that ends before the nutation's next maximum (a period
/// longer than the window) gives its end, a point below the envelope.
ExponentialFit FitEnvelope(const std::vector<EnvelopePeak>& peaks,
                           double floor = kFitFloor,
                           double ceiling = kFitCeiling,
                           double t_start = -std::numeric_limits<double>::infinity());

/// [s] the time after `phase_begin` from which every other mode of `s` that decays
/// relative to the nutation mode (real part below its growth rate) is 1e-4 of it, had
/// they started alike: ln(1e4) / (growth_rate - rate_k) for the slowest of them.
/// -inf without a linearization.
double FitStart(const SteadySpin& s, double phase_begin);

/// The outcome classes, most severe first.
enum class OutcomeClass {
  kIncomplete,  ///< the run did not reach its end
  kFlipping,    ///< periodic flips (spin about the intermediate axis)
  kTransition,  ///< ends spinning about another axis (minor -> major: a flat spin)
  kGrowing,     ///< nutation growing (an unstable spin not yet gone)
  kDecaying,    ///< nutation decaying (an asymptotically stable spin)
  kTumbling,    ///< no steady spin: the spin axis swings 45 deg or more from h_N
  kBounded,     ///< nutation bounded (a steady spin)
};
/// "incomplete", "flipping", "transition", "growing", "decaying", "tumbling", "bounded"
/// (OutcomeName says "flat spin" for a minor -> major transition).
std::string ToString(OutcomeClass c);
/// The outcome's name: ToString(c), "flat spin" for a transition from a minor-axis spin
/// (at the final phase's start) to the major axis.
std::string OutcomeName(OutcomeClass c, AxisRole phase, AxisRole end);

/// A deployment fault.
struct DeploymentFault {
  enum class Kind { kJam, kNeverLatched, kRestsShort, kNeverReleased };
  Kind kind = Kind::kJam;
  int panel = 0;
  std::string panel_name;
  double t = std::numeric_limits<double>::quiet_NaN();            ///< [s] NaN: never
  double angle = std::numeric_limits<double>::quiet_NaN();        ///< [rad] where it stopped
  double latch_angle = std::numeric_limits<double>::quiet_NaN();  ///< [rad]
};
/// "jam", "never latched", "rests short of latch", "never released".
std::string ToString(DeploymentFault::Kind k);

struct MotionOutcome {
  OutcomeClass outcome = OutcomeClass::kBounded;
  std::string outcome_name;  ///< ToString(outcome), "flat spin" for minor -> major
  /// The body axis the run spins about at the start and at the end: "+x" ... "-z" (the
  /// body axis nearest the principal axis nearest H_B), and its role in J_B there.
  std::string axis_start, axis_end;
  AxisRole role_start = AxisRole::kDegenerate, role_end = AxisRole::kDegenerate;
  /// The role of the run's spin axis at the start of the final phase (a deployment may
  /// have turned a minor axis into the intermediate one).
  AxisRole role_phase = AxisRole::kDegenerate;
  double phase_begin = 0.0;  ///< [s] start of the final phase (the fits' window)
  double t_end = 0.0;        ///< [s] the run's end
  double nutation_begin = 0.0, nutation_end = 0.0, nutation_max = 0.0;  ///< [rad] the phase's
  ExponentialFit trend;  ///< of the final phase's envelope
  int flips = 0;         ///< in the final phase
  double flip_interval = std::numeric_limits<double>::quiet_NaN();  ///< [s] mean
  /// [s] a flat spin's: separatrix_time; another transition's: last_45_time.
  double transition_time = std::numeric_limits<double>::quiet_NaN();
  /// [s] the last rising crossing of the separatrix gap (run_recorder.h, SeparatrixGap)
  /// in the final phase, for a flat spin; NaN otherwise.
  double separatrix_time = std::numeric_limits<double>::quiet_NaN();
  /// [s] the first and the last passage of the spin axis 45 deg from h_N in the final
  /// phase (NaN: none).
  double first_45_time = std::numeric_limits<double>::quiet_NaN();
  double last_45_time = std::numeric_limits<double>::quiet_NaN();
  double max_excursion = 0.0;  ///< [rad] largest angle between the initial spin axis and h_N
  std::vector<DeploymentFault> faults;
  // The predictions for the final phase's steady spin.
  SteadySpin linear;  ///< linear.found false: none (linear.reason)
  /// [s] when the nutation would reach 45 deg growing at linear.growth_rate from
  /// nutation_begin (NaN: not growing): the time to a flat spin or a tumble predicted
  /// from the small motion, beside the measured transition_time.
  double predicted_45_time = std::numeric_limits<double>::quiet_NaN();
  /// [s] the time to tumble: from the final phase's start to the spin axis's first
  /// passage 45 deg from h_N, measured when the run gets there (time_to_tumble_measured),
  /// else predicted (predicted_45_time - phase_begin); +inf when the linearization says
  /// the steady spin does not grow; NaN when neither says.
  double time_to_tumble = std::numeric_limits<double>::quiet_NaN();
  bool time_to_tumble_measured = false;
  std::string rigid_rule;    ///< "stable" / "unstable" / "" (degenerate axis)
  std::string disagreement;  ///< why the rigid-body rule and the linearization differ
  std::string headline;      ///< one sentence: faults first, then the motion
};

/// "+x", "+y", "+z", "-x", "-y", "-z": the body axis nearest the unit vector a.
std::string BodyAxisName(const math::Vec3& a);

/// The one-sentence headline of an outcome (faults first, then the motion, then the
/// prediction where it disagrees with the rigid-body rule).
std::string Headline(const MotionOutcome& o);

/// The outcome as one JSON object (SI units, angles in rad, NaN and infinities as null):
/// the record `analyze --json` prints as "outcome" and the HDF5 file stores as the root
/// attribute `outcome` (docs/file_formats.md, "Outcome").
std::string OutcomeJson(const MotionOutcome& o);

}  // namespace deploysim::analysis
