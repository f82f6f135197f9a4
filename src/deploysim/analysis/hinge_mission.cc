// RunHingeMission: the hybrid run of a hinge profile (docs/design.md 2.7).
//
// The run is cut into segments at every time the system changes: a release, a latch, a
// jam, a stop impact, a panel coming to rest, a prescribed window's start or end. Between
// them the hinges are each locked, prescribed or free:
//   - with free hinges, integrators::IntegrateShape (Lie-group RKMK on SO(3) x R^2m)
//     advances (R_NB, theta_f, p_f), stopping at the first located latch, jam or stop;
//   - with none, the body is a hub with locked and prescribed hinges: the rigid-body
//     path (integrators::Integrate with the FreeHingeSystem as the inertia source), so
//     `exact` uses the closed form wherever nothing moves.
// At an event the impulse of docs/design.md 2.7 changes only p_k (H_B and every other
// p_j unchanged); the event is reported with its impulse, the hub's angular-velocity jump
// and the energy dissipated. The stage table is made of the phases between these changes.
// Samples, flips, 45-degree crossings, the spin-axis extrema and the phases go to the
// RunRecorder.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/analysis/run_recorder.h"
#include "deploysim/analysis/work_estimate.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/shape_integrate.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::analysis {

namespace {

using math::Mat3;
using math::Vec3;
using schedule::FreeHingeSystem;
using schedule::HingePlan;

/// The energy in the springs of every hinge with a free plan at angles theta.
double SpringEnergyAll(const std::vector<HingePlan>& plans, const Eigen::VectorXd& theta) {
  double v = 0.0;
  for (std::size_t k = 0; k < plans.size(); ++k) {
    if (plans[k].kind == HingePlan::Kind::kFree) {
      v += schedule::SpringEnergy(plans[k].drive, theta[static_cast<Eigen::Index>(k)]);
    }
  }
  return v;
}

bool Dissipates(const schedule::FreeDrive& d) { return d.damping > 0.0 || d.friction.torque > 0.0; }

/// Hinge events at one instant beyond which a run stops with an error instead of looping
/// (a hold released and taken again at once; each repeat raises the hold's margin tenfold,
/// so a few suffice).
constexpr int kMaxEventsAtOneInstant = 1000;

/// [rad/s] How far past 0 a slipping hinge's rate goes before its slip ends (then an
/// impulse sets it to 0 exactly): above the rounding error of a rate (~1e-16 of the
/// state's rates), far below what any tolerance resolves (kinetic energy ~1e-24 J).
constexpr double kSlipEndRate = 1e-12;

/// The hinges' swing [rad] (stiffest rate times the run's length, analysis::EstimateWork)
/// beyond which the free segments project their energy (FreeSegment): 1600 periods. Below
/// it the steps' energy errors add up to less than the tolerance asks (every shipped
/// profile, the longest 7000 rad).
constexpr double kProjectionRadians = 1e4;
/// The longest move of the energy projection, in tolerances of the state (FreeSegment).
constexpr double kProjectionReach = 4.0;

/// What a located event of a segment is.
struct EventTag {
  enum class What { kHinge, kFlip, kCross45, kSeparatrix, kExtremum };
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
  /// [N m] the margin by which the holding torque must exceed what holds the hinge before
  /// it moves: 1e-9 of the torques at the hold's start, so that at the located release the
  /// hinge's net acceleration points away (a release located a rounding error early would
  /// find it pressed back at once). Ten times more at each repeat at one instant.
  double offset = 0.0;
};

/// How a segment ended.
enum class SegmentEnd { kReached, kHingeEvent, kStopped };

/// The state at t0: InitialState, plus, when the profile gives the hub's angular velocity,
/// the momentum of the hinges it starts moving (H_B = J w + B theta', linear in the rates).
integrators::State HingeInitialState(const schedule::Profile& profile,
                                     const FreeHingeSystem& sys,
                                     const model::HingedBody& body) {
  integrators::State y = InitialState(profile, sys);
  const Eigen::VectorXd& rate0 = profile.initial.hinge_rates;
  if (profile.initial.w_NB_B && rate0.size() > 0) {
    const Eigen::VectorXd& theta0 =
        profile.model.configuration(profile.initial.configuration).hinge_angles;
    y.H_B += model::ComputeMassProperties(body, theta0, rate0).h_rel_B;
  }
  return y;
}

class HingeRun {
 public:
  HingeRun(const CompiledRun& run,
           SampleSink* sink,
           const std::function<void(double)>& progress,
           const RunOptions& options);
  MissionResult Run();

 private:
  /// The body of the (validated) profile, its hinge axes normalized.
  static model::HingedBody BodyOf(const schedule::Profile& profile, const std::string& where);
  RunSample SampleOf(double t,
                     const Vec3& H_B,
                     const math::Quat& q_NB,
                     const Eigen::VectorXd& x,
                     dynamics::Side side) const;
  RunSample Current(dynamics::Side side) const { return SampleOf(t_, y_.H_B, y_.q_NB, x_, side); }
  PhaseInfo Describe(double t) const;
  /// Opens a phase at the current time from `start`, with the linear stability of its
  /// steady spin (linear_stability.h) found from there.
  void OpenPhase(const RunSample& start);
  bool ReleasesDue();
  double NextChange() const;
  /// [s] the time a hinge held at a steady rate (a motor-held rotor) turns once at t; 0
  /// if none turns (the fastest if several).
  double RotorPeriod(double t) const;
  /// The free hinges (free order) that can turn without bound: free rotors (no spring,
  /// stops, latch, damper, friction or motor).
  std::vector<int> WindingHinges() const;
  /// Their axes in B: a panel's on the hub, NaN for a deeper one (its axis moves).
  std::vector<math::Vec3> WindingAxes() const;
  SegmentEnd FreeSegment(double t_next);
  SegmentEnd RigidSegment(double t_next);
  void FreeEvents(std::vector<integrators::ShapeEventFunction>& events,
                  std::vector<EventTag>& tags) const;
  void OnHingeEvent(const EventTag& tag, bool stuck);
  /// A stop impact of free hinge tag.a at t_ with rebound rate `rebound`: true when the
  /// panel rests on the stop instead (schedule::Stops, kContactTime).
  bool RestsOnStop(const EventTag& tag, double rebound);
  /// Exact Coulomb friction brought free hinge tag.a's rate to 0: it sticks (true) or,
  /// when friction cannot hold it, slips on the way its torque pulls (false; x_ changed).
  bool Sticks(const EventTag& tag, bool stuck);
  /// Held hinge k leaves its hold (a lift-off or a slip): freed at rate 0.
  void Unhold(int k, HingeEvent::Kind kind);
  /// Free hinge k (just freed at rest, friction Coulomb): slips the way the holding torque
  /// pulls, or sticks when friction holds it (true).
  bool StartSlip(int k, double lambda);
  /// How far the torque holding hinge k is past what holds it (> 0: it moves).
  double HoldMargin(int k, double t, const Vec3& H_B, const Eigen::VectorXd& x) const;
  bool AnyHeld() const;
  /// Appends the event of `kind` on panel k at t_ (with the impulse's numbers, if any).
  void Record(HingeEvent::Kind kind,
              int k,
              double angle,
              const FreeHingeSystem::Impulse* imp = nullptr);
  /// Holds locked hinge k (a rest on a stop: side +-1; friction: 0) from now.
  void StartHold(int k, Hold::Kind kind, int side);
  /// Hinge events at one instant: a run whose events repeat at one time without end stops.
  void CountInstant();
  void AddStats(const integrators::Statistics& s);
  bool Stopped(integrators::Termination t, const std::string& message);
  double Cos(const Vec3& H_B) const { return s_.dot(H_B) / H_B.norm(); }
  const FreeHingeSystem::Snapshot& SnapOf(const integrators::ShapeState& y) const;
  Mat3 JdotOf(const integrators::ShapeState& y) const;

