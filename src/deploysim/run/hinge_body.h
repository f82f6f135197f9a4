#pragma once

/// The body of a hinge profile for the run loop (run_loop.h, docs/design.md 2.7): the hub
/// with its hinges, each locked, prescribed or free, and the discrete changes between
/// them — a release, a latch, a jam, a stop impact, a panel coming to rest, a lift-off or
/// slip of a held hinge. With hinges free, its free segment (integrators::IntegrateShape:
/// Lie-group RKMK on SO(3) x R^2m) advances (R_NB, theta_f, p_f) to the first located
/// event; at an event the impulse of docs/design.md 2.7 changes only p_k (H_B and every
/// other p_j unchanged) and the event is reported with its impulse, the hub's
/// angular-velocity jump and the energy dissipated. With none free, the loop's rigid path
/// runs on the FreeHingeSystem as the inertia source. The phases are those between these
/// changes and the prescribed windows.

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "deploysim/integrators/shape_integrate.h"
#include "deploysim/model/model.h"
#include "deploysim/run/run_loop.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::run {

class HingeBody final : public RunBody {
 public:
  /// `run`: a compiled hinge profile (schedule::Profile::is_hinge_profile()).
  HingeBody(const CompiledRun& run, const RunOptions& options);

  const dynamics::InertiaSource& source() const override { return sys_; }
  void Start(RunState& st) override;
  RunSample SampleOf(double t,
                     const math::Vec3& H_B,
                     const math::Quat& q_NB,
                     const Eigen::VectorXd& x,
                     dynamics::Side side) const override;
  std::vector<double> PhaseBoundaries(double /*t0*/, double /*t1*/) const override {
    return windows_;
  }
  PhaseInfo Describe(double t) const override;
  analysis::SteadySpin Steady(const RunSample& start, const PhaseInfo& info) const override;
  bool ChangesDue(RunState& st, bool started) override;
  bool FreeMotion() const override { return sys_.free_count() > 0 || AnyHeld(); }
  double NextChange(double t, double t1) const override;
  double NextFreeChange(double t, double t1) const override;
  SegmentEnd FreeSegment(RunState& st, double t_next) override;

 private:
  /// What a located event of a free segment is.
  struct EventTag {
    enum class What { kHinge, kFlip, kCross45, kSeparatrix };
    What what = What::kFlip;
    HingeEvent::Kind kind = HingeEvent::Kind::kLatch;  ///< kHinge: latch, jam or stop.
    int a = 0;                                         ///< kHinge: index in the free set.
    double angle = 0.0;                                ///< kHinge: the event's angle [rad].
    double restitution = 0.0;                          ///< kHinge: stops.
    int side = 0;    ///< kHinge, stops: +1 the max stop, -1 the min stop.
    int panel = -1;  ///< kHinge, lift-off and slip: the held hinge (not free: a is unused).
  };
  /// How a free hinge that is not moving is held, until the torque that holds it (the
  /// FreeHingeSystem's HoldingTorque) exceeds what holds it.
  struct Hold {
    enum class Kind { kNone, kStop, kStick };
    Kind kind = Kind::kNone;
    int side = 0;  ///< kStop: +1 on the max stop, -1 on the min stop.
    /// [N m] the margin by which the holding torque must exceed what holds the hinge
    /// before it moves: 1e-9 of the torques at the hold's start, so that at the located
    /// release the hinge's net acceleration points away (a release located a rounding
    /// error early would find it pressed back at once). Ten times more at each repeat at
    /// one instant.
    double offset = 0.0;
  };

