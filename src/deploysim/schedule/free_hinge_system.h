#pragma once

/// The hub + panel tree of a hinge profile as a dynamical system (docs/design.md 2.7): each
/// hinge is, at any moment, locked (held before its release, latched, jammed, resting on
/// a stop, or a `locked` plan), prescribed (its moves) or free (state). The hybrid driver
/// (run/hinge_body.cc) changes the set at events; between events this class is the
/// dynamics::ShapeSystem of the free hinges, or (no hinge free) a dynamics::InertiaSource.
///
/// Evaluation at (t, H_B, x = (theta_f, p_f)): theta of every hinge (locked: its angle;
/// prescribed: PrescribedHinge::At(t); free: theta_f), the mass matrix M over
/// (w, theta'_f, theta'_p) (model/mass_matrix.h; p: the prescribed hinges moving at t),
/// the SPD solve
///   [J_B  B_f ] [w       ]   [H_B - B_p theta'_p    ]
///   [B_f' M_ff] [theta'_f] = [p_f - M_fp theta'_p  ]
/// and p'_f = dT/dtheta_f (at fixed velocities) + Q_f (schedule::DriveTorque).
/// Not thread-safe (scratch space): one object per run.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/dynamics/shape_system.h"
#include "deploysim/model/mass_matrix.h"
#include "deploysim/model/model.h"
#include "deploysim/schedule/hinge_motion.h"
#include "deploysim/schedule/hinge_plan.h"

namespace deploysim::schedule {

/// Hinges that move together as theta = theta_0 + basis q (a flexible appendage reduced to
/// its first modes, model::Appendage::modes): their plans are free (spring, damper), and q
/// are coordinates of the shape state from the start.
struct ModalGroup {
  std::string name;         ///< the appendage's, for messages and phase names
  std::vector<int> hinges;  ///< model panel indices
  Eigen::MatrixXd basis;    ///< hinges.size() x K
};

/// The modal groups of a model's appendages (those with modes).
std::vector<ModalGroup> ModalGroupsOf(const model::Model& m);

class FreeHingeSystem final : public dynamics::ShapeSystem, public dynamics::InertiaSource {
 public:
  /// `body` valid (model::ValidatedHingedBody: unit axes), one plan per panel, the angles
  /// at the start. Every non-prescribed hinge starts locked at its initial angle.
  /// Panels whose plan is `locked` and under which no panel ever moves cost nothing: each
  /// such subtree is merged into its parent as one rigid body (its composite mass, CoM
  /// and inertia at its locked angles), so the kinematics, the mass matrix and the
  /// energy gradient run over the panels that can move and their ancestors only (a tree
  /// of 2048 panels with one free is a chain of 12). Every interface below still speaks
  /// of the model's panels by their index.
  ///
  /// Modal coordinates (`modal`): the shape state is laid out as (theta_f, q, p_f, p_q):
  /// the free hinges' angles, then every group's coordinates q; their momenta in the same
  /// order. free_count() counts both; free_hinges() lists the hinges only (state entries
  /// 0 .. free_hinges().size() - 1 of each half). A modal group's hinges count as free
  /// (IsFree) from the start and are never locked.
  FreeHingeSystem(const model::HingedBody& body,
                  const std::vector<HingePlan>& plans,
                  const Eigen::VectorXd& initial_angles,
                  const std::vector<ModalGroup>& modal = {});

  /// The model's panels (merged or not).
  int panel_count() const { return static_cast<int>(red_of_.size()); }
  /// The panels computed with (the others are merged into them): for tests.
  int computed_panel_count() const { return static_cast<int>(plans_.size()); }

  /// Locks hinge k (not prescribed) at `angle` [rad]; a free hinge leaves the free set
  /// (the shape state loses its entries: the caller rebuilds x, or uses the overload).
  void Lock(int k, double angle);
  /// Frees hinge k (kFree plan, now locked): it joins the end of the free set.
  void Free(int k);
  /// The shape state x = (theta_f, p_f) is laid out in free-set order; these change the
  /// set and return the new state from the old one.
  /// Locks free hinge k at `angle`: x without hinge k's entries, the other angles and
  /// momenta unchanged.
  Eigen::VectorXd Lock(int k, double angle, const Eigen::VectorXd& x);
  /// Frees hinge k at time t at its locked angle, moving at `rate` [rad/s] (0: at rest; a
  /// run may start a hinge moving): it joins the end of the set; H_B and the other free
  /// hinges' angles and momenta are kept (so w takes up the rate's momentum).
  Eigen::VectorXd Free(
      int k, double t, const math::Vec3& H_B, const Eigen::VectorXd& x, double rate = 0.0);
  /// The free hinges in shape-state order.
  const std::vector<int>& free_hinges() const { return free_orig_; }
  bool IsFree(int k) const;
  /// The angle of a locked hinge [rad].
  double locked_angle(int k) const {
    const int r = red_of_[static_cast<std::size_t>(k)];
    return r < 0 ? full_angles_[k] : angles_[r];
  }

