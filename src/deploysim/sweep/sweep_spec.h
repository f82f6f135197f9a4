#pragma once

/// A parameter sweep, free of YAML (docs/sweeps.md): a base deployment profile plus
/// parameter axes, as a grid (Cartesian product) and/or seeded Monte Carlo samples.
/// sweep_file.h reads it from YAML; this file turns a case index into the case's
/// parameter values and its deployment profile.
///
/// Case numbering. With G grid points (the product of the axis lengths; 1 without a grid)
/// and S Monte Carlo samples per grid point (1 without Monte Carlo), there are G * S
/// cases; case i is grid point g = i / S, sample j = i % S. Grid points are numbered
/// row-major over the axes in file order (the last axis varies fastest).
///
/// Determinism. A case is a pure function of (spec, i): Monte Carlo draws come from
/// Rng(seed, j, parameter position), so sample j has the same dispersions at every grid
/// point (common random numbers: differences across the grid are the grid's alone).
///
/// Application order in BuildCase, whatever the order in the file (docs/sweeps.md):
///   1. model: the appendages' parameters change their specs (the values bending_stiffness,
///      damping_ratio and fill_fraction, all-appendage targets first, then per-appendage
///      ones; then the factor bending_stiffness_scale, all-appendage and per-appendage
///      factors multiply), the appendages are expanded again from the model file's own
///      body (model::RebuildAppendages: springs, dampers, a tank's pendulum and fixed
///      mass, as the model file with these values would give them) and their bending
///      hinges' plans reset from the result (schedule::SetAppendagePlans); then
///      panel_mass_scale (mass and inertia of the panel(s), generated ones included;
///      all-panel and per-panel factors multiply), inertia_scale (tensors models; factors
///      multiply);
///   2. stage profiles (`stages:`): coupling; law (all move stages, then per-stage values
///      override);
///      hinge profiles (`hinges:`; Target::panel -1 = every free panel but the hinges
///      the appendages generated, whose springs and dampers are step 1's): values that
///      set a quantity (spring_stiffness, damping, latch_angle, motor_torque, release_time,
///      release_delay, friction_torque, stick_fraction), all-panel targets first, then
///      per-panel ones; then the factors (spring_stiffness_scale, motor_torque_scale;
///      all-panel and per-panel multiply); then latch_fails = yes: the panel's latch is
///      disabled (unless it jams first: stick_fraction > 0 keeps it), and a panel
///      released after that latch (after_latch) is never released: its release moves
///      past the end of the run;
///   3. stage profiles: timing: every move stage's duration times deploy_duration_scale,
///      then stage_duration values replace single stages' durations; stages stay
///      contiguous from the first stage's start (later stages shift, holds keep theirs);
///   4. initial state: nutation / nutation_azimuth tilt H_B(t0) about the spin axis
///      (|H_B| kept), then spin_rate scales H_B so that w_NB_B(t0) . s = spin_rate.
/// The spin axis s is the principal axis of the case's J_B(t0) nearest the BASE
/// profile's spin axis (analysis::InitialSpinAxis of the base), so that every case of a
/// sweep measures its angles from the same body axis.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/analysis/motion_outcome.h"
#include "deploysim/math/types.h"
#include "deploysim/model/model.h"
#include "deploysim/run/compiled_run.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::sweep {