  const schedule::Profile& profile_;
  const std::string where_;
  const model::HingedBody body_;
  const int n_;
  const std::vector<HingePlan>& plans_;
  const RunOptions& options_;
  const double t0_, t1_;
  FreeHingeSystem sys_;
  const Eigen::VectorXd plans_rate0_;  // initial.hinge_rates (empty: all at rest)
  integrators::State y_;               // H_B, q_NB at t_
  WorkLedger work_;                    // the work done on the system from t0 to t_
  // The last shape state the event functions and their rates asked about (several ask
  // about each step's end): its snapshot and, once asked for, dJ_B/dt.
  mutable integrators::ShapeState memo_state_;
  mutable FreeHingeSystem::Snapshot memo_snap_;
  mutable bool memo_valid_ = false, memo_jdot_valid_ = false;
  mutable Mat3 memo_jdot_ = Mat3::Zero();
  Eigen::VectorXd x_;  // shape state of the free set
  double t_;
  Vec3 s_;
  double M_;  // |h_N(t0)|
  RunRecorder rec_;
  std::vector<double> release_time_, release_angle_;
  std::vector<char> done_;  // released and locked again for good (latched, jammed)
  std::vector<Hold> hold_;  // held by a stop or by friction until pulled away
  std::vector<double> unheld_t_, unheld_offset_;  // the last release from a hold, its offset
  std::vector<double> last_impact_;               // the time of each hinge's last stop impact
  double instant_t_ = -std::numeric_limits<double>::infinity();
  int instant_events_ = 0;
  std::vector<double> windows_;  // prescribed window boundaries: phase boundaries
  integrators::IntegratorSettings settings_;
  std::string shape_method_;
  std::unique_ptr<integrators::Stepper> rigid_stepper_;
  bool started_ = false;         // the first phase is open
  bool project_energy_ = false;  // FreeSegment's energy projection (see there)
  const integrators::UniformGridTimes full_grid_;
  const WindowTimes grid_;
  std::size_t next_out_ = 0;
  integrators::Statistics stats_;
  integrators::Termination termination_ = integrators::Termination::kReachedEnd;
  std::string message_;
  MissionResult out_;
};

model::HingedBody HingeRun::BodyOf(const schedule::Profile& profile, const std::string& where) {
  const model::Model& model = profile.model;
  if (model.kind != model::ModelKind::kHinged) {
    throw std::invalid_argument(where + ": hinges: the model is not a hinged model");
  }
  return model::ValidatedHingedBody(model.hinged,
                                    model.source.empty() ? where + ": model" : model.source);
}

HingeRun::HingeRun(const CompiledRun& run,
                   SampleSink* sink,
                   const std::function<void(double)>& progress,
                   const RunOptions& options)
    : profile_(run.profile()),
      where_(profile_.source.empty() ? profile_.name : profile_.source),
      body_(BodyOf(profile_, where_)),
      n_(static_cast<int>(body_.panels.size())),
      plans_(profile_.hinges),
      options_(options),
      t0_(profile_.t_begin()),
      t1_(profile_.t_end()),
      sys_(body_,
           plans_,
           profile_.model.configuration(profile_.initial.configuration).hinge_angles,
           schedule::ModalGroupsOf(profile_.model)),
      plans_rate0_(profile_.initial.hinge_rates),
      y_(HingeInitialState(profile_, sys_, body_)),
      t_(t0_),
      s_(options.spin_axis_B ? *options.spin_axis_B
                             : InitialSpinAxis(sys_.Evaluate(t0_).J_B, y_.H_B)),
      M_((y_.q_NB * y_.H_B).norm()),
      rec_(s_, y_.q_NB * y_.H_B, sink, progress, t0_, t1_),
      release_time_(static_cast<std::size_t>(n_), std::numeric_limits<double>::infinity()),
      done_(static_cast<std::size_t>(n_), 0),
      hold_(static_cast<std::size_t>(n_)),
      unheld_t_(static_cast<std::size_t>(n_), std::numeric_limits<double>::quiet_NaN()),
      unheld_offset_(static_cast<std::size_t>(n_), 0.0),
      last_impact_(static_cast<std::size_t>(n_), -std::numeric_limits<double>::infinity()),
      windows_(sys_.Breakpoints(t0_, t1_)),
      settings_(run.settings()),
      full_grid_(t0_, t1_, profile_.output.dt),
      grid_(full_grid_, 0, sink != nullptr ? full_grid_.size() : 0),
      message_(integrators::ToString(termination_)) {
  const std::string& method = profile_.integrator.method;
  shape_method_ = NumericalMethodOf(method);
  rigid_stepper_ = MakeStepper(method);
  // Releases: time-based ones now; after-latch ones when their latch happens. Every free
  // hinge is at rest (held) until its release.
  const Eigen::VectorXd theta0 =
      profile_.model.configuration(profile_.initial.configuration).hinge_angles;
  release_angle_.assign(theta0.data(), theta0.data() + n_);
  for (int k = 0; k < n_; ++k) {
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind != HingePlan::Kind::kFree) continue;
    if (p.drive.release.kind == schedule::Release::Kind::kAtStart) {
      release_time_[static_cast<std::size_t>(k)] = t0_;
    } else if (p.drive.release.kind == schedule::Release::Kind::kAtTime) {
      release_time_[static_cast<std::size_t>(k)] = std::max(t0_, p.drive.release.time);
    }
  }
  // Modal coordinates are in the shape state from the start: the appendages at their
  // angles, at the hinges' initial rates.
  if (sys_.modal_count() > 0) {
    const Eigen::VectorXd rates0 =
        plans_rate0_.size() > 0 ? plans_rate0_ : Eigen::VectorXd::Zero(theta0.size());
    x_ = sys_.ShapeState(t0_, y_.H_B, theta0, rates0);
  }
  // The stiffest hinge rate times the run's length: the radians its swing can cover.
  project_energy_ =
      profile_.has_free_hinge() && run.work().hinge_rate * (t1_ - t0_) > kProjectionRadians;
  out_.run = run.handle();
  out_.spin_axis_B = s_;
  out_.latch_times.assign(static_cast<std::size_t>(n_), std::numeric_limits<double>::quiet_NaN());
  rec_.SpinAxisCos(s_.dot(y_.H_B) / M_);
}

