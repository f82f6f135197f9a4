// The independent Simbody model of free hinges. See simbody_free_hinges.h.
// Nothing here uses the reduced model's dynamics: the bodies, forces and the integration
// are Simbody's, and the event impulses come from Simbody's mass matrix.

#include "deploysim/crosscheck/simbody_free_hinges.h"

#include <Simbody.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/crosscheck/simbody_body.h"
#include "deploysim/crosscheck/simtk_support.h"
#include "deploysim/math/number_format.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/hinge_motion.h"
#include "deploysim/schedule/laws.h"

namespace deploysim::crosscheck {

namespace {

using simtk::AboutOrigin;
using simtk::ThrowIfOver;
using simtk::ToEigen;
using simtk::ToInertia;
using simtk::ToRotation;
using simtk::ToSimTK;
using simtk::Vec6;

using run::HingeEvent;
using schedule::HingePlan;
using SimTK::Real;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Two times closer than this (relative to max(1, |t|)) are the same instant: a grid time
// next to a release or window end is integrated to that restart point.
constexpr double kSameTime = 1e-9;
constexpr std::uintmax_t kMaxLocateIterations = 200;
// After a rebound off a stop, the step is limited to this fraction of the predicted
// duration of the bounce (2 |rate| / |acceleration|), so that the next impact is seen.
constexpr double kBounceStepFraction = 0.125;
// Interior probes searched when a step nevertheless jumped over a whole bounce.
constexpr int kBounceProbes = 16;
// Hub mobilities of a Free mobilizer: 3 angular, 3 linear speeds.
constexpr int kHubU = 6;

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Exact = math::FormatNumber;

double SameTime(double t) { return kSameTime * std::max(1.0, std::abs(t)); }

/// Which restart point the integration is heading for: prescribed hinges are evaluated
/// from the left there (a rate may jump), from the right elsewhere.
struct SegmentClock {
  double segment_end = kInf;
  bool Left(double t) const {
    return std::isfinite(segment_end) && t >= segment_end - SameTime(segment_end);
  }
};

/// theta, theta', theta'' of a prescribed hinge.
struct PathValue {
  double q = 0.0;
  double qdot = 0.0;
  double qddot = 0.0;
};

/// The angle of a prescribed hinge along its windows (schedule::HingeMove): kTo along its
/// law from the angle at the window's start, kRate at constant rate, held between windows.
class PrescribedPath {
 public:
  PrescribedPath(std::vector<schedule::HingeMove> moves, double angle0)
      : moves_(std::move(moves)), angle0_(angle0) {
    double a = angle0;
    for (std::size_t i = 0; i < moves_.size(); ++i) {
      start_.push_back(a);
      a = EndAngle(i);
    }
  }

  /// At time t, from the left (t in (t_begin, t_end] is inside a window) or the right.
  PathValue At(double t, bool left) const {
    double held = angle0_;
    for (std::size_t i = 0; i < moves_.size(); ++i) {
      const schedule::HingeMove& m = moves_[i];
      const bool inside = left ? (t > m.t_begin && t <= m.t_end) : (t >= m.t_begin && t < m.t_end);
      if (inside) return InWindow(i, t);
      if (left ? t > m.t_end : t >= m.t_end) held = EndAngle(i);
    }
    return {held, 0.0, 0.0};
  }

 private:
  double EndAngle(std::size_t i) const {
    const schedule::HingeMove& m = moves_[i];
    return m.kind == schedule::HingeMove::Kind::kTo ? m.angle
                                                    : start_[i] + m.rate * (m.t_end - m.t_begin);
  }
  PathValue InWindow(std::size_t i, double t) const {
    const schedule::HingeMove& m = moves_[i];
    if (m.kind == schedule::HingeMove::Kind::kRate) {
      return {start_[i] + m.rate * (t - m.t_begin), m.rate, 0.0};
    }
    const double T = m.t_end - m.t_begin;
    const schedule::LawValue v = schedule::EvaluateLaw(m.law, (t - m.t_begin) / T);
    const double d = m.angle - start_[i];
    return {start_[i] + d * v.s, d * v.ds / T, d * v.dds / (T * T)};
  }

  std::vector<schedule::HingeMove> moves_;
  double angle0_;
  std::vector<double> start_;  // angle at each window's t_begin
};

/// Position-level Motion of a prescribed pin.
class PrescribedHinge final : public SimTK::Motion::Custom::Implementation {
 public:
  PrescribedHinge(PrescribedPath path, const SegmentClock& clock)
      : path_(std::move(path)), clock_(clock) {}
  SimTK::Motion::Level getLevel(const SimTK::State&) const override {
    return SimTK::Motion::Position;
  }
  void calcPrescribedPosition(const SimTK::State& s, int nq, Real* q) const override {
    q[0] = Value(s, nq).q;
  }
  void calcPrescribedPositionDot(const SimTK::State& s, int nq, Real* qdot) const override {
    qdot[0] = Value(s, nq).qdot;
  }
  void calcPrescribedPositionDotDot(const SimTK::State& s, int nq, Real* qddot) const override {
    qddot[0] = Value(s, nq).qddot;
  }