/// What a sweep axis varies.
enum class Parameter {
  kDeployDurationScale,  ///< [1] > 0: factor on the duration of every move stage.
  kStageDuration,        ///< [s] > 0: duration of one stage (Target::stage).
  kSpinRate,             ///< [rad/s] > 0: w_NB_B(t0) . s (file: spin_rate or spin_rate_rpm).
  kNutation,             ///< [rad] in [0, pi/2): angle of H_B(t0) from s (file: nutation_deg).
  kNutationAzimuth,      ///< [rad]: direction of the tilt about s (file: nutation_azimuth_deg).
  kPanelMassScale,       ///< [1] > 0: factor on panel mass and inertia (hinged models).
  kInertiaScale,         ///< [1] > 0: factor on configuration tensors (tensors models).
  kLaw,                  ///< categorical: interpolation law of move stages.
  kCoupling,             ///< categorical: quasi-rigid | exact.
  // Free hinges of hinge profiles (schedule::FreeDrive), per panel (Target::panel).
  kSpringStiffness,       ///< [N m/rad] >= 0: Spring::stiffness.
  kSpringStiffnessScale,  ///< [1] >= 0: factor on Spring::stiffness (a weak spring).
  kDamping,               ///< [N m s/rad] >= 0: FreeDrive::damping.
  kLatchAngle,            ///< [rad]: Latch::angle (file: latch_angle_deg).
  kMotorTorque,           ///< [N m]: a constant motor's torque (adds one where none).
  kMotorTorqueScale,      ///< [1] > 0: factor on a constant torque or a stall torque.
  kReleaseTime,           ///< [s]: release at this time (Release::kAtTime).
  kReleaseDelay,          ///< [s] >= 0: delay of an after-latch release.
  kFrictionTorque,        ///< [N m] >= 0: Friction::torque.
  kStickFraction,         ///< [1] in [0, 1): Latch::jam_fraction (0: no jam).
  kLatchFails,            ///< categorical: no | yes (Latch::enabled = false).
  // The model's appendages (model.h Appendage), per appendage (Target::appendage).
  kBendingStiffness,       ///< [N m^2] > 0: EI of every bending plane of a beam.
  kBendingStiffnessScale,  ///< [1] > 0: factor on EI of every bending plane of a beam.
  kDampingRatio,           ///< [1] in [0, 1): a beam's or a slosh pendulum's damping ratio.
  kFillFraction,           ///< [1] in (0, 1]: a slosh tank's fill fraction (SloshTank).
};

/// True for the categorical parameters (law, coupling, latch_fails).
bool IsCategorical(Parameter p);
/// True for the parameters of stage profiles only (deploy_duration_scale,
/// stage_duration, law, coupling).
bool IsStageParameter(Parameter p);
/// True for the parameters of free hinges (hinge profiles only).
bool IsHingeParameter(Parameter p);
/// True for the parameters of the model's appendages (bending_stiffness,
/// bending_stiffness_scale, damping_ratio, fill_fraction).
bool IsAppendageParameter(Parameter p);
/// Whether an appendage parameter acts on `a`: on a beam (bending_stiffness and its scale,
/// damping_ratio) or a slosh pendulum given by a damping ratio (damping_ratio) or a tank
/// (fill_fraction).
bool AppliesTo(Parameter p, const model::Appendage& a);
/// SI unit of the parameter's column ("1", "s", "rad/s", "rad", "none" for categorical).
std::string UnitsOf(Parameter p);
/// Category names of a categorical parameter (code = position), empty otherwise.
const std::vector<std::string>& CategoriesOf(Parameter p);

/// One varied quantity: the parameter and what it applies to.
struct Target {
  Parameter parameter = Parameter::kSpinRate;
  std::string column;  ///< Result-table column name, unique within a sweep.
  int stage = -1;      ///< kStageDuration (required), kLaw (-1: every move stage).
  /// kPanelMassScale: panel index, -1: every panel; hinge parameters: panel index, -1:
  /// every free panel.
  int panel = -1;
  /// Appendage parameters: index in the model's appendages, -1: every appendage the
  /// parameter applies to (AppliesTo).
  int appendage = -1;
  std::string configuration;  ///< kInertiaScale: configuration name, empty: all.
  int axis = -1;              ///< kInertiaScale: body axis 0, 1, 2 or -1: the whole tensor.
  std::string description;    ///< For the results file: what the column means.
};

/// A grid axis: the values of one target (SI; categorical values are category codes).
struct GridAxis {
  Target target;
  std::vector<double> values;
};

/// A Monte Carlo parameter's distribution.
struct Distribution {
  enum class Kind { kUniform, kNormal, kChoice };
  Kind kind = Kind::kUniform;
  double a = 0.0;  ///< uniform: lower bound; normal: mean (SI).
  double b = 0.0;  ///< uniform: upper bound; normal: standard deviation (SI, > 0).
  /// normal: truncation bounds (resampled until inside), -inf/+inf when not given.
  double min = -1e308;
  double max = 1e308;
  std::vector<double> choices;  ///< kChoice: category codes (or numbers), equally likely
                                ///< unless `cumulative` is given.
  /// kChoice with weights: cumulative probabilities of the choices (ascending, the last
  /// exactly 1); empty: equally likely. A draw takes the first choice whose cumulative
  /// probability exceeds a uniform number in [0, 1).
  std::vector<double> cumulative;
};

