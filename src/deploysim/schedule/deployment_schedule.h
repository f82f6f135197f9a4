#pragma once

/// The deployment scheduler (docs/design.md 2.6): turns a profile's stages into J_B(t),
/// dJ_B/dt and h_rel_B(t) for the integrators, consistently at any time asked, with
/// the stage boundaries as breakpoints.
///
/// On stage i with duration D = t_end - t_begin, tau = (t - t_begin) / D and law value
/// s(tau) (laws.h):
///   tensor mode:   J_B = (1 - s) J_from + s J_to,  dJ_B/dt = s'(tau) / D (J_to - J_from),
///                  h_rel_B = 0, relative_kinetic_energy = 0. Convex combinations of valid tensors
///                  are valid. For a hinged model, J_from/J_to are the configurations' zero-rate
///                  tensors.
///   geometry mode: theta = (1 - s) theta_from + s theta_to [rad],
///                  theta' = s'(tau) / D (theta_to - theta_from),
///                  theta'' = s''(tau) / D^2 (theta_to - theta_from);
///                  J_B, dJ_B/dt, h_rel_B and the relative kinetic energy T_rel from
///                  model::ComputeMassProperties (docs/design.md 2.5); h_rel_B and T_rel
///                  set to 0 under quasi-rigid coupling (the instantaneously rigid body).
/// Holds are constant. A step-law stage has its `to` configuration on (t_begin, t_end] and
/// at t_begin from the right, zero rates. At a stage boundary Side::kLeft takes the stage
/// that ends there and Side::kRight the stage that starts there; times within
/// 1e-12 * max|boundary| of a boundary count as the boundary. Every stage lasts at least
/// kMinStageDurationFraction (1e-8) * max|boundary| (ValidateProfile), 1e4 times that
/// tolerance, so no boundary is ever absorbed by a neighbour: every stage boundary is a
/// breakpoint. Before the first stage and after the last the schedule holds the first
/// stage's start and the last stage's end configuration with zero rates.

#include <Eigen/Core>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::schedule {

/// Marks a profile that has passed ValidateProfile (run::CompiledRun builds the
/// schedule of the profile it has just validated).
struct Validated {};
inline constexpr Validated kValidated{};

class DeploymentSchedule final : public dynamics::InertiaSource {
 public:
  /// Validates the profile (ValidateProfile; throws std::invalid_argument), resolves an
  /// empty `from` to the previous stage's `to`, and precomputes the configurations.
  /// A hinge profile (Profile::is_hinge_profile) has no stages: std::invalid_argument.
  explicit DeploymentSchedule(const Profile& profile);
  /// The same for a profile that has passed ValidateProfile: not validated again.
  DeploymentSchedule(const Profile& profile, Validated);

  dynamics::InertiaSample Evaluate(double t,
                                   dynamics::Side side = dynamics::Side::kRight) const override;
  /// Stage boundaries (including the first start and the last end) strictly inside
  /// (t0, t1), ascending; boundaries within the rounding tolerance of t0 or t1 are left out.
  std::vector<double> Breakpoints(double t0, double t1) const override;
  /// True iff [t0, t1] lies within one hold, within one step-law stage (t0 may be its
  /// start: the switch has happened from the right), or entirely before the first or after
  /// the last stage. t0 and t1 may miss a stage bound by the rounding tolerance.
  bool IsRigidOn(double t0, double t1) const override;

  /// Index of the stage containing t (right-continuous; the last stage for t >= end, the
  /// first for t < start; Side::kLeft picks the stage that ends at a boundary).
  int StageAt(double t, dynamics::Side side = dynamics::Side::kRight) const;
  const std::vector<Stage>& stages() const { return stages_; }

  /// Geometry mode: hinge angles [rad], rates [rad/s] and accelerations [rad/s^2] at t,
  /// one per panel. Tensor mode: empty vectors.
  Eigen::VectorXd HingeAngles(double t, dynamics::Side side = dynamics::Side::kRight) const;
  Eigen::VectorXd HingeRates(double t, dynamics::Side side = dynamics::Side::kRight) const;
  Eigen::VectorXd HingeAccelerations(double t, dynamics::Side side = dynamics::Side::kRight) const;

  /// Full mass properties at t as the dynamics sees them. Geometry mode: everything
  /// (mass, CoM and its rate, J_B, dJ_B/dt, h_rel_B and relative_kinetic_energy, both 0
  /// under quasi-rigid coupling). Tensor mode: J_B and dJ_B/dt only; mass, CoM, h_rel_B
  /// and relative_kinetic_energy are zero.
  model::MassProperties MassPropertiesAt(double t,
                                         dynamics::Side side = dynamics::Side::kRight) const;

 private:
  /// Where a time falls: before the first stage, inside stage `stage` at normalized time
  /// tau in [0, 1], or after the last stage. Outside the stages the schedule holds the
  /// first stage's start and the last stage's end configuration.
  enum class Region { kBefore, kInside, kAfter };
  struct Where {
    Region region = Region::kInside;
    int stage = 0;
    double tau = 0.0;
  };
  /// Relative tolerance within which a time counts as a stage boundary, so that
  /// t_begin + (t_end - t_begin) rounding off by an ulp still picks the side asked for.
  static constexpr double kBoundaryRelTolerance = 1e-12;
  static_assert(kMinStageDurationFraction >= 1e3 * kBoundaryRelTolerance,
                "a stage must be much longer than the boundary tolerance, or a boundary "
                "within the tolerance of another would be dropped from the breakpoints");

  Where Locate(double t, dynamics::Side side) const;
  /// Region ordinal: -1 before, stage index inside, stages_.size() after.
  int Ordinal(const Where& w) const;
  /// True when stage i's J is constant with zero rates (hold, or step after its switch).
  bool StageIsRigid(int i) const;
  /// Law value at w: s, ds/dtau, d2s/dtau2; zero rates on rigid stages and outside.
  LawValue LawAt(const Where& w) const;
  /// The constant sample that applies at w when LawAt has zero rates.
  const dynamics::InertiaSample& RigidSample(const Where& w) const;
  /// Geometry mode: mass properties at w with law value v (h_rel and T_rel zeroed if
  /// quasi-rigid).
  model::MassProperties GeometryAt(const Where& w, const LawValue& v) const;

  // implementation details are the schedule module's own
  std::vector<Stage> stages_;  // `from` resolved (a `to` stage starts where the previous ends)
  Mode mode_;
  Coupling coupling_;
  model::Model model_;                                  // hinged body validated (unit hinge axes)
  std::vector<math::Mat3> J_from_, J_to_;               // per stage, both modes
  std::vector<Eigen::VectorXd> theta_from_, theta_to_;  // geometry mode, per stage
  std::vector<model::MassProperties> mp_from_, mp_to_;  // geometry mode, zero rates
  std::vector<dynamics::InertiaSample> sample_from_, sample_to_;  // zero-rate samples
  std::vector<double> bounds_;   // stages_.size() + 1 boundaries, ascending
  double time_tolerance_ = 0.0;  // [s] kBoundaryRelTolerance * max |boundary|
};

}  // namespace deploysim::schedule