// A state of the free-hinge path (shape state x), or of the rigid path (no hinge free:
// x empty).
RunSample HingeRun::SampleOf(double t,
                             const Vec3& H_B,
                             const math::Quat& q_NB,
                             const Eigen::VectorXd& x,
                             dynamics::Side side) const {
  const FreeHingeSystem::Snapshot snap = sys_.Snap(t, H_B, x, side);
  RunSample o;
  o.t = t;
  o.H_B = H_B;
  o.q_NB = q_NB;
  o.w = snap.w_NB_B;
  o.J_B = snap.J_B;
  o.h_rel_B = snap.h_rel_B;
  o.kinetic = snap.kinetic_energy;
  o.theta = snap.theta;
  o.theta_dot = snap.theta_dot;
  o.spring = SpringEnergyAll(plans_, snap.theta);
  o.work = work_;
  return o;
}

PhaseInfo HingeRun::Describe(double t) const {
  PhaseInfo ph;
  std::string free_list, moving;
  auto name = [this](int k) { return body_.panels[static_cast<std::size_t>(k)].name; };
  for (int k : sys_.free_hinges()) {
    free_list += (free_list.empty() ? "" : ", ") + name(k);
    ph.dissipative = ph.dissipative || Dissipates(plans_[static_cast<std::size_t>(k)].drive);
  }
  for (const schedule::ModalGroup& g : sys_.modal_groups()) {
    free_list += (free_list.empty() ? "" : ", ") + g.name + " (" + std::to_string(g.basis.cols()) +
                 " modes)";
    for (int k : g.hinges) {
      ph.dissipative = ph.dissipative || Dissipates(plans_[static_cast<std::size_t>(k)].drive);
    }
  }
  for (int k = 0; k < n_; ++k) {
    const HingePlan& p = plans_[static_cast<std::size_t>(k)];
    if (p.kind != HingePlan::Kind::kPrescribed) continue;
    for (const schedule::HingeMove& mv : p.moves) {
      if (mv.t_begin <= t && t < mv.t_end) {
        moving += (moving.empty() ? "" : ", ") + name(k);
        break;
      }
    }
  }
  ph.rotor = !WindingHinges().empty() || RotorPeriod(t) > 0.0;
  if (!free_list.empty()) {
    ph.name = "free: " + free_list + (moving.empty() ? "" : "; moved: " + moving);
    ph.law = "free";
  } else if (!moving.empty()) {
    ph.name = "moved: " + moving;
    ph.law = "prescribed";
  } else {
    ph.name = "locked";
    ph.law = "hold";
    ph.rigid = true;
  }
  return ph;
}

// Frees the hinges whose release time has come (each at rest); true if any was. The
// first release closes the open phase.
bool HingeRun::ReleasesDue() {
  bool changed = false;
  for (int k = 0; k < n_; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    if (!(release_time_[i] <= t_) || sys_.IsFree(k) || done_[i]) continue;
    const RunSample before = Current(dynamics::Side::kRight);
    if (!changed && started_) rec_.ClosePhase(before);
    changed = true;
    // A hinge the profile starts moving (initial.hinge_rates) is released at t0 with it.
    const Eigen::VectorXd& rate0 = plans_rate0_;
    const double rate = t_ == t0_ && rate0.size() > 0 ? rate0[k] : 0.0;
    const bool coulomb = schedule::IsCoulomb(plans_[i].drive.friction);
    const double lambda = coulomb && rate == 0.0 ? sys_.HoldingTorque(k, t_, y_.H_B, x_) : 0.0;
    x_ = sys_.Free(k, t_, y_.H_B, x_, rate);
    release_angle_[i] = before.theta[k];
    release_time_[i] = std::numeric_limits<double>::infinity();
    Record(HingeEvent::Kind::kRelease, k, before.theta[k]);
    if (coulomb) {
      if (rate != 0.0) {
        sys_.SetSlip(k, rate > 0.0 ? 1 : -1);
      } else {
        StartSlip(k, lambda);
      }
    }
  }
  return changed;
}

bool HingeRun::StartSlip(int k, double lambda) {
  const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  if (std::abs(lambda) > d.friction.torque) {
    sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
    return false;
  }
  // Friction holds it where it was released.
  const double angle = Current(dynamics::Side::kRight).theta[k];
  x_ = sys_.Lock(k, angle, x_);
  StartHold(k, Hold::Kind::kStick, 0);
  Record(HingeEvent::Kind::kStick, k, angle);
  return true;
}