 private:
  PathValue Value(const SimTK::State& s, int nq) const {
    if (nq != 1) std::abort();  // a Pin has exactly one q: broken internal invariant
    const double t = s.getTime();
    return path_.At(t, clock_.Left(t));
  }
  PrescribedPath path_;
  const SegmentClock& clock_;
};

/// Preload, motor and friction of a free hinge (the spring and damper are Simbody's
/// MobilityLinearSpring and MobilityLinearDamper): Q = preload + motor - mu tanh(u/omega_f).
/// Potential energy -preload (theta - rest): with the spring's, the stored energy of
/// schedule/hinge_plan.h.
/// A servo motor (schedule::Motor::Kind::kServo) adds servo_stiffness (theta_ref - theta) +
/// servo_damping (theta'_ref - theta'), theta_ref along its `follow` moves (its window ends
/// are restart points, as a prescribed hinge's).
class HingeDrive final : public SimTK::Force::Custom::Implementation {
 public:
  HingeDrive(const SimTK::MobilizedBody::Pin& pin,
             const schedule::FreeDrive& drive,
             double angle0,
             const SegmentClock& clock)
      : pin_(pin), drive_(drive), servo_path_(drive.motor.follow, angle0), clock_(clock) {}
  void calcForce(const SimTK::State& s,
                 SimTK::Vector_<SimTK::SpatialVec>&,
                 SimTK::Vector_<SimTK::Vec3>&,
                 SimTK::Vector& mobility_forces) const override {
    const double u = pin_.getOneU(s, 0);
    double Q = drive_.spring.preload;
    const schedule::Motor& m = drive_.motor;
    if (m.kind == schedule::Motor::Kind::kConstant) Q += m.torque;
    if (m.kind == schedule::Motor::Kind::kTorqueSpeed) {
      Q += m.stall_torque * (1.0 - u / m.no_load_speed);
    }
    if (m.kind == schedule::Motor::Kind::kServo) {
      const double t = s.getTime();
      const PathValue ref = servo_path_.At(t, clock_.Left(t));
      Q += m.servo_stiffness * (ref.q - pin_.getOneQ(s, 0)) + m.servo_damping * (ref.qdot - u);
    }
    const schedule::Friction& f = drive_.friction;
    if (f.torque > 0.0) Q -= f.torque * std::tanh(u / f.regularization_speed);
    pin_.applyOneMobilityForce(s, 0, Q, mobility_forces);
  }
  Real calcPotentialEnergy(const SimTK::State& s) const override {
    return -drive_.spring.preload * (pin_.getOneQ(s, 0) - drive_.spring.rest_angle);
  }
  bool dependsOnlyOnPositions() const override { return false; }

 private:
  SimTK::MobilizedBody::Pin pin_;
  schedule::FreeDrive drive_;
  PrescribedPath servo_path_;
  const SegmentClock& clock_;
};

/// The multibody system with the compliant latches and the clock its prescribed hinges
/// read.
struct FreeSystem : simtk::HingedSystem {
  // Compliant latch (CompliantLatch), per panel; empty handles without one.
  std::vector<SimTK::Force::MobilityLinearStop> latch_stops;
  std::vector<SimTK::Force::MobilityLinearDamper> latch_dampers;
  SegmentClock clock;
};

using simtk::AddHingedBodies;
using simtk::HubAngularVelocity_B;
using simtk::HubRotation;
using simtk::KineticEnergyAboutCom;
using simtk::SystemInertia_B;

Vec6 CentralMomentum(const FreeSystem& sys, const SimTK::State& s) {
  return simtk::CentralMomentum(sys.system, sys.matter, s);
}

math::Vec3 Momentum_B(const FreeSystem& sys, const SimTK::State& s) {
  return HubRotation(sys, s).transpose() * simtk::Momentum_N(sys, s);
}

/// Samples of the continuous functions located between steps.
struct FlipValue {
  double g = 0.0;
  bool intermediate = false;
};

/// Grows `run` by one sample.
void AppendSample(const FreeSystem& sys,
                  const SimTK::State& s,
                  double t_label,
                  SimbodyFreeHingeRun& run) {
  simtk::AppendSample(sys, s, t_label, run.trajectory);
  sys.system.realize(s, SimTK::Stage::Dynamics);
  const double T = run.trajectory.kinetic_energy.back();
  const double V = sys.system.calcPotentialEnergy(s);
  run.stored_energy.push_back(V);
  run.total_energy.push_back(T + V);
  run.J_B.push_back(SystemInertia_B(sys, s));
}

/// An event witness of a free hinge: value = direction (theta - angle), crossing from
/// negative to >= 0 triggers.
struct Witness {
  /// In priority order for simultaneous crossings (a jam comes before the latch; a latch at
  /// a stop's angle is a latch).
  enum class Type { kJam, kLatch, kStopMax, kStopMin };
  Type type = Type::kLatch;
  std::size_t panel = 0;
  double angle = 0.0;      // [rad]
  double direction = 1.0;  // +1 or -1
  bool enabled = true;     // off once the hinge is locked for good (or compliantly latched)
  bool armed = false;      // last value seen < 0 (or <= 0 at release)
  bool after_rebound = false;
  double value = 0.0;         // at the start of the current step
  double bounce_time = kInf;  // [s] predicted duration of the bounce after a rebound
  double Value(double theta) const { return direction * (theta - angle); }
};

/// Runs one hinge profile on the Simbody model.
class Runner {
 public:
  Runner(const schedule::Profile& profile,
         const std::vector<double>& grid,
         const math::Vec3& spin_axis_B,
         const SimbodyFreeHingeOptions& options)
      : profile_(profile), grid_(grid), spin_axis_B_(spin_axis_B), options_(options) {}

  SimbodyFreeHingeRun Run() {
    const auto wall0 = std::chrono::steady_clock::now();
    Build();
    SimTK::State s0 = InitialState();
    run_.accuracy = options_.accuracy;
    run_.latch_times.assign(n_, kNaN);
    main_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(sys_.system);
    probe_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(sys_.system);
    for (SimTK::Integrator* integ : {main_.get(), probe_.get()}) {
      integ->setAccuracy(options_.accuracy);
      integ->setAllowInterpolation(false);
    }
    main_->setReturnEveryInternalStep(true);
    for (std::size_t k = 0; k < n_; ++k) {
      if (released_[k]) Release(s0, k);
    }
    Restart(s0);
    run_.stats.restarts = 0;
    h_N0_ = CentralMomentum(sys_, prev_).head<3>();

    std::size_t gi = 0;
    auto record_due = [&](double t) {
      while (gi < grid_.size() && grid_[gi] <= t + SameTime(t)) {
        AppendSample(sys_, prev_, grid_[gi], run_);
        const double drift = (run_.trajectory.h_N.back() - h_N0_).norm() / h_N0_.norm();
        run_.max_momentum_drift = std::max(run_.max_momentum_drift, drift);
        ++gi;
      }
    };
    record_due(t0_);
    while (gi < grid_.size()) {
      double target = grid_[gi];
      const double t_event = NextTimeEvent();
      if (t_event <= target + SameTime(target)) target = t_event;
      if (prev_.getTime() < target) {
        main_->stepTo(target, target);
        ThrowIfOver(*main_);
        const SimTK::State& cur = main_->getState();
        if (cur.getTime() > prev_.getTime()) {  // else: the start of a continuous interval
          if (HandleWitnesses(cur)) continue;   // an event: restarted at it
          LocateContinuous(prev_, cur);
          Advance(cur);
        }
        if (prev_.getTime() < target) continue;
      }
      if (target == t_event) ApplyTimeEvents(target);
      record_due(target);
    }
    run_.stats.steps = main_->getNumStepsTaken();
    run_.stats.attempts = main_->getNumStepsAttempted();
    run_.stats.realizations = main_->getNumRealizations();
    run_.stats.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    return std::move(run_);
  }