struct MonteCarloParameter {
  Target target;
  Distribution distribution;
};

struct MonteCarlo {
  std::size_t samples = 1;
  std::uint64_t seed = 0;
  std::vector<MonteCarloParameter> parameters;
};

/// Settings of the per-case outcome analysis.
struct OutcomeSettings {
  /// [rad] A final motion whose momentum cone about its circulation axis is wider than
  /// this is "tumbling", else a spin about that axis. Default: the project's definition
  /// of tumbling (analysis::kTumbleAngle, 45 deg), the outcome's.
  double tumble_angle = analysis::kTumbleAngle;
  /// [rad/s] The largest acceptable latch shock (max_latch_w_jump) of the question a
  /// sweep asks, if it states one (outcome.latch_shock_limit_deg_s): recorded in the
  /// results file for the maps; it changes no outcome.
  std::optional<double> latch_shock_limit;
};

struct SweepSpec {
  std::string name;
  std::string description;
  std::string source;          ///< The sweep file's path (for messages), or empty.
  std::string text;            ///< The sweep file's text (stored in the results file).
  schedule::Profile base;      ///< The base profile, integrator overrides applied.
  std::string model_text;      ///< The base model file's text (fingerprint of the journal).
  std::vector<GridAxis> grid;  ///< Empty: one grid point (the base).
  std::optional<MonteCarlo> monte_carlo;
  OutcomeSettings outcome;
  /// BaseSpinAxis(base), if already computed (the loader sets it; BuildCase computes it
  /// when unset).
  std::optional<math::Vec3> base_spin_axis_B;

  /// Number of grid points (product of the axis lengths; 1 without a grid).
  std::size_t grid_points() const;
  /// Monte Carlo samples per grid point (1 without Monte Carlo).
  std::size_t samples() const;
  std::size_t case_count() const { return grid_points() * samples(); }
  /// Every target in column order: grid axes, then Monte Carlo parameters.
  std::vector<Target> targets() const;
};

/// The parameters of one case, in the order of SweepSpec::targets().
struct CaseParameters {
  std::size_t index = 0;         ///< Case index.
  std::size_t grid_index = 0;    ///< g = index / samples.
  std::size_t sample_index = 0;  ///< j = index % samples.
  std::vector<double> values;    ///< SI; categorical: category code.
};

/// The parameters of case `index` (< case_count(); std::out_of_range otherwise).
CaseParameters ParametersOf(const SweepSpec& spec, std::size_t index);

/// A case's profile and the body axis its angles are measured from.
struct Case {
  CaseParameters parameters;
  /// The case's run, compiled once (its profile has initial.H_B set, initial.w_NB_B
  /// cleared; a stage profile's schedule is built).
  std::shared_ptr<const run::CompiledRun> run;
  const schedule::Profile& profile() const { return run->profile(); }
  math::Vec3 spin_axis_B = math::Vec3::UnitZ();  ///< Unit, B components.
  /// Hinge profiles: the free panels that have a latch in the BASE profile (a latch that
  /// fails in this case still counts: the outcome's all_latched asks whether each of
  /// them latched).
  std::int64_t latches_expected = 0;
};

/// Builds case `index` (application order in the file comment). Throws
/// std::invalid_argument "<sweep source>: case <i> {<column>=<value>, ...}: <rule>" when
/// the case's profile is not valid (run::CompiledRun::Compile).
Case BuildCase(const SweepSpec& spec, std::size_t index);

/// The spin axis of the base profile: analysis::InitialSpinAxis of J_B(t0), H_B(t0).
math::Vec3 BaseSpinAxis(const schedule::Profile& base);

/// "{deploy_duration_scale=0.5, law=linear}" for messages (values as written, SI).
std::string DescribeParameters(const SweepSpec& spec, const CaseParameters& p);

}  // namespace deploysim::sweep