void HingeRun::StartHold(int k, Hold::Kind kind, int side) {
  const std::size_t i = static_cast<std::size_t>(k);
  const schedule::Friction& f = plans_[i].drive.friction;
  const double mu = schedule::IsCoulomb(f) ? f.torque : 0.0;
  Hold h;
  h.kind = kind;
  h.side = side;
  h.offset = 1e-9 * (mu + std::abs(sys_.HoldingTorque(k, t_, y_.H_B, x_)));
  if (unheld_t_[i] == t_) h.offset = std::max(h.offset, 10.0 * unheld_offset_[i]);
  hold_[i] = h;
}

void HingeRun::Record(HingeEvent::Kind kind,
                      int k,
                      double angle,
                      const FreeHingeSystem::Impulse* imp) {
  HingeEvent ev;
  ev.kind = kind;
  ev.t = t_;
  ev.panel = k;
  ev.angle = angle;
  if (imp != nullptr) {
    ev.rate_before = imp->rate_before;
    ev.rate_after = imp->rate_after;
    ev.impulse = imp->lambda;
    ev.w_jump_B = imp->w_jump_B;
    ev.energy_dissipated = imp->energy_dissipated;
    ev.drive_work = imp->drive_work;
  }
  out_.hinge_events.push_back(ev);
}

bool HingeRun::AnyHeld() const {
  for (const Hold& h : hold_) {
    if (h.kind != Hold::Kind::kNone) return true;
  }
  return false;
}

double HingeRun::HoldMargin(int k, double t, const Vec3& H_B, const Eigen::VectorXd& x) const {
  const Hold& h = hold_[static_cast<std::size_t>(k)];
  const schedule::Friction& f = plans_[static_cast<std::size_t>(k)].drive.friction;
  const double mu = schedule::IsCoulomb(f) ? f.torque : 0.0;
  const double lambda = sys_.HoldingTorque(k, t, H_B, x);
  // A stop holds one way (the max stop with lambda <= 0), friction both ways up to mu.
  const double need = h.kind == Hold::Kind::kStop ? h.side * lambda : std::abs(lambda);
  return need - mu - h.offset;
}

void HingeRun::CountInstant() {
  if (t_ != instant_t_) {
    instant_t_ = t_;
    instant_events_ = 0;
  }
  if (++instant_events_ > kMaxEventsAtOneInstant) {
    throw std::runtime_error(where_ +
                             ": hinge events repeat without end at t = " + math::FormatNumber(t_) +
                             " s (" + std::to_string(kMaxEventsAtOneInstant) +
                             " at one instant): the run cannot advance (please report it with "
                             "the profile)");
  }
}

void HingeRun::Unhold(int k, HingeEvent::Kind kind) {
  const std::size_t i = static_cast<std::size_t>(k);
  const RunSample before = Current(dynamics::Side::kRight);
  const double lambda = sys_.HoldingTorque(k, t_, y_.H_B, x_);
  rec_.ClosePhase(before);
  Record(kind, k, before.theta[k]);
  unheld_t_[i] = t_;
  unheld_offset_[i] = hold_[i].offset;
  hold_[i] = Hold();
  x_ = sys_.Free(k, t_, y_.H_B, x_, 0.0);
  if (schedule::IsCoulomb(plans_[i].drive.friction)) sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
  OpenPhase(Current(dynamics::Side::kRight));
}

// The segment's end: the next release, prescribed window boundary, or t1.
double HingeRun::NextChange() const {
  double t_next = t1_;
  for (double r : release_time_) {
    if (r > t_) t_next = std::min(t_next, r);
  }
  // windows_ ascends: the first boundary after t_ (a rotor may have 10^4 windows).
  const auto w = std::upper_bound(windows_.begin(), windows_.end(), t_);
  if (w != windows_.end()) t_next = std::min(t_next, *w);
  return t_next;
}

void HingeRun::AddStats(const integrators::Statistics& s) {
  stats_.steps += s.steps;
  stats_.rejected += s.rejected;
  stats_.evaluations += s.evaluations;
  stats_.dense_steps += s.dense_steps;
}

bool HingeRun::Stopped(integrators::Termination t, const std::string& message) {
  if (t == integrators::Termination::kReachedEnd) return false;
  termination_ = t;
  message_ = message;
  return true;
}

const FreeHingeSystem::Snapshot& HingeRun::SnapOf(const integrators::ShapeState& y) const {
  if (!(memo_valid_ && y.t == memo_state_.t && y.H_B == memo_state_.H_B &&
        y.x.size() == memo_state_.x.size() && y.x == memo_state_.x)) {
    memo_snap_ = sys_.Snap(y.t, y.H_B, y.x);
    memo_state_ = y;
    memo_valid_ = true;
    memo_jdot_valid_ = false;
  }
  return memo_snap_;
}

Mat3 HingeRun::JdotOf(const integrators::ShapeState& y) const {
  SnapOf(y);  // the memo's state
  if (!memo_jdot_valid_) {
    memo_jdot_ = sys_.InertiaRate(y.t, y.H_B, y.x);
    memo_jdot_valid_ = true;
  }
  return memo_jdot_;
}