  // dynamics::ShapeSystem
  int free_count() const override { return static_cast<int>(free_.size()) + modal_count(); }
  /// The modal coordinates (after the free hinges in each half of the shape state).
  int modal_count() const { return static_cast<int>(phi_.cols()); }
  /// The modal groups' hinges (model indices), in the rows' order of their bases.
  const std::vector<int>& modal_hinges() const { return modal_orig_; }
  const std::vector<ModalGroup>& modal_groups() const { return groups_; }
  void Evaluate(double t,
                const math::Vec3& H_B,
                const Eigen::VectorXd& x,
                dynamics::Side side,
                math::Vec3& w_NB_B,
                Eigen::VectorXd& x_dot) const override;
  /// Window boundaries of the prescribed hinges in (t0, t1) (both interfaces).
  std::vector<double> Breakpoints(double t0, double t1) const override;
  /// The first prescribed or servo window boundary after t (+inf if none), beyond any end.
  double NextBreakpoint(double t) const;

  // dynamics::InertiaSource, valid while no hinge is free (throws std::logic_error
  // otherwise): J_B, dJ_B/dt, h_rel_B, T_rel of the locked and prescribed hinges at t (modal
  // coordinates at 0, at rest).
  dynamics::InertiaSample Evaluate(double t,
                                   dynamics::Side side = dynamics::Side::kRight) const override;
  bool IsRigidOn(double t0, double t1) const override;

  /// The power [W] of each source of work on the system at one state: the dampers,
  /// friction and motors (servos included) of the free hinges, and the drives of the
  /// moving prescribed hinges (dT/dt at fixed H_B and x: what the prescribed motion puts
  /// in). Along the flow dE/dt is their sum (E = T + V).
  struct Powers {
    double damper = 0.0, friction = 0.0, motor = 0.0, drive = 0.0;
    double sum() const { return damper + friction + motor + drive; }
  };
  /// The entries of the work accumulators a shape state may carry after (theta_f, p_f):
  /// Evaluate gives their rates, the Powers in this order, and they do not act back.
  static constexpr int kLedgerTerms = 4;

  /// Everything at one state (outputs, events, impulses).
  struct Snapshot {
    math::Vec3 w_NB_B = math::Vec3::Zero();   ///< [rad/s]
    Eigen::VectorXd theta;                    ///< [rad] every hinge
    Eigen::VectorXd theta_dot;                ///< [rad/s] every hinge
    math::Mat3 J_B = math::Mat3::Zero();      ///< [kg m^2] about the system CoM
    math::Vec3 h_rel_B = math::Vec3::Zero();  ///< [kg m^2/s] = B theta'
    double kinetic_energy = 0.0;              ///< [J] 1/2 v^T M v
    double spring_energy = 0.0;               ///< [J] sum of the free hinges' springs V
    /// [W] sum over free hinges of NonConservativeTorque theta' (servos included): dE/dt
    /// along the flow while no prescribed hinge moves.
    double power = 0.0;
    Powers powers;  ///< [W] by source, the prescribed drives' included
    /// [rad/s] the rate of each coordinate of the shape state (free hinges, then modal).
    Eigen::VectorXd coordinate_rates;
  };
  Snapshot Snap(double t,
                const math::Vec3& H_B,
                const Eigen::VectorXd& x,
                dynamics::Side side = dynamics::Side::kRight) const;

  /// dJ_B/dt [kg m^2/s] at the state (the moving hinges' rates; merged panels move with
  /// their parents, so this costs the computed panels only).
  math::Mat3 InertiaRate(double t,
                         const math::Vec3& H_B,
                         const Eigen::VectorXd& x,
                         dynamics::Side side = dynamics::Side::kRight) const;

  /// The shape state for the current free set from the hub momentum and every hinge's
  /// angle and rate (theta_f, p_f = (Bm^T w + M theta')_f with w solved from H_B): used
  /// after Free() (a released hinge starts with theta' = 0) and to start a run.
  Eigen::VectorXd ShapeState(double t,
                             const math::Vec3& H_B,
                             const Eigen::VectorXd& theta,
                             const Eigen::VectorXd& theta_dot,
                             dynamics::Side side = dynamics::Side::kRight) const;