  /// The body of the (validated) profile, its hinge axes normalized.
  static model::HingedBody BodyOf(const schedule::Profile& profile, const std::string& where);
  /// The state at the current time, with the work done so far.
  RunSample Current(dynamics::Side side) const;
  void OpenPhase(const RunSample& start) { RunBody::OpenPhase(*st_, start); }
  /// [s] the time a hinge held at a steady rate (a motor-held rotor) turns once at t; 0
  /// if none turns (the fastest if several).
  double RotorPeriod(double t) const;
  /// The free hinges (free order) that can turn without bound: free rotors (no spring,
  /// stops, latch, damper, friction or motor).
  std::vector<int> WindingHinges() const;
  /// Their axes in B: a panel's on the hub, NaN for a deeper one (its axis moves).
  std::vector<math::Vec3> WindingAxes() const;
  void FreeEvents(std::vector<integrators::ShapeEventFunction>& events,
                  std::vector<EventTag>& tags) const;
  /// The spin-axis events of a free segment: flips, 45-degree crossings, the separatrix.
  void SpinAxisEvents(std::vector<integrators::ShapeEventFunction>& events,
                      std::vector<EventTag>& tags) const;
  /// The energy projection of a free segment's step end y (see FreeSegment), for a
  /// segment that started at energy e_start.
  void Project(integrators::ShapeState& y, double e_start) const;
  void OnHingeEvent(const EventTag& tag, bool stuck);
  /// A stop impact of free hinge tag.a at t with rebound rate `rebound`: true when the
  /// panel rests on the stop instead (schedule::Stops, kContactTime).
  bool RestsOnStop(const EventTag& tag, double rebound);
  /// Exact Coulomb friction brought free hinge tag.a's rate to 0: it sticks (true) or,
  /// when friction cannot hold it, slips on the way its torque pulls (false; x changed).
  bool Sticks(const EventTag& tag, bool stuck);
  /// Held hinge k leaves its hold (a lift-off or a slip): freed at rate 0.
  void Unhold(int k, HingeEvent::Kind kind);
  /// Free hinge k (just freed at rest, friction Coulomb): slips the way the holding torque
  /// pulls, or sticks when friction holds it (true).
  bool StartSlip(int k, double lambda);
  /// How far the torque holding hinge k is past what holds it (> 0: it moves).
  double HoldMargin(int k, double t, const math::Vec3& H_B, const Eigen::VectorXd& x) const;
  bool AnyHeld() const;
  /// Appends the event of `kind` on panel k at the current time (with the impulse's
  /// numbers, if any).
  void Record(HingeEvent::Kind kind,
              int k,
              double angle,
              const schedule::FreeHingeSystem::Impulse* imp = nullptr);
  /// Holds locked hinge k (a rest on a stop: side +-1; friction: 0) from now.
  void StartHold(int k, Hold::Kind kind, int side);
  /// Hinge events at one instant: a run whose events repeat at one time without end stops.
  void CountInstant();
  double Cos(const math::Vec3& H_B) const { return st_->s.dot(H_B) / H_B.norm(); }
  const schedule::FreeHingeSystem::Snapshot& SnapOf(const integrators::ShapeState& y) const;
  math::Mat3 JdotOf(const integrators::ShapeState& y) const;

  const schedule::Profile& profile_;
  const std::string where_;
  const model::HingedBody body_;
  const int n_;
  const std::vector<schedule::HingePlan>& plans_;
  const RunOptions& options_;
  const double t0_, t1_;
  schedule::FreeHingeSystem sys_;
  const Eigen::VectorXd plans_rate0_;  // initial.hinge_rates (empty: all at rest)
  RunState* st_ = nullptr;             // the run's state (Start)
  // The last shape state the event functions and their rates asked about (several ask
  // about each step's end): its snapshot and, once asked for, dJ_B/dt.
  mutable integrators::ShapeState memo_state_;
  mutable schedule::FreeHingeSystem::Snapshot memo_snap_;
  mutable bool memo_valid_ = false, memo_jdot_valid_ = false;
  mutable math::Mat3 memo_jdot_ = math::Mat3::Zero();
  std::vector<double> release_time_, release_angle_;
  std::vector<char> done_;  // released and locked again for good (latched, jammed)
  std::vector<Hold> hold_;  // held by a stop or by friction until pulled away
  std::vector<double> unheld_t_, unheld_offset_;  // the last release from a hold, its offset
  std::vector<double> last_impact_;               // the time of each hinge's last stop impact
  double instant_t_ = -std::numeric_limits<double>::infinity();
  int instant_events_ = 0;
  std::vector<double> windows_;  // prescribed window boundaries: phase boundaries
  std::string shape_method_;
  bool project_energy_ = false;  // FreeSegment's energy projection (see there)
};

}  // namespace deploysim::run