// The terminal events of the free hinges (latches, jams, stops) and the spin-axis events,
// each with its rate (a hinge angle's is the hinge rate).
void HingeRun::FreeEvents(std::vector<integrators::ShapeEventFunction>& events,
                          std::vector<EventTag>& tags) const {
  const std::vector<int>& free = sys_.free_hinges();
  auto add_hinge = [&](const std::string& name, double sense, double angle, HingeEvent::Kind kind,
                       int a, double restitution, int side = 0) {
    const int k = free[static_cast<std::size_t>(a)];
    events.push_back(
        {name,
         [a, sense, angle](const integrators::ShapeState& s) { return sense * (s.x[a] - angle); },
         1, true, options_.refine_events,
         [this, k, sense](const integrators::ShapeState& s) {
           return sense * SnapOf(s).theta_dot[k];
         }});
    tags.push_back({EventTag::What::kHinge, kind, a, angle, restitution, side});
  };
  for (int a = 0; a < static_cast<int>(free.size()); ++a) {
    const int k = free[static_cast<std::size_t>(a)];
    const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
    const double theta_r = release_angle_[static_cast<std::size_t>(k)];
    const std::string name = body_.panels[static_cast<std::size_t>(k)].name;
    if (d.latch.enabled) {
      const double sense = d.latch.angle >= theta_r ? 1.0 : -1.0;
      if (d.latch.jam_fraction > 0.0) {
        const double jam = theta_r + d.latch.jam_fraction * (d.latch.angle - theta_r);
        add_hinge("jam " + name, sense, jam, HingeEvent::Kind::kJam, a, 0.0);
      }
      add_hinge("latch " + name, sense, d.latch.angle, HingeEvent::Kind::kLatch, a, 0.0);
    }
    if (std::isfinite(d.stops.max_angle)) {
      add_hinge("stop max " + name, 1.0, d.stops.max_angle, HingeEvent::Kind::kStop, a,
                d.stops.restitution, 1);
    }
    if (std::isfinite(d.stops.min_angle)) {
      add_hinge("stop min " + name, -1.0, d.stops.min_angle, HingeEvent::Kind::kStop, a,
                d.stops.restitution, -1);
    }
    // Exact Coulomb friction: the rate reaching 0 against the slip ends the slip (at
    // -kSlipEndRate: a slip starts at rate 0 up to rounding, which must not end it).
    if (schedule::IsCoulomb(d.friction)) {
      const double slip = sys_.slip(k);
      events.push_back({"slip ends " + name,
                        [this, k, slip](const integrators::ShapeState& s) {
                          return slip * SnapOf(s).theta_dot[k] + kSlipEndRate;
                        },
                        -1, true, options_.refine_events});
      tags.push_back({EventTag::What::kHinge, HingeEvent::Kind::kStick, a});
    }
  }
  // Held hinges: released when the torque holding them exceeds what holds them.
  for (int k = 0; k < n_; ++k) {
    const Hold& h = hold_[static_cast<std::size_t>(k)];
    if (h.kind == Hold::Kind::kNone) continue;
    const bool stop = h.kind == Hold::Kind::kStop;
    events.push_back(
        {(stop ? "lift-off " : "slip ") + body_.panels[static_cast<std::size_t>(k)].name,
         [this, k](const integrators::ShapeState& s) { return HoldMargin(k, s.t, s.H_B, s.x); }, 1,
         true, options_.refine_events});
    EventTag tag{EventTag::What::kHinge,
                 stop ? HingeEvent::Kind::kLiftOff : HingeEvent::Kind::kSlip};
    tag.side = h.side;
    tag.panel = k;
    tags.push_back(tag);
  }
  const Vec3 s = s_;
  auto h_dot = [this](const integrators::ShapeState& y) {
    return Vec3(y.H_B.cross(SnapOf(y).w_NB_B));
  };
  events.push_back({"flip",
                    [this, s](const integrators::ShapeState& y) {
                      return FlipFunction(SnapOf(y).J_B, s, y.H_B);
                    },
                    0, false, options_.refine_events,
                    [this, s, h_dot](const integrators::ShapeState& y) {
                      return FlipFunctionRate(SnapOf(y).J_B, JdotOf(y), s, y.H_B, h_dot(y));
                    }});
  tags.push_back({EventTag::What::kFlip});
  events.push_back({"spin axis 45 deg",
                    [s](const integrators::ShapeState& y) { return SpinAxis45Gap(s, y.H_B); }, 0,
                    false, options_.refine_events,
                    [s, h_dot](const integrators::ShapeState& y) {
                      return SpinAxis45GapRate(s, y.H_B, h_dot(y));
                    }});
  tags.push_back({EventTag::What::kCross45});
  events.push_back(
      {"separatrix",
       [this](const integrators::ShapeState& y) { return SeparatrixGap(SnapOf(y).J_B, y.H_B); }, 0,
       false, options_.refine_events});
  tags.push_back({EventTag::What::kSeparatrix});
}

