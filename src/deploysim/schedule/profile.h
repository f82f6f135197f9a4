#pragma once

/// A deployment profile, free of YAML: the model, the initial state, the stages, the
/// integrator and the output sampling (docs/design.md 2.6, 5). io/ reads it from YAML with
/// strict validation; docs/file_formats.md documents the file.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/math/types.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/hinge_plan.h"
#include "deploysim/schedule/laws.h"

namespace deploysim::schedule {

/// How J(t) is formed between configurations.
enum class Mode {
  kTensor,    ///< Interpolate the inertia tensors (convex combinations stay valid).
  kGeometry,  ///< Interpolate the hinge angles and compute J, h_rel from the geometry.
};

/// Whether the panels' relative motion enters the momentum.
enum class Coupling {
  kQuasiRigid,  ///< h_rel = 0: the seed thesis's instantaneously rigid body.
  kExact,       ///< h_rel from the hinge rates (geometry mode only).
};

std::string ToString(Mode m);
std::string ToString(Coupling c);

/// One stage on [t_begin, t_end]: a hold (from == to) or a move from the previous
/// stage's configuration to `to` with `law`.
struct Stage {
  std::string name;
  /// Configuration at t_begin. Required on the first stage; on later stages it must equal
  /// the previous stage's `to`, or be empty (meaning exactly that).
  std::string from;
  std::string to;  ///< Configuration at t_end (== from for a hold).
  Law law = Law::kStep;
  double t_begin = 0.0;  ///< [s]
  double t_end = 0.0;    ///< [s] > t_begin.
  bool is_hold() const { return from == to; }
};

/// The initial spin as analysts give it (`initial.spin`, initial_spin.h): resolved on load
/// to H_B(t0), which the run uses; kept to describe the input.
struct InitialSpin {
  math::Vec3 axis_B = math::Vec3::UnitZ();  ///< Body axis s (unit).
  double rate = 0.0;                        ///< [rad/s] > 0: w_NB_B(t0) . s.
  std::optional<double> nutation;           ///< [rad] in [0, pi/2): angle of H_B(t0) from s.
  std::optional<double> azimuth;            ///< [rad]: direction of that tilt about s.
  /// The rate was given in rpm (`rate_rpm`): a unit chosen on purpose, so a fast spin
  /// (Explorer 1's 750 rpm) is no mistaken unit (schedule::ProfileWarnings).
  bool rate_in_rpm = false;
};

struct InitialState {
  math::Quat q_NB = math::Quat::Identity();
  /// Exactly one of these is set: the body angular velocity w_NB_B [rad/s] or the
  /// total angular momentum H_B [kg m^2/s] at t = t_begin of the first stage.
  std::optional<math::Vec3> w_NB_B;
  std::optional<math::Vec3> H_B;
  /// Set when the file gave `spin`: H_B is then the momentum it resolves to
  /// (schedule::SpinMomentum) and w_NB_B is unset.
  std::optional<InitialSpin> spin;
  /// `hinges:` profiles: the model configuration giving the hinge angles at t0 (required
  /// there; empty in stage profiles, whose first stage names it).
  std::string configuration;
  /// `hinges:` profiles: the hinge rates at t0 [rad/s], one per panel (empty: every hinge
  /// at rest). Non-zero only for a free hinge released at the start (a panel released
  /// while moving, a free rotor already spinning); ValidateProfile states the rule.
  Eigen::VectorXd hinge_rates;
};

struct IntegratorSpec {
  std::string method = "rkmk-rkf78";
  double step = 0.0;  ///< [s] fixed step, or initial step of adaptive methods (0: automatic).
  double rtol = 1e-10;
  /// Momenta: relative to |H_B(0)|; angles (attitude, hinge angles): in rad.
  double atol = 1e-12;
  double max_step = 1e300;
};

/// The accepted tolerances. Tighter than kMinRtol no double-precision run can meet its
/// tolerance over a long run (the steps underflow); looser than kMaxRtol or kMaxAtol
/// (an angle of 0.06 deg, a momentum of 0.1 % of the spin's) the error control no longer
/// keeps a free hinge's swing, its stop impacts and the energy to any stated accuracy
/// (at atol 1e12 a wing passed its stop by 130 deg and the energy rose with no source).
inline constexpr double kMinRtol = 1e-14;
inline constexpr double kMaxRtol = 1e-3;
inline constexpr double kMaxAtol = 1e-3;

/// The rule that `value` of an `integrator:` key ("rtol", "atol", "step", "max_step")
/// violates, as the text after "must ..." ("must be in [1e-14, 0.001]"); empty when it
/// keeps it. The one statement of these ranges, for profiles, sweeps and Python dicts.
std::string IntegratorRuleViolated(const std::string& key, double value);

struct OutputSpec {
  double dt = 0.1;   ///< [s] output sampling interval.
  bool csv = false;  ///< Also write a CSV next to the HDF5 file.
};

/// A profile is one of two kinds:
///  - a stage profile (`stages:`): every panel follows the stages' configurations
///    together (docs/design.md 2.6); `hinges` is empty;
///  - a hinge profile (`hinges:`): each panel has its own HingePlan (locked,
///    prescribed on its own windows, or free), the run goes from `start` to `until`,
///    mode is geometry and coupling exact; `stages` is empty (the stage table of a run is
///    made of the phases between the run's events, run/mission.h).
struct Profile {
  std::string name;
  std::string description;
  std::string source;  ///< File it was read from, or empty.
  std::string text;    ///< The profile's own text (stored in the HDF5 file).
  model::Model model;
  Mode mode = Mode::kTensor;
  Coupling coupling = Coupling::kQuasiRigid;
  InitialState initial;
  std::vector<Stage> stages;  ///< Contiguous, increasing times (stage profiles only).
  /// Hinge profiles only: one plan per panel, in the model's panel order.
  std::vector<HingePlan> hinges;
  double start = 0.0;  ///< [s] hinge profiles: start time.
  double until = 0.0;  ///< [s] hinge profiles: end time (> start).
  IntegratorSpec integrator;
  OutputSpec output;
  bool is_hinge_profile() const { return !hinges.empty(); }
  /// True when a hinge has a free plan (it needs analysis::RunsFreeHinges's methods).
  bool has_free_hinge() const {
    for (const HingePlan& h : hinges) {
      if (h.kind == HingePlan::Kind::kFree) return true;
    }
    return false;
  }
  double t_begin() const { return is_hinge_profile() ? start : stages.front().t_begin; }
  double t_end() const { return is_hinge_profile() ? until : stages.back().t_end; }
};

/// Shortest stage allowed, as a fraction of the profile's time scale
/// max(|t_begin|, |t_end|) of the whole profile: every stage must last at least
/// kMinStageDurationFraction * max(|t_begin|, |t_end|). Shorter stages are rejected
/// (docs/file_formats.md, "Stage durations"): a time that close to a stage boundary is
/// rounding noise to the scheduler (it snaps times within 1e-12 of the time scale to
/// the boundary, DeploymentSchedule), to the integrators' step control (1e-14) and to the
/// Simbody cross-check (which merges report times within 1e-9), so such a stage's
/// boundaries would be lost instead of being integrator breakpoints.
inline constexpr double kMinStageDurationFraction = 1e-8;

/// Checks the cross-field rules a file reader cannot see key by key (stages contiguous
/// and increasing, no stage shorter than kMinStageDurationFraction of the time scale,
/// configurations exist, exact coupling only in geometry mode, step law not with exact
/// coupling, ...). Hinge profiles (docs/file_formats.md, "Hinge profiles"): no stages, a
/// hinged model, geometry mode, exact coupling; finite start < until; an existing
/// initial.configuration; one plan per panel; prescribed moves in time order, not
/// overlapping, after start, not step, each at least kMinStageDurationFraction of the
/// time scale long; free drives with stiffness, damping and friction >= 0, a friction
/// regularization speed > 0, a torque-speed motor's stall torque and no-load speed
/// non-zero and of one sign, stops min < max with restitution in [0, 1], the initial and
/// latch angles within the stops, the latch angle != the initial angle, jam_fraction in
/// (0, 1) (0: none), a release at >= start or after the latch of another free, latched
/// panel with delay >= 0, and no cycle of releases; every number finite. Throws
/// std::invalid_argument "<file>: <key path> = <value>: <rule>" (key paths as in the file:
/// `hinges.wing_plus_x.free.latch.angle_deg`, angles shown in degrees).
void ValidateProfile(const Profile& p);

/// How many times ValidateProfile has run in this process (a compiled run validates its
/// profile once: tests count it).
std::uint64_t ValidationCount();

/// Sets the plans of the model's appendages' bending hinges (model.h Appendage): free from
/// the start, on the spring (rest angle 0) and damper the model generated. `plans` has one
/// plan per panel of m.hinged.
void SetAppendagePlans(const model::Model& m, std::vector<HingePlan>& plans);

}  // namespace deploysim::schedule