  /// The impulse at free hinge free_hinges()[a] that sets its rate to `rate_after`
  /// (docs/design.md 2.7: only p_k changes, by lambda = (rate_after - rate_before) /
  /// (M^-1)_kk with M over the unknowns (w, theta'_f)). Updates x.
  struct Impulse {
    double lambda = 0.0;                         ///< [N m s]
    double rate_before = 0.0, rate_after = 0.0;  ///< [rad/s]
    math::Vec3 w_jump_B = math::Vec3::Zero();    ///< [rad/s]
    double energy_dissipated = 0.0;              ///< [J] -(work of the impulse)
    /// [J] work of the impulses the drives of the moving prescribed hinges exert to keep
    /// their rates: the kinetic energy jumps by drive_work - energy_dissipated.
    double drive_work = 0.0;
  };
  Impulse ApplyImpulse(
      double t, const math::Vec3& H_B, Eigen::VectorXd& x, int a, double rate_after) const;

  /// (M^-1)_aa [1 / (kg m^2)] over the unknowns (w, theta'_f) at the state: the rate change of
  /// free hinge free_hinges()[a] per unit impulse on it.
  double InverseMass(double t, const math::Vec3& H_B, const Eigen::VectorXd& x, int a) const;

  /// The torque [N m] that holds locked hinge k (a kFree plan, not free now: resting on a
  /// stop or stuck by friction) at rest at the state (t, H_B, x) of the current free set:
  /// lambda = -theta''_k / (M^-1)_kk, theta''_k the acceleration hinge k would have if it
  /// were free at rate 0 without friction (docs/design.md 2.7). A stop on the max side
  /// holds it while lambda <= 0, on the min side while lambda >= 0; friction while
  /// |lambda| <= its torque. theta''_k is the central difference of the rate along the flow
  /// of the system with k free over +-kHoldingStep (exact for the motion's quadratic part;
  /// its rounding error, ~1e-16 |v| / kHoldingStep in rad/s^2, is far below the resolution
  /// any stop or friction decision needs).
  double HoldingTorque(int k, double t, const math::Vec3& H_B, const Eigen::VectorXd& x) const;
  /// theta''_k [rad/s^2] of free hinge free_hinges()[a] at the state (x: theta_f, p_f, then
  /// ledger terms or not), the central difference of its rate along the flow over
  /// +-kHoldingStep (see HoldingTorque).
  double Acceleration(int a, double t, const math::Vec3& H_B, const Eigen::VectorXd& x) const;
  static constexpr double kHoldingStep = 1e-6;  ///< [s]

  /// The direction (+1, -1) free hinge k slips in: its exact Coulomb friction is -torque
  /// times it (hinge_motion.h DriveTorque); 0: none (at rest).
  void SetSlip(int k, int direction) { slip_[static_cast<std::size_t>(Computed(k))] = direction; }
  int slip(int k) const { return slip_[static_cast<std::size_t>(Computed(k))]; }

 private:
  struct Merged;
  FreeHingeSystem(Merged merged,
                  const Eigen::VectorXd& full_angles,
                  const std::vector<ModalGroup>& modal);
  static Merged MergeLockedLeaves(const model::HingedBody& body,
                                  const std::vector<HingePlan>& plans,
                                  const Eigen::VectorXd& angles);
  /// The computed panel of model panel k (throws std::logic_error for a merged one: it is
  /// locked for the whole run).
  int Computed(int k) const;
  void LockComputed(int r, double angle);
  void FreeComputed(int r);
  /// Every model panel's angles (rates) from the computed panels' (merged: locked).
  Eigen::VectorXd Expand(const Eigen::VectorXd& computed, bool rates) const;
  /// Column a of the inverse of M over the unknowns (w, theta'_f): the response of the
  /// unknowns to a unit jump of p_a (after Setup and Solve at the state: theta_dot_ holds).
  Eigen::VectorXd ImpulseResponse(double t,
                                  const math::Vec3& H_B,
                                  const Eigen::VectorXd& x,
                                  int a) const;
  /// theta and the known rates at t; cols_ = free then moving prescribed.
  void Setup(double t, const Eigen::VectorXd& x, dynamics::Side side) const;
  /// Mass matrix over cols_ and the solve for (w, theta'_f) into w_, theta_dot_.
  void Solve(const math::Vec3& H_B, const Eigen::VectorXd& x) const;
  /// M_ over cols_ at pose_ (kept while neither the angles nor cols_ change).
  void UpdateMassMatrix() const;
  /// The Powers at the state of the last Setup and Solve (x: its theta_f, p_f).
  Powers PowersNow(double t,
                   dynamics::Side side,
                   const math::Vec3& H_B,
                   const Eigen::VectorXd& x) const;
  /// The prescribed drives' power: dT/dt at fixed (H_B, p_f), after Setup and Solve.
  double DrivePower(double t,
                    dynamics::Side side,
                    const math::Vec3& H_B,
                    const Eigen::VectorXd& x) const;