 private:
  // ---- construction ------------------------------------------------------------------

  void Build() {
    if (profile_.model.kind != model::ModelKind::kHinged) {
      throw std::invalid_argument(profile_.source + ": free hinges need a hinged model");
    }
    body_ = model::ValidatedHingedBody(profile_.model.hinged, profile_.model.source);
    n_ = body_.panels.size();
    if (profile_.hinges.size() != n_) {
      throw std::invalid_argument(
          profile_.source + ": hinges: " + std::to_string(profile_.hinges.size()) + " plans for " +
          std::to_string(n_) + " panels (must be one per panel)");
    }
    t0_ = profile_.t_begin();
    angle0_ = profile_.model.configuration(profile_.initial.configuration).hinge_angles;
    if (angle0_.size() != static_cast<Eigen::Index>(n_)) {
      throw std::invalid_argument(profile_.source + ": initial.configuration '" +
                                  profile_.initial.configuration +
                                  "' has the wrong number of hinge angles");
    }
    AddHingedBodies(sys_, body_, profile_.model.source);
    sys_.latch_stops.resize(n_);
    sys_.latch_dampers.resize(n_);
    released_.assign(n_, false);
    for (std::size_t k = 0; k < n_; ++k) {
      const HingePlan& plan = profile_.hinges[k];
      SimTK::MobilizedBody::Pin& pin = sys_.pins[k];
      if (plan.kind == HingePlan::Kind::kPrescribed) {
        SimTK::Motion::Custom(
            pin, new PrescribedHinge(PrescribedPath(plan.moves, angle0_[Index(k)]), sys_.clock));
        for (const schedule::HingeMove& m : plan.moves) {
          for (double t : {m.t_begin, m.t_end}) {
            if (t > t0_ + SameTime(t0_)) time_events_.push_back({t, TimeEvent::kWindow, k});
          }
        }
      }
      if (plan.kind != HingePlan::Kind::kFree) continue;
      const schedule::FreeDrive& d = plan.drive;
      if (d.spring.stiffness > 0.0) {
        SimTK::Force::MobilityLinearSpring(sys_.forces, pin, SimTK::MobilizerQIndex(0),
                                           d.spring.stiffness, d.spring.rest_angle);
      }
      if (d.damping > 0.0) {
        SimTK::Force::MobilityLinearDamper(sys_.forces, pin, SimTK::MobilizerUIndex(0), d.damping);
      }
      if (d.spring.preload != 0.0 || d.motor.kind != schedule::Motor::Kind::kNone ||
          d.friction.torque > 0.0) {
        SimTK::Force::Custom(sys_.forces, new HingeDrive(pin, d, angle0_[Index(k)], sys_.clock));
        for (const schedule::HingeMove& m : d.motor.follow) {
          for (double t : {m.t_begin, m.t_end}) {
            if (t > t0_ + SameTime(t0_)) time_events_.push_back({t, TimeEvent::kWindow, k});
          }
        }
      }
      if (d.latch.enabled && options_.compliant_latch.stiffness > 0.0) {
        sys_.latch_stops[k] = SimTK::Force::MobilityLinearStop(
            sys_.forces, pin, SimTK::MobilizerQIndex(0), options_.compliant_latch.stiffness, 0.0,
            d.latch.angle, d.latch.angle);
        sys_.latch_stops[k].setDisabledByDefault(true);
        sys_.latch_dampers[k] =
            SimTK::Force::MobilityLinearDamper(sys_.forces, pin, SimTK::MobilizerUIndex(0), 0.0);
        sys_.latch_dampers[k].setDisabledByDefault(true);
      }
      const schedule::Release& r = d.release;
      switch (r.kind) {
        case schedule::Release::Kind::kAtStart:
          released_[k] = true;
          break;
        case schedule::Release::Kind::kAtTime:
          if (r.time <= t0_ + SameTime(t0_)) {
            released_[k] = true;
          } else {
            time_events_.push_back({r.time, TimeEvent::kRelease, k});
          }
          break;
        case schedule::Release::Kind::kAfterLatch:
          if (r.panel < 0 || r.panel >= static_cast<int>(n_) || r.panel == static_cast<int>(k)) {
            throw std::invalid_argument(profile_.source + ": hinges." + body_.panels[k].name +
                                        ".release.after_latch = " + std::to_string(r.panel) +
                                        ": must be another panel");
          }
          break;
      }
      AddWitnesses(k, d);
    }
    SortTimeEvents();
  }

  void AddWitnesses(std::size_t k, const schedule::FreeDrive& d) {
    const double a0 = angle0_[Index(k)];  // the release angle: held there until released
    if (d.latch.enabled) {
      const double dir = d.latch.angle >= a0 ? 1.0 : -1.0;
      if (d.latch.jam_fraction > 0.0) {
        Witness w;
        w.type = Witness::Type::kJam;
        w.panel = k;
        w.angle = a0 + d.latch.jam_fraction * (d.latch.angle - a0);
        w.direction = dir;
        witnesses_.push_back(w);
      }
      Witness w;
      w.type = Witness::Type::kLatch;
      w.panel = k;
      w.angle = d.latch.angle;
      w.direction = dir;
      witnesses_.push_back(w);
    }
    if (d.stops.max_angle < kInf) {
      Witness w;
      w.type = Witness::Type::kStopMax;
      w.panel = k;
      w.angle = d.stops.max_angle;
      w.direction = 1.0;
      witnesses_.push_back(w);
    }
    if (d.stops.min_angle > -kInf) {
      Witness w;
      w.type = Witness::Type::kStopMin;
      w.panel = k;
      w.angle = d.stops.min_angle;
      w.direction = -1.0;
      witnesses_.push_back(w);
    }
  }