// Free hinges: the shape integrator, to t_next or the first latch / jam / stop. The
// largest spin-axis angle: f = s . H_B / M and its rate at every accepted step's end, a
// minimum of f inside a step from the cubic Hermite interpolant of f (no extra
// right-hand sides; the error control keeps steps short against the nutation).
SegmentEnd HingeRun::FreeSegment(double t_next) {
  memo_valid_ = false;  // the free set may have changed
  std::vector<integrators::ShapeEventFunction> events;
  std::vector<EventTag> tags;
  FreeEvents(events, tags);
  auto point = [this](const integrators::ShapeState& y) {
    const Vec3 Hdot = y.H_B.cross(sys_.Snap(y.t, y.H_B, y.x).w_NB_B);
    const double rate = s_.dot(Hdot) / M_;
    return AxisPoint{y.t, s_.dot(y.H_B) / M_, rate, rate, y.H_B, Hdot, Hdot};
  };
  // The shape state carries the work of the free hinges' sources and of the prescribed
  // drives over this segment (FreeHingeSystem::kLedgerTerms accumulators, from 0).
  constexpr int kTerms = FreeHingeSystem::kLedgerTerms;
  const Eigen::Index nx = x_.size();
  auto work_at = [this, nx](const integrators::ShapeState& y) {
    WorkLedger w = work_;
    w.damper += y.x[nx];
    w.friction += y.x[nx + 1];
    w.motor += y.x[nx + 2];
    w.drive += y.x[nx + 3];
    return w;
  };
  integrators::ShapeState ys;
  ys.t = t_;
  ys.H_B = y_.H_B;
  ys.q_NB = y_.q_NB;
  ys.x.resize(nx + kTerms);
  ys.x << x_, Eigen::VectorXd::Zero(kTerms);
  AxisPoint prev = point(ys);
  // Energy projection (Hairer, Lubich and Wanner, Geometric Numerical Integration, 2nd ed.,
  // section IV.4), in a run whose hinges swing through more than kProjectionRadians: each
  // step's end (theta_f, p_f) is moved onto E = E_start + W, W the sources' work the
  // ledger integrates over the segment. A Runge-Kutta method's energy error grows with
  // every step (an undamped 1e6 N m/rad spring over 84000 periods: 2.7e-7 of E at rtol
  // 1e-11); projected, it stays at the steps' own error (5e-13). H_B and the attitude are
  // kept. Shorter swings keep their energy to the tolerance unprojected (every shipped
  // profile).
  const FreeHingeSystem::Snapshot start_snap = sys_.Snap(ys.t, ys.H_B, ys.x);
  const double e_start = start_snap.kinetic_energy + start_snap.spring_energy;
  const int m = sys_.free_count();
  const auto project = [&](integrators::ShapeState& y) {
    if (!project_energy_ || m == 0) return;
    const auto energy = [&](const Eigen::VectorXd& x) {
      const FreeHingeSystem::Snapshot s = sys_.Snap(y.t, y.H_B, x);
      return s.kinetic_energy + s.spring_energy;
    };
    const FreeHingeSystem::Snapshot s = sys_.Snap(y.t, y.H_B, y.x);
    const double excess = s.kinetic_energy + s.spring_energy - (e_start + y.x.tail<kTerms>().sum());
    // The move that changes E by -excess and is smallest in units of the tolerance of each
    // component (tol_i: atol scale + rtol |y_i|, as the error control weighs them):
    // delta_i = -excess tol_i^2 g_i / sum (tol_j g_j)^2, g = dE/d(theta_f, p_f) (theta'_f
    // for p_f; a central difference for theta_f). The move is at most kProjectionReach
    // tolerances long: a projection of the steps' error, never a jump (a larger excess,
    // where the hinges are nearly at rest, is taken up over the next steps).
    const integrators::Tolerances& tol = settings_.tolerances;
    Eigen::VectorXd g(2 * m), w(2 * m);
    for (int a = 0; a < m; ++a) {
      const double th = y.x[a];
      const double h = 1e-7 * std::max(1.0, std::abs(th));
      Eigen::VectorXd xp = y.x, xm = y.x;
      xp[a] += h;
      xm[a] -= h;
      g[a] = (energy(xp) - energy(xm)) / (2.0 * h);
      w[a] = tol.atol + tol.rtol * std::abs(th);
      g[m + a] = s.coordinate_rates[a];
      w[m + a] = tol.atol * M_ + tol.rtol * std::abs(y.x[m + a]);
    }
    const double reach2 = g.cwiseProduct(w).squaredNorm();
    if (!(reach2 > 0.0) || !std::isfinite(excess)) return;
    const double cap = kProjectionReach * std::sqrt(reach2);
    const double take = std::clamp(excess, -cap, cap);
    y.x.head(2 * m) -= (take / reach2) * w.cwiseProduct(w).cwiseProduct(g);
  };
  const integrators::ShapeIntegrationResult r = integrators::IntegrateShape(
      shape_method_, settings_, sys_, ys, t_next, grid_, &next_out_, events,
      [&](const integrators::ShapeState& y) {
        RunSample o = SampleOf(y.t, y.H_B, y.q_NB, y.x, dynamics::Side::kRight);
        o.work = work_at(y);
        // On a prescribed rate jump at the segment's end the sample holds the state after
        // it: the drive's impulsive work there counts.
        if (y.t >= t_next && t_next < t1_) {
          o.work.drive +=
              o.kinetic - SampleOf(y.t, y.H_B, y.q_NB, y.x, dynamics::Side::kLeft).kinetic;
        }
        rec_.Sample(o);
      },
      [&](const integrators::ShapeState& y) {
        rec_.Progress(y.t);
        const AxisPoint p = point(y);
        rec_.SpinAxisStep(prev, p);
        prev = p;
      },
      project);
  AddStats(r.stats);
  if (settings_.step <= 0.0 || r.next_step > 0.0) settings_.step = r.next_step;
  for (const integrators::ShapeEvent& e : r.events) {
    const EventTag& tag = tags[static_cast<std::size_t>(e.index)];
    if (tag.what == EventTag::What::kFlip) {
      rec_.CandidateFlip(e.t, sys_.Snap(e.t, e.state.H_B, e.state.x).J_B, e.state.H_B);
    } else if (tag.what == EventTag::What::kCross45) {
      rec_.Crossing45(e.t);
    } else if (tag.what == EventTag::What::kSeparatrix) {
      rec_.SeparatrixCrossing(e.t, e.direction);
    }
  }
  if (Stopped(r.termination, r.message)) return SegmentEnd::kStopped;
  rec_.SpinAxisCos(Cos(r.final_state.H_B));
  // The segment's end, or the event; a segment shorter than the driver's time
  // resolution (kTimeEps) counts as reached, so the loop always advances.
  t_ = r.stopped_at_event ? r.final_state.t : t_next;
  y_.t = t_;
  y_.H_B = r.final_state.H_B;
  y_.q_NB = r.final_state.q_NB;
  work_ = work_at(r.final_state);
  x_ = r.final_state.x.head(nx);
  if (!r.stopped_at_event) return SegmentEnd::kReached;
  OnHingeEvent(tags[static_cast<std::size_t>(r.events.back().index)], r.stuck);
  return SegmentEnd::kHingeEvent;
}

// A located hinge event at t_: a lift-off or slip of a held hinge; the end of a slip; a
// latch, jam or stop of free hinge tag.a: the impulse; a lock (latch, jam, coming to
// rest) ends the phase and may start after-latch releases; a bounce does not.
void HingeRun::OnHingeEvent(const EventTag& tag, bool stuck) {
  CountInstant();
  if (tag.panel >= 0) {
    Unhold(tag.panel, tag.kind);
    return;
  }
  if (tag.kind == HingeEvent::Kind::kStick) {
    Sticks(tag, stuck);
    return;
  }
  const int k = sys_.free_hinges()[static_cast<std::size_t>(tag.a)];
  const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  // Snap the hinge onto the event's angle (the located state is within the event
  // location tolerance of it).
  x_[tag.a] = tag.angle;
  const RunSample before = Current(dynamics::Side::kRight);
  HingeEvent::Kind kind = tag.kind;
  // A stop at the latch angle is the latch.
  if (kind == HingeEvent::Kind::kStop && d.latch.enabled && d.latch.angle == tag.angle) {
    kind = HingeEvent::Kind::kLatch;
  }
  // Stuck: the panel could not leave the stop it just rebounded off (its rebound is
  // shorter than integrators::kMinLeaveStep): it rests there.
  if (stuck) kind = HingeEvent::Kind::kRest;
  double target = 0.0;
  if (kind == HingeEvent::Kind::kStop) {
    target = -tag.restitution * before.theta_dot[k];
    if (RestsOnStop(tag, target)) {
      kind = HingeEvent::Kind::kRest;
      target = 0.0;
    }
  }
  const FreeHingeSystem::Impulse imp = sys_.ApplyImpulse(t_, y_.H_B, x_, tag.a, target);
  work_.impacts -= imp.energy_dissipated;
  work_.drive += imp.drive_work;
  Record(kind, k, tag.angle, &imp);
  if (kind == HingeEvent::Kind::kStop) return;
  rec_.ClosePhase(before);
  x_ = sys_.Lock(k, tag.angle, x_);
  out_.latch_times[static_cast<std::size_t>(k)] = t_;
  if (kind == HingeEvent::Kind::kRest && tag.side != 0) {
    StartHold(k, Hold::Kind::kStop, tag.side);
  } else {
    done_[static_cast<std::size_t>(k)] = 1;
  }
  if (kind == HingeEvent::Kind::kLatch) {
    for (int j = 0; j < n_; ++j) {
      const HingePlan& p = plans_[static_cast<std::size_t>(j)];
      if (p.kind == HingePlan::Kind::kFree &&
          p.drive.release.kind == schedule::Release::Kind::kAfterLatch &&
          p.drive.release.panel == k) {
        release_time_[static_cast<std::size_t>(j)] = t_ + p.drive.release.delay;
      }
    }
  }
  OpenPhase(Current(dynamics::Side::kRight));
}