  /// The coordinates' rates (free hinges' theta', then q') from the last Solve.
  Eigen::VectorXd CoordinateRates() const;
  /// The generalized forces on the coordinates at the state of the last Setup and Solve:
  /// free hinges' drive torques, then basis^T (the modal hinges' spring and damper).
  Eigen::VectorXd CoordinateForces(double t, dynamics::Side side, const Eigen::VectorXd& x) const;
  /// Gradient dT/d(coordinates) from the hinges' gradient over (free_, modal_, extra...):
  /// the modal block projected by basis^T, the rest as is.
  Eigen::VectorXd ProjectGradient(const Eigen::VectorXd& g_hinges) const;
  /// Hinge rates over tree_ from coordinate velocities z = (w, coordinates, ...): free
  /// hinges z[3 + a], modal hinges basis z.segment(3 + mh, K).
  void HingeRatesOf(const Eigen::VectorXd& z, Eigen::VectorXd& rates) const;

  model::HingedBody body_;
  model::PanelTree tree_;
  // Modal coordinates: the groups, their hinges (computed indices and model indices), the
  // block-diagonal basis (rows: modal_, columns: q) and the hinges' angles at q = 0.
  std::vector<ModalGroup> groups_;
  std::vector<int> modal_, modal_orig_;
  std::vector<char> is_modal_;  // per computed panel
  Eigen::MatrixXd phi_;
  Eigen::VectorXd modal_theta0_;
  mutable Eigen::MatrixXd speeds_;  // the coordinates as directions of (w, every hinge)
  mutable std::vector<model::TreeVelocity> fields_;
  mutable Eigen::VectorXd q_dot_;
  std::vector<HingePlan> plans_;
  std::vector<PrescribedHinge> prescribed_;  // per panel (empty moves unless prescribed)
  std::vector<PrescribedHinge> servo_ref_;   // per panel: a servo motor's planned motion
  // The model's panels and the computed ones (the constructor's comment).
  std::vector<int> red_of_;      // per model panel: its computed panel, -1 if merged
  std::vector<int> orig_of_;     // per computed panel: its model panel
  Eigen::VectorXd full_angles_;  // every model panel's initial angle
  std::vector<int> free_;        // computed indices
  std::vector<int> free_orig_;   // the same, model indices
  std::vector<char> is_free_;
  std::vector<int> slip_;  // per hinge: SetSlip
  // HoldingTorque's system: this one with the held hinge probe_k_ free (rebuilt when the
  // free set or the hinge changes).
  mutable std::shared_ptr<FreeHingeSystem> probe_;
  mutable int probe_k_ = -1;
  mutable std::vector<int> probe_free_;
  Eigen::VectorXd angles_;  // locked angles (every hinge; free/prescribed: last known)

  // Scratch.
  mutable model::TreePose pose_;
  mutable model::TreeVelocity vel_;
  mutable Eigen::VectorXd theta_, theta_dot_;
  mutable std::vector<int> cols_, moving_;
  mutable Eigen::MatrixXd M_, A_;
  mutable Eigen::VectorXd rhs_, sol_, grad_, rates_;
  mutable model::TreeVelocity drive_vel_;
  mutable Eigen::VectorXd drive_rates_, drive_gx_, drive_gy_;
  // What pose_, M_ and the last inertia sample were computed from: while every hinge is
  // locked (or at rest) the outputs and events of a rigid phase ask for the same
  // configuration again and again, and the tree's kinematics need not be redone. Keyed
  // on the exact values, so a Lock(), Free() or a moving hinge is seen without a signal.
  mutable Eigen::VectorXd pose_theta_;
  mutable bool pose_valid_ = false;
  mutable std::vector<int> mass_cols_;
  mutable bool mass_valid_ = false;
  mutable Eigen::VectorXd sample_theta_, sample_theta_dot_;
  mutable bool sample_valid_ = false;
  mutable dynamics::InertiaSample sample_;
  mutable math::Vec3 w_ = math::Vec3::Zero();
  /// The drive's generalized force on free hinge k at time t (DriveTorque + ServoTorque).
  double Torque(int k, double t, dynamics::Side side, double theta, double theta_dot) const;
};

}  // namespace deploysim::schedule