  SimTK::State InitialState() {
    SimTK::State s = sys_.system.realizeTopology();
    sys_.system.realizeModel(s);
    s.updTime() = t0_;
    const math::Mat3 R_NB0 = profile_.initial.q_NB.normalized().toRotationMatrix();
    sys_.hub.setQToFitRotation(s, ToRotation(R_NB0));
    sys_.hub.setQToFitTranslation(s, SimTK::Vec3(0));
    // Every hinge at rest but those the profile starts moving (free from the start).
    const Eigen::VectorXd& rate0 = profile_.initial.hinge_rates;
    auto rate_of = [&rate0](std::size_t k) { return rate0.size() > 0 ? rate0[Index(k)] : 0.0; };
    for (std::size_t k = 0; k < n_; ++k) {
      sys_.pins[k].setOneQ(s, 0, angle0_[Index(k)]);
      sys_.pins[k].setOneU(s, 0, rate_of(k));
    }
    for (std::size_t k = 0; k < n_; ++k) {
      if (profile_.hinges[k].kind != HingePlan::Kind::kPrescribed && rate_of(k) == 0.0) {
        sys_.pins[k].lock(s);
      }
    }
    u_index_.assign(kHubU + n_, 0);
    const int hub_first = sys_.hub.getFirstUIndex(s);
    for (int j = 0; j < kHubU; ++j) u_index_[static_cast<std::size_t>(j)] = hub_first + j;
    for (std::size_t k = 0; k < n_; ++k) {
      u_index_[kHubU + k] = sys_.pins[k].getFirstUIndex(s);
    }
    sys_.clock.segment_end = NextTimeEvent();
    sys_.system.prescribe(s);
    if (profile_.initial.w_NB_B) {
      const math::Vec3 w_N = R_NB0 * *profile_.initial.w_NB_B;
      simtk::FitHubVelocity(sys_, s, &w_N, math::Vec3::Zero(), math::Vec3::Zero());
    } else if (profile_.initial.H_B) {
      simtk::FitHubVelocity(sys_, s, nullptr, R_NB0 * *profile_.initial.H_B, math::Vec3::Zero());
    } else {
      throw std::invalid_argument(profile_.source +
                                  ": initial: neither angular velocity nor momentum");
    }
    return s;
  }

  // ---- time events (releases, prescribed window ends) -----------------------------------

  struct TimeEvent {
    double t;
    enum Kind { kWindow, kRelease } kind;
    std::size_t panel;
  };

  void SortTimeEvents() {
    std::stable_sort(time_events_.begin(), time_events_.end(),
                     [](const TimeEvent& a, const TimeEvent& b) { return a.t < b.t; });
  }

  /// The first pending time event (inf if none); they are removed once applied.
  double NextTimeEvent() const { return time_events_.empty() ? kInf : time_events_.front().t; }

  /// Applies the time events at t (the integration has just reached t).
  void ApplyTimeEvents(double t) {
    SimTK::State s = prev_;
    bool window = false;
    std::vector<std::size_t> releases;
    for (auto it = time_events_.begin(); it != time_events_.end();) {
      if (std::abs(it->t - t) <= SameTime(t)) {
        if (it->kind == TimeEvent::kWindow) window = true;
        if (it->kind == TimeEvent::kRelease) releases.push_back(it->panel);
        it = time_events_.erase(it);
      } else {
        ++it;
      }
    }
    sys_.clock.segment_end = NextTimeEvent();
    if (window) {
      // Prescribed rates may jump: re-prescribe from the right, keeping the momenta of the
      // free mobilities (the hub and the free hinges).
      const Eigen::VectorXd u_minus = GetU(s);
      sys_.system.prescribe(s);
      const Eigen::VectorXd u_target = GetU(s);
      ApplyJump(s, u_minus, ConstrainedMask(s, -1), u_target);
    }
    for (std::size_t k : releases) Release(s, k);
    Restart(s);
  }

  void Release(SimTK::State& s, std::size_t k) {
    released_[k] = true;
    const double theta = sys_.pins[k].getOneQ(s, 0);
    HingeEvent e;
    e.kind = HingeEvent::Kind::kRelease;
    e.t = s.getTime();
    e.panel = static_cast<int>(k);
    e.angle = theta;
    RecordEvent(s, e, FreeMask(s));
    sys_.pins[k].unlock(s);
    for (Witness& w : witnesses_) {
      if (w.panel != k) continue;
      w.value = w.Value(theta);
      w.armed = w.value <= 0.0;
      w.after_rebound = false;
    }
  }

  // ---- mobilities and velocity jumps ---------------------------------------------------

  static Eigen::Index Index(std::size_t k) { return static_cast<Eigen::Index>(k); }

  /// u in the order hub (6), pins in panel order.
  Eigen::VectorXd GetU(const SimTK::State& s) const {
    Eigen::VectorXd u(static_cast<Eigen::Index>(u_index_.size()));
    const SimTK::Vector& su = s.getU();
    for (std::size_t i = 0; i < u_index_.size(); ++i) u[Index(i)] = su[u_index_[i]];
    return u;
  }

  bool Moving(const SimTK::State& s, std::size_t k) const {
    return profile_.hinges[k].kind == HingePlan::Kind::kFree && released_[k] &&
           !sys_.pins[k].isLocked(s);
  }

  std::vector<bool> FreeMask(const SimTK::State& s) const {
    std::vector<bool> m(n_);
    for (std::size_t k = 0; k < n_; ++k) m[k] = Moving(s, k);
    return m;
  }