// Exact Coulomb friction brought free hinge tag.a to rest: the impulse that makes its rate
// exactly 0 (a rounding error of the located state), then held if friction can hold it
// (or if it could not leave rest the other way: `stuck`), else it slips back.
bool HingeRun::Sticks(const EventTag& tag, bool stuck) {
  const int k = sys_.free_hinges()[static_cast<std::size_t>(tag.a)];
  const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  const RunSample before = Current(dynamics::Side::kRight);
  const FreeHingeSystem::Impulse imp = sys_.ApplyImpulse(t_, y_.H_B, x_, tag.a, 0.0);
  work_.impacts -= imp.energy_dissipated;
  work_.drive += imp.drive_work;
  const double angle = x_[tag.a];
  Eigen::VectorXd held = sys_.Lock(k, angle, x_);
  const double lambda = sys_.HoldingTorque(k, t_, y_.H_B, held);
  if (!stuck && std::abs(lambda) > d.friction.torque) {
    // It slips on, the way the holding torque pulls it (back, or on after a touch of 0).
    x_ = sys_.Free(k, t_, y_.H_B, held, 0.0);
    sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
    return false;
  }
  rec_.ClosePhase(before);
  x_ = held;
  StartHold(k, Hold::Kind::kStick, 0);
  Record(HingeEvent::Kind::kStick, k, angle, &imp);
  OpenPhase(Current(dynamics::Side::kRight));
  return true;
}

bool HingeRun::RestsOnStop(const EventTag& tag, double rebound) {
  const int k = sys_.free_hinges()[static_cast<std::size_t>(tag.a)];
  const schedule::Stops& st = plans_[static_cast<std::size_t>(k)].drive.stops;
  const double v = std::abs(rebound);
  // A rattle: the impacts come faster than one contact lasts, or the rebound would reach
  // the other stop within it.
  double& last = last_impact_[static_cast<std::size_t>(k)];
  const bool rattle = t_ - last < schedule::kContactTime;
  last = t_;
  if (rattle || st.max_angle - st.min_angle < v * schedule::kContactTime) return true;
  // The acceleration pressing the hinge onto the stop, at rest there without friction.
  Eigen::VectorXd at_rest = x_;
  sys_.ApplyImpulse(t_, y_.H_B, at_rest, tag.a, 0.0);
  const int slip = sys_.slip(k);
  sys_.SetSlip(k, 0);
  const double press = tag.side * sys_.Acceleration(tag.a, t_, y_.H_B, at_rest);
  sys_.SetSlip(k, slip);
  if (!(press > 0.0)) return false;
  const double angle_tol =
      settings_.tolerances.atol + settings_.tolerances.rtol * std::abs(tag.angle);
  return v < schedule::kRestSpeed || 2.0 * v / press < schedule::kContactTime ||
         v * v / (2.0 * press) <= angle_tol;
}

// No free hinge: locked and prescribed hinges, the rigid-body path. The spin-axis
// extrema are located as events (zeros of the rate of s . H_B).
SegmentEnd HingeRun::RigidSegment(double t_next) {
  const std::size_t out_end = CountTimes(grid_, t_next, true);
  const WindowTimes times(grid_, next_out_, out_end);
  const Vec3 s = s_;
  const double M = M_;
  const FreeHingeSystem& sys = sys_;
  const integrators::EventFunction extremum{"spin axis extremum",
                                            [&sys, s, M](const integrators::State& y) {
                                              const dynamics::InertiaSample js = sys.Evaluate(y.t);
                                              const Vec3 w = js.J_inv_B * (y.H_B - js.h_rel_B);
                                              return s.dot(y.H_B.cross(w)) / M;
                                            }};
  std::vector<integrators::EventFunction> events =
      RigidSpinAxisEvents(s, [&sys](double t) { return sys.Evaluate(t); });
  events.push_back(extremum);
  const std::vector<EventTag> tags = {
      {EventTag::What::kFlip}, {EventTag::What::kCross45}, {EventTag::What::kExtremum}};
  // With no hinge free the prescribed drives are the only source of work: theirs is the
  // change of the kinetic energy (the locked springs hold theirs).
  const double kinetic0 = Current(dynamics::Side::kRight).kinetic;
  // An outcome-only run measures the nutation along the steps (run_recorder.h); with
  // every hinge locked the inertia is the segment's start's throughout.
  std::optional<dynamics::InertiaSample> held;
  if (!rec_.sampling() && Describe(0.5 * (t_ + t_next)).rigid) held = sys.Evaluate(t_);
  auto point = [&sys, &held](const integrators::State& y) {
    const dynamics::InertiaSample js = held ? *held : sys.Evaluate(y.t);
    const Vec3 Hdot = y.H_B.cross(js.J_inv_B * (y.H_B - js.h_rel_B));
    return AxisPoint{y.t, 0.0, 0.0, 0.0, y.H_B, Hdot, Hdot};
  };
  AxisPoint prev = rec_.sampling() ? AxisPoint() : point(y_);
  const integrators::IntegrationResult r = integrators::Integrate(
      *rigid_stepper_, settings_, sys_, y_, t_next, times, events,
      [&](const integrators::State& y) {
        rec_.Progress(y.t);
        if (rec_.sampling()) return;
        const AxisPoint p = point(y);
        rec_.NutationStep(prev, p);
        prev = p;
      },
      [&](const integrators::State& y) {
        // At a prescribed rate jump (a window's end on an output time) the sample holds
        // the state after it, as every output does; the run's end holds its final state.
        const dynamics::Side side = y.t >= t1_ ? dynamics::Side::kLeft : dynamics::Side::kRight;
        RunSample o = SampleOf(y.t, y.H_B, y.q_NB, Eigen::VectorXd(), side);
        o.work.drive += o.kinetic - kinetic0;
        rec_.Sample(o);
      });
  next_out_ = out_end;
  AddStats(r.stats);
  for (const integrators::Event& e : r.events) {
    switch (tags[static_cast<std::size_t>(e.index)].what) {
      case EventTag::What::kFlip:
        rec_.CandidateFlip(e.t, sys_.Evaluate(e.t).J_B, e.state.H_B);
        break;
      case EventTag::What::kCross45:
        rec_.Crossing45(e.t);
        break;
      default:
        rec_.SpinAxisCos(Cos(e.state.H_B));
    }
  }
  if (Stopped(r.termination, r.message)) return SegmentEnd::kStopped;
  t_ = t_next;
  y_ = r.final_state;
  y_.t = t_;
  work_.drive += Current(dynamics::Side::kLeft).kinetic - kinetic0;
  rec_.SpinAxisCos(Cos(y_.H_B));
  return SegmentEnd::kReached;
}