  /// Mobilities whose speed is set (locked or prescribed hinges, and `extra` if >= 0).
  std::vector<bool> ConstrainedMask(const SimTK::State& s, int extra) const {
    std::vector<bool> c(u_index_.size(), false);
    for (std::size_t k = 0; k < n_; ++k) {
      c[kHubU + k] = !Moving(s, k) || static_cast<int>(k) == extra;
    }
    return c;
  }

  /// Sets the speeds after an impulse: the constrained mobilities take u_target, the free
  /// ones keep their generalized momenta (M u)_F with Simbody's mass matrix:
  ///   M_FF du_F = -M_FC du_C.
  /// Returns the generalized impulse M (u+ - u-), in the order of GetU.
  Eigen::VectorXd ApplyJump(SimTK::State& s,
                            const Eigen::VectorXd& u_minus,
                            const std::vector<bool>& constrained,
                            const Eigen::VectorXd& u_target) const {
    sys_.system.realize(s, SimTK::Stage::Position);
    SimTK::Matrix Ms;
    sys_.matter.calcM(s, Ms);
    const auto N = static_cast<Eigen::Index>(u_index_.size());
    Eigen::MatrixXd M(N, N);
    for (Eigen::Index i = 0; i < N; ++i) {
      for (Eigen::Index j = 0; j < N; ++j) {
        M(i, j) = Ms(u_index_[static_cast<std::size_t>(i)], u_index_[static_cast<std::size_t>(j)]);
      }
    }
    std::vector<Eigen::Index> F, C;
    for (Eigen::Index i = 0; i < N; ++i) {
      (constrained[static_cast<std::size_t>(i)] ? C : F).push_back(i);
    }
    Eigen::VectorXd du = Eigen::VectorXd::Zero(N);
    for (Eigen::Index c : C) du[c] = u_target[c] - u_minus[c];
    Eigen::MatrixXd M_FF(F.size(), F.size());
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(F.size()));
    for (std::size_t a = 0; a < F.size(); ++a) {
      for (std::size_t b = 0; b < F.size(); ++b) {
        M_FF(Index(a), Index(b)) = M(F[a], F[b]);
      }
      for (Eigen::Index c : C) rhs[Index(a)] -= M(F[a], c) * du[c];
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(M_FF);
    if (ldlt.info() != Eigen::Success) std::abort();  // SPD mass matrix: broken invariant
    const Eigen::VectorXd du_F = ldlt.solve(rhs);
    for (std::size_t a = 0; a < F.size(); ++a) du[F[a]] = du_F[Index(a)];
    const Eigen::VectorXd u_plus = u_minus + du;
    SimTK::Vector& su = s.updU();
    for (std::size_t i = 0; i < u_index_.size(); ++i) su[u_index_[i]] = u_plus[Index(i)];
    sys_.system.realize(s, SimTK::Stage::Velocity);
    return M * du;
  }

  /// The plastic (rate_after = 0) or restitutive impulse at hinge k; fills `e`.
  void HingeImpulse(SimTK::State& s, std::size_t k, double rate_after, HingeEvent& e) {
    sys_.system.realize(s, SimTK::Stage::Velocity);
    const math::Vec3 w_minus = HubAngularVelocity_B(sys_, s);
    const Eigen::VectorXd u_minus = GetU(s);
    Eigen::VectorXd u_target = u_minus;
    u_target[Index(kHubU + k)] = rate_after;
    const Eigen::VectorXd impulse =
        ApplyJump(s, u_minus, ConstrainedMask(s, static_cast<int>(k)), u_target);
    e.t = s.getTime();
    e.panel = static_cast<int>(k);
    e.angle = sys_.pins[k].getOneQ(s, 0);
    e.rate_before = u_minus[Index(kHubU + k)];
    e.rate_after = sys_.pins[k].getOneU(s, 0);
    e.impulse = impulse[Index(kHubU + k)];
    e.w_jump_B = HubAngularVelocity_B(sys_, s) - w_minus;
    // The work of the impulsive torque pair, -lambda (u- + u+) / 2 = (M^-1)_kk lambda^2 / 2
    // (restitution: (1 - e^2) times the plastic loss). It is the kinetic energy lost unless
    // a prescribed hinge moves: its drive then does impulsive work too.
    e.energy_dissipated = -0.5 * e.impulse * (e.rate_before + e.rate_after);
  }

  void RecordEvent(const SimTK::State& s, const HingeEvent& e, std::vector<bool> free_before) {
    run_.events.push_back(e);
    Eigen::VectorXd angles(Index(n_));
    for (std::size_t k = 0; k < n_; ++k) angles[Index(k)] = sys_.pins[k].getOneQ(s, 0);
    run_.event_hinge_angles.push_back(angles);
    run_.event_free_hinges.push_back(std::move(free_before));
  }

  // ---- witness events ------------------------------------------------------------------

  bool Active(const SimTK::State& s, const Witness& w) const {
    return w.enabled && Moving(s, w.panel);
  }

  double Theta(const SimTK::State& s, std::size_t k) const { return sys_.pins[k].getOneQ(s, 0); }

  /// The state integrated from `start` to t (restarted integration at the same accuracy).
  const SimTK::State& Probe(const SimTK::State& start, double t) {
    if (t <= start.getTime()) return start;
    probe_->initialize(start);
    ++run_.stats.location_integrations;
    while (probe_->getTime() < t) {
      probe_->stepTo(t, t);
      ThrowIfOver(*probe_);
    }
    return probe_->getState();
  }

  /// Root in (t_lo, t_hi] of f along the trajectory from `start` (f(t_lo) = f_lo < 0 <=
  /// f_hi = f(t_hi)): the bracket's end where f >= 0, kEventTimeTolerance wide.
  double LocateRoot(const SimTK::State& start,
                    double t_lo,
                    double f_lo,
                    double t_hi,
                    double f_hi,
                    const std::function<double(const SimTK::State&)>& f) {
    if (f_lo >= 0.0) return t_lo;
    if (f_hi <= 0.0) return t_hi;
    auto g = [&](double t) { return f(Probe(start, t)); };
    const auto done = [](double lo, double hi) {
      return hi - lo <= kEventTimeTolerance * std::max(1.0, std::abs(hi));
    };
    std::uintmax_t iterations = kMaxLocateIterations;
    const std::pair<double, double> bracket =
        boost::math::tools::toms748_solve(g, t_lo, t_hi, f_lo, f_hi, done, iterations);
    return g(bracket.second) >= 0.0 ? bracket.second : bracket.first;
  }

  /// Whether witness w, armed with value w.value at the step's start, has crossed when its
  /// value is v: past zero, or onto zero from below.
  static bool Crossed(const Witness& w, double v) {
    return w.armed && (v > 0.0 || (v == 0.0 && w.value < 0.0));
  }

  /// Checks the witnesses over the step (prev_, cur]; if one crossed, locates the first
  /// crossing, applies it (and any simultaneous ones) and restarts there.
  bool HandleWitnesses(const SimTK::State& cur) {
    struct Crossing {
      std::size_t witness;
      double t;
    };
    std::vector<Crossing> crossings;
    for (std::size_t i = 0; i < witnesses_.size(); ++i) {
      const Witness& w = witnesses_[i];
      if (!Active(cur, w)) continue;
      const double v = w.Value(Theta(cur, w.panel));
      auto f = [this, i](const SimTK::State& s) {
        return witnesses_[i].Value(Theta(s, witnesses_[i].panel));
      };
      if (Crossed(w, v)) {
        crossings.push_back({i, LocateRoot(prev_, prev_.getTime(), w.value, cur.getTime(), v, f)});
      } else if (!w.armed && w.after_rebound && v >= 0.0 && prev_is_restart_) {
        // The step jumped over a whole bounce: look for the interval inside it.
        const double t_a = prev_.getTime();
        const double t_b = cur.getTime();
        for (int j = 1; j < kBounceProbes; ++j) {
          const double t = t_a + (t_b - t_a) * j / kBounceProbes;
          const double fv = f(Probe(prev_, t));
          if (fv < 0.0) {
            crossings.push_back({i, LocateRoot(prev_, t, fv, t_b, v, f)});
            break;
          }
        }
      }
    }
    if (crossings.empty()) return false;
    const Crossing* first = &crossings.front();
    for (const Crossing& c : crossings) {
      const double tol = 2.0 * kEventTimeTolerance * std::max(1.0, std::abs(c.t));
      if (c.t < first->t - tol ||
          (c.t <= first->t + tol && witnesses_[c.witness].type < witnesses_[first->witness].type)) {
        first = &c;
      }
    }
    SimTK::State s = Probe(prev_, first->t);
    LocateContinuous(prev_, s);
    ApplyWitness(s, first->witness);
    // Simultaneous crossings: armed witnesses that have crossed by this instant (the rule
    // of Crossed; a hinge released here on its stop is not pressed into it yet).
    for (bool more = true; more;) {
      more = false;
      for (std::size_t i = 0; i < witnesses_.size(); ++i) {
        const Witness& w = witnesses_[i];
        if (!Active(s, w)) continue;
        if (Crossed(w, w.Value(Theta(s, w.panel)))) {
          ApplyWitness(s, i);
          more = true;
        }
      }
    }
    Restart(s);
    return true;
  }

  /// Applies witness i's event to the state s at its crossing.
  void ApplyWitness(SimTK::State& s, std::size_t i) {
    Witness& w = witnesses_[i];
    const std::size_t k = w.panel;
    const schedule::FreeDrive& d = profile_.hinges[k].drive;
    const std::vector<bool> free_before = FreeMask(s);
    HingeEvent e;
    if (w.type == Witness::Type::kLatch && options_.compliant_latch.stiffness > 0.0) {
      // The compliant latch engages: no impulse.
      e.kind = HingeEvent::Kind::kLatch;
      e.t = s.getTime();
      e.panel = static_cast<int>(k);
      e.angle = Theta(s, k);
      e.rate_before = e.rate_after = sys_.pins[k].getOneU(s, 0);
      const double inertia = 1.0 / InverseMassEntry(s, k);
      sys_.latch_dampers[k].setDamping(s,
                                       2.0 * options_.compliant_latch.damping_ratio *
                                           std::sqrt(options_.compliant_latch.stiffness * inertia));
      sys_.latch_stops[k].enable(s);
      sys_.latch_dampers[k].enable(s);
      DisableWitnesses(k);
      RecordEvent(s, e, free_before);
      Latched(s, k);
      return;
    }
    const double rate = sys_.pins[k].getOneU(s, 0);
    bool lock = true;
    double rate_after = 0.0;
    switch (w.type) {
      case Witness::Type::kJam:
        e.kind = HingeEvent::Kind::kJam;
        break;
      case Witness::Type::kLatch:
        e.kind = HingeEvent::Kind::kLatch;
        break;
      case Witness::Type::kStopMax:
      case Witness::Type::kStopMin:
        rate_after = -d.stops.restitution * rate;
        if (std::abs(rate_after) < schedule::kRestSpeed) {
          e.kind = HingeEvent::Kind::kRest;
          rate_after = 0.0;
        } else {
          e.kind = HingeEvent::Kind::kStop;
          lock = false;
        }
        break;
    }
    HingeImpulse(s, k, rate_after, e);
    RecordEvent(s, e, free_before);
    if (lock) {
      sys_.pins[k].lock(s);
      DisableWitnesses(k);
      if (e.kind == HingeEvent::Kind::kLatch) Latched(s, k);
      return;
    }
    // A rebound: this witness re-arms once the hinge has left the stop; limit the steps to
    // see the next impact.
    w.armed = false;
    w.after_rebound = true;
    sys_.system.realize(s, SimTK::Stage::Acceleration);
    const double v = w.direction * sys_.pins[k].getOneU(s, 0);     // < 0: leaving
    const double a = w.direction * sys_.pins[k].getOneUDot(s, 0);  // > 0: pushed back
    w.bounce_time = a > 0.0 ? 2.0 * std::abs(v) / a : kInf;
  }