void HingeRun::OpenPhase(const RunSample& start) {
  rec_.OpenPhase(Describe(t_), start);
  const Eigen::VectorXd x = sys_.ShapeState(start.t, start.H_B, start.theta, start.theta_dot);
  Eigen::VectorXd y(3 + x.size());
  y << start.H_B, x;
  // The phase lasts to the next window boundary of a prescribed hinge (beyond the run's
  // end too: a rotor held through the run is one phase however short the run).
  const double length = sys_.NextBreakpoint(start.t) - start.t;
  SteadySpin s = LinearizeSteadySpin(
      FlowOf(sys_, start.t, length, RotorPeriod(start.t), WindingHinges(), WindingAxes()), y);
  if (s.orbit_rotor >= 0) s.orbit_rotor_panel = sys_.free_hinges()[s.orbit_rotor];
  rec_.SetSteadySpin(s);
}

std::vector<math::Vec3> HingeRun::WindingAxes() const {
  std::vector<math::Vec3> out;
  const std::vector<int>& free = sys_.free_hinges();
  for (int a : WindingHinges()) {
    const model::Panel& p = body_.panels[static_cast<std::size_t>(free[a])];
    out.push_back(p.parent < 0 ? p.hinge_axis_B
                               : math::Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  }
  return out;
}

double HingeRun::RotorPeriod(double t) const {
  double rate = 0.0;
  for (const HingePlan& p : plans_) {
    if (p.kind != HingePlan::Kind::kPrescribed) continue;
    for (const schedule::HingeMove& mv : p.moves) {
      if (mv.kind == schedule::HingeMove::Kind::kRate && mv.t_begin <= t && t < mv.t_end)
        rate = std::max(rate, std::abs(mv.rate));
    }
  }
  constexpr double two_pi = 6.283185307179586477;
  return rate > 0.0 ? two_pi / rate : 0.0;
}

std::vector<int> HingeRun::WindingHinges() const {
  std::vector<int> out;
  const std::vector<int>& free = sys_.free_hinges();
  for (std::size_t a = 0; a < free.size(); ++a) {
    const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(free[a])].drive;
    // A free rotor: nothing holds its angle or its rate (friction or a motor would stop or
    // drive it: no steady motion to linearize about then).
    if (d.spring.stiffness == 0.0 && d.spring.preload == 0.0 && !d.stops.any() &&
        !d.latch.enabled && d.friction.torque == 0.0 && d.damping == 0.0 &&
        d.motor.kind == schedule::Motor::Kind::kNone)
      out.push_back(static_cast<int>(a));
  }
  return out;
}

MissionResult HingeRun::Run() {
  while (true) {
    const bool changed = ReleasesDue();
    if (!started_ || changed) {
      const RunSample start = Current(dynamics::Side::kRight);
      if (!started_) out_.energy_initial = start.kinetic + start.spring;
      OpenPhase(start);
      started_ = true;
    }
    if (!(t_ < t1_)) break;
    const double t_next = NextChange();
    // A held hinge's release is a terminal event: the shape path, with no hinge free.
    const SegmentEnd end =
        sys_.free_count() > 0 || AnyHeld() ? FreeSegment(t_next) : RigidSegment(t_next);
    if (end == SegmentEnd::kStopped) break;
    if (end == SegmentEnd::kHingeEvent) continue;
    // A prescribed window boundary: a phase boundary.
    if (t_ < t1_ && std::binary_search(windows_.begin(), windows_.end(), t_)) {
      const RunSample before = Current(dynamics::Side::kLeft);
      rec_.ClosePhase(before);
      // A prescribed rate may jump here: the drive's impulsive work.
      work_.drive += Current(dynamics::Side::kRight).kinetic - before.kinetic;
      OpenPhase(Current(dynamics::Side::kRight));
    }
  }
  // A run that stopped early: the remaining times get its last state.
  if (termination_ != integrators::Termination::kReachedEnd && rec_.sampling()) {
    RunSample s = Current(dynamics::Side::kRight);
    while (next_out_ < grid_.size()) {
      s.t = grid_.at(next_out_++);
      rec_.Sample(s);
    }
  }
  const RunSample final_sample = Current(dynamics::Side::kLeft);
  rec_.ClosePhase(final_sample);
  out_.final_state = y_;
  out_.final_J_B = final_sample.J_B;
  out_.energy_final = final_sample.kinetic + final_sample.spring;
  out_.work = work_;
  out_.stats = stats_;
  out_.termination = termination_;
  out_.message = message_;
  rec_.Finish(out_);
  return std::move(out_);
}

}  // namespace

MissionResult RunHingeMission(const CompiledRun& compiled,
                              SampleSink& sink,
                              const std::function<void(double)>& progress,
                              const RunOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  HingeRun run(compiled, options.sample_trajectory ? &sink : nullptr, progress, options);
  MissionResult out = run.Run();
  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::analysis