  void DisableWitnesses(std::size_t k) {
    for (Witness& w : witnesses_) {
      if (w.panel == k) w.enabled = false;
    }
  }

  /// Hinge k latched at s's time: record it and release the hinges that wait for it.
  void Latched(SimTK::State& s, std::size_t k) {
    const double t = s.getTime();
    if (std::isnan(run_.latch_times[k])) run_.latch_times[k] = t;
    for (std::size_t j = 0; j < n_; ++j) {
      const HingePlan& plan = profile_.hinges[j];
      if (plan.kind != HingePlan::Kind::kFree || released_[j]) continue;
      const schedule::Release& r = plan.drive.release;
      if (r.kind != schedule::Release::Kind::kAfterLatch || r.panel != static_cast<int>(k))
        continue;
      if (r.delay <= 0.0) {
        Release(s, j);
      } else {
        time_events_.push_back({t + r.delay, TimeEvent::kRelease, j});
        SortTimeEvents();
        sys_.clock.segment_end = NextTimeEvent();
      }
    }
  }

  /// (M^-1)_kk with M Simbody's mass matrix restricted to the free mobilities and hinge k.
  double InverseMassEntry(const SimTK::State& s, std::size_t k) const {
    sys_.system.realize(s, SimTK::Stage::Position);
    SimTK::Matrix Ms;
    sys_.matter.calcM(s, Ms);
    const std::vector<bool> c = ConstrainedMask(s, -1);
    std::vector<int> idx;
    Eigen::Index kk = -1;
    for (std::size_t i = 0; i < u_index_.size(); ++i) {
      if (!c[i] || i == kHubU + k) {
        if (i == kHubU + k) kk = static_cast<Eigen::Index>(idx.size());
        idx.push_back(u_index_[i]);
      }
    }
    const auto m = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd M(m, m);
    for (Eigen::Index a = 0; a < m; ++a) {
      for (Eigen::Index b = 0; b < m; ++b) {
        M(a, b) = Ms(idx[static_cast<std::size_t>(a)], idx[static_cast<std::size_t>(b)]);
      }
    }
    return M.inverse()(kk, kk);
  }

  // ---- flips and spin-axis crossings -----------------------------------------------------

  FlipValue Flip(const SimTK::State& s) const {
    const math::Mat3 J_B = SystemInertia_B(sys_, s);
    const math::Vec3 H_B = Momentum_B(sys_, s);
    const analysis::SpinAxisRole r = analysis::LocateSpinAxis(J_B, spin_axis_B_);
    return {H_B.dot(r.axis_B), r.role == analysis::AxisRole::kIntermediate};
  }

  /// cos(angle between the body spin axis and h_N).
  double SpinCosine(const SimTK::State& s) const {
    const math::Vec3 H_B = Momentum_B(sys_, s);
    return spin_axis_B_.dot(H_B) / H_B.norm();
  }

  /// Locates flips and spin-axis crossings between a and b (b on a's trajectory).
  void LocateContinuous(const SimTK::State& a, const SimTK::State& b) {
    const double t_a = a.getTime();
    const double t_b = b.getTime();
    if (t_b <= t_a) return;
    if (options_.locate_flips) {
      const FlipValue fa = Flip(a);
      const FlipValue fb = Flip(b);
      if (fa.intermediate && fb.intermediate && (fa.g < 0.0) != (fb.g < 0.0)) {
        const double sign = fa.g < 0.0 ? 1.0 : -1.0;  // makes the function rise through 0
        auto f = [this, sign](const SimTK::State& s) { return sign * Flip(s).g; };
        const double t = LocateRoot(a, t_a, sign * fa.g, t_b, sign * fb.g, f);
        const SimTK::State& st = Probe(a, t);
        if (analysis::IsFlip(SystemInertia_B(sys_, st), spin_axis_B_, Momentum_B(sys_, st))) {
          run_.flip_times.push_back(t);
        }
      }
    }
    if (options_.spin_axis_angles.empty()) return;
    const double ca = SpinCosine(a);
    const double cb = SpinCosine(b);
    for (double angle : options_.spin_axis_angles) {
      const double c = std::cos(angle);
      const double va = ca - c;
      const double vb = cb - c;
      if ((va < 0.0) == (vb < 0.0)) continue;
      const double sign = va < 0.0 ? 1.0 : -1.0;
      auto f = [this, sign, c](const SimTK::State& s) { return sign * (SpinCosine(s) - c); };
      const double t = LocateRoot(a, t_a, sign * va, t_b, sign * vb, f);
      run_.spin_axis_crossings.push_back({angle, t, va >= 0.0});
    }
  }

  // ---- the main integration ------------------------------------------------------------

  /// The step (prev_, cur] had no event: cur becomes prev_; witnesses re-arm.
  void Advance(const SimTK::State& cur) {
    bool limits_changed = false;
    for (Witness& w : witnesses_) {
      if (!Active(cur, w)) continue;
      w.value = w.Value(Theta(cur, w.panel));
      if (!w.armed && w.value < 0.0) {
        w.armed = true;
        if (w.after_rebound) limits_changed = true;
        w.after_rebound = false;
      }
    }
    prev_ = cur;
    prev_is_restart_ = false;
    if (limits_changed) main_->setMaximumStepSize(MaxStep());
  }

  /// The step-size limit while a rebound is pending (see kBounceStepFraction).
  double MaxStep() const {
    double h = kInf;
    for (const Witness& w : witnesses_) {
      if (w.enabled && w.after_rebound && !w.armed) {
        h = std::min(h, kBounceStepFraction * w.bounce_time);
      }
    }
    return h;
  }

  /// Restarts the main integration at s.
  void Restart(const SimTK::State& s) {
    main_->setMaximumStepSize(MaxStep());
    main_->initialize(s);
    prev_ = main_->getState();
    prev_is_restart_ = true;
    for (Witness& w : witnesses_) {
      if (Active(prev_, w)) w.value = w.Value(Theta(prev_, w.panel));
    }
    ++run_.stats.restarts;
  }

  const schedule::Profile& profile_;
  const std::vector<double>& grid_;
  math::Vec3 spin_axis_B_;
  SimbodyFreeHingeOptions options_;
  FreeSystem sys_;
  // Made once the system is built: the main integration, and the restarted integrations
  // that locate events and crossings.
  std::unique_ptr<SimTK::RungeKuttaMersonIntegrator> main_;
  std::unique_ptr<SimTK::RungeKuttaMersonIntegrator> probe_;
  model::HingedBody body_;
  std::size_t n_ = 0;
  double t0_ = 0.0;
  Eigen::VectorXd angle0_;
  std::vector<bool> released_;
  std::vector<TimeEvent> time_events_;
  std::vector<Witness> witnesses_;
  std::vector<int> u_index_;  // Simbody u index of hub (6) and pins, in panel order
  SimTK::State prev_;
  bool prev_is_restart_ = false;
  math::Vec3 h_N0_ = math::Vec3::Zero();
  SimbodyFreeHingeRun run_;
};

void CheckInputs(const schedule::Profile& profile,
                 const std::vector<double>& grid,
                 const math::Vec3& spin_axis_B,
                 const SimbodyFreeHingeOptions& options) {
  if (!profile.is_hinge_profile()) {
    throw std::invalid_argument(profile.source +
                                ": the free-hinge cross-check needs a hinge profile (hinges:)");
  }
  // The Simbody model has the regularized friction law only (a Coulomb stick needs the
  // holding torque's events, which it does not model).
  for (std::size_t k = 0; k < profile.hinges.size(); ++k) {
    const schedule::HingePlan& h = profile.hinges[k];
    if (h.kind == schedule::HingePlan::Kind::kFree && schedule::IsCoulomb(h.drive.friction)) {
      throw std::invalid_argument(
          profile.source + ": hinges." + profile.model.hinged.panels[k].name +
          ".free.friction: exact Coulomb friction (no regularization_speed_deg_s) is not "
          "modelled by the Simbody cross-check (rule: cross-check a profile with the "
          "regularized law)");
    }
  }
  if (!(options.accuracy > 0.0 && options.accuracy < 1.0)) {
    throw std::invalid_argument("crosscheck: accuracy = " + Exact(options.accuracy) +
                                ": must be in (0, 1)");
  }
  const CompliantLatch& c = options.compliant_latch;
  if (!(c.stiffness >= 0.0 && std::isfinite(c.stiffness))) {
    throw std::invalid_argument("crosscheck: compliant_latch.stiffness = " + Exact(c.stiffness) +
                                ": must be finite and >= 0");
  }
  if (!(c.damping_ratio > 0.0 && std::isfinite(c.damping_ratio))) {
    throw std::invalid_argument("crosscheck: compliant_latch.damping_ratio = " +
                                Exact(c.damping_ratio) + ": must be finite and > 0");
  }
  for (double a : options.spin_axis_angles) {
    if (!(a > 0.0 && a < SimTK::Pi)) {
      throw std::invalid_argument("crosscheck: spin_axis_angles: " + Exact(a) +
                                  " rad: must be in (0, pi)");
    }
  }
  if (!(std::abs(spin_axis_B.norm() - 1.0) < 1e-9)) {
    throw std::invalid_argument("crosscheck: the spin axis must be a unit vector");
  }
  if (grid.empty()) throw std::invalid_argument("crosscheck: empty output grid");
  const double t0 = profile.t_begin();
  const double t1 = profile.t_end();
  if (std::abs(grid.front() - t0) > SameTime(t0) || grid.back() > t1 + SameTime(t1) ||
      !std::is_sorted(grid.begin(), grid.end())) {
    throw std::invalid_argument(
        "crosscheck: the output grid must be ascending, start at t_begin and end by t_end of " +
        profile.source);
  }
}

}  // namespace

SimbodyFreeHingeRun RunSimbodyFreeHinges(const schedule::Profile& profile,
                                         const std::vector<double>& grid,
                                         const math::Vec3& spin_axis_B,
                                         const SimbodyFreeHingeOptions& options) {
  CheckInputs(profile, grid, spin_axis_B, options);
  Runner runner(profile, grid, spin_axis_B, options);
  return runner.Run();
}

Eigen::MatrixXd SimbodyMassMatrix(const model::HingedBody& body,
                                  const Eigen::VectorXd& hinge_angles) {
  const model::HingedBody valid = model::ValidatedHingedBody(body, "SimbodyMassMatrix");
  const std::size_t n = valid.panels.size();
  if (hinge_angles.size() != static_cast<Eigen::Index>(n)) {
    throw std::invalid_argument("SimbodyMassMatrix: " + std::to_string(hinge_angles.size()) +
                                " hinge angles for " + std::to_string(n) + " panels");
  }
  FreeSystem sys;
  AddHingedBodies(sys, valid, "SimbodyMassMatrix");
  SimTK::State s = sys.system.realizeTopology();
  sys.system.realizeModel(s);
  for (std::size_t k = 0; k < n; ++k) {
    sys.pins[k].setOneQ(s, 0, hinge_angles[static_cast<Eigen::Index>(k)]);
  }
  sys.system.realize(s, SimTK::Stage::Position);
  SimTK::Matrix Ms;
  sys.matter.calcM(s, Ms);
  std::vector<int> idx;
  for (int j = 0; j < kHubU; ++j) idx.push_back(sys.hub.getFirstUIndex(s) + j);
  for (std::size_t k = 0; k < n; ++k) idx.push_back(sys.pins[k].getFirstUIndex(s));
  const auto N = static_cast<Eigen::Index>(idx.size());
  Eigen::MatrixXd M(N, N);
  for (Eigen::Index i = 0; i < N; ++i) {
    for (Eigen::Index j = 0; j < N; ++j) {
      M(i, j) = Ms(idx[static_cast<std::size_t>(i)], idx[static_cast<std::size_t>(j)]);
    }
  }
  return M;
}

}  // namespace deploysim::crosscheck
