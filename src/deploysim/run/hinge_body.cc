#include "deploysim/run/hinge_body.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/linear_stability.h"
#include "deploysim/analysis/work_estimate.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/shape_integrate.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/math/units.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/run/mission.h"
#include "deploysim/run/run_recorder.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::run {

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

}  // namespace

model::HingedBody HingeBody::BodyOf(const schedule::Profile& profile, const std::string& where) {
  const model::Model& model = profile.model;
  if (model.kind != model::ModelKind::kHinged) {
    throw std::invalid_argument(where + ": hinges: the model is not a hinged model");
  }
  return model::ValidatedHingedBody(model.hinged,
                                    model.source.empty() ? where + ": model" : model.source);
}

HingeBody::HingeBody(const CompiledRun& run, const RunOptions& options)
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
      release_time_(static_cast<std::size_t>(n_), std::numeric_limits<double>::infinity()),
      done_(static_cast<std::size_t>(n_), 0),
      hold_(static_cast<std::size_t>(n_)),
      unheld_t_(static_cast<std::size_t>(n_), std::numeric_limits<double>::quiet_NaN()),
      unheld_offset_(static_cast<std::size_t>(n_), 0.0),
      last_impact_(static_cast<std::size_t>(n_), -std::numeric_limits<double>::infinity()),
      windows_(sys_.Breakpoints(t0_, t1_)),
      shape_method_(analysis::NumericalMethodOf(profile_.integrator.method)) {
  // Releases: time-based ones now; after-latch ones when their latch happens. Every free
  // hinge is at rest (held) until its release.
  const Eigen::VectorXd& theta0 =
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
  // The stiffest hinge rate times the run's length: the radians its swing can cover.
  project_energy_ =
      profile_.has_free_hinge() && run.work().hinge_rate * (t1_ - t0_) > kProjectionRadians;
}

void HingeBody::Start(RunState& st) {
  st_ = &st;
  st.y = HingeInitialState(profile_, sys_, body_);
  // Modal coordinates are in the shape state from the start: the appendages at their
  // angles, at the hinges' initial rates.
  if (sys_.modal_count() > 0) {
    const Eigen::VectorXd& theta0 =
        profile_.model.configuration(profile_.initial.configuration).hinge_angles;
    const Eigen::VectorXd rates0 =
        plans_rate0_.size() > 0 ? plans_rate0_ : Eigen::VectorXd::Zero(theta0.size());
    st.x = sys_.ShapeState(t0_, st.y.H_B, theta0, rates0);
  }
  st.out.latch_times.assign(static_cast<std::size_t>(n_), std::numeric_limits<double>::quiet_NaN());
}

RunSample HingeBody::Current(dynamics::Side side) const {
  RunSample o = SampleOf(st_->t, st_->y.H_B, st_->y.q_NB, st_->x, side);
  o.work = st_->work;
  return o;
}

// A state of the free-hinge path (shape state x), or of the rigid path (no hinge free:
// x empty).
RunSample HingeBody::SampleOf(double t,
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
  return o;
}

PhaseInfo HingeBody::Describe(double t) const {
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
bool HingeBody::ChangesDue(RunState& st, bool started) {
  st_ = &st;
  bool changed = false;
  for (int k = 0; k < n_; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    if (!(release_time_[i] <= st_->t) || sys_.IsFree(k) || done_[i]) continue;
    const RunSample before = Current(dynamics::Side::kRight);
    if (!changed && started) st_->rec().ClosePhase(before);
    changed = true;
    // A hinge the profile starts moving (initial.hinge_rates) is released at t0 with it.
    const Eigen::VectorXd& rate0 = plans_rate0_;
    const double rate = st_->t == t0_ && rate0.size() > 0 ? rate0[k] : 0.0;
    const bool coulomb = schedule::IsCoulomb(plans_[i].drive.friction);
    const double lambda =
        coulomb && rate == 0.0 ? sys_.HoldingTorque(k, st_->t, st_->y.H_B, st_->x) : 0.0;
    st_->x = sys_.Free(k, st_->t, st_->y.H_B, st_->x, rate);
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

bool HingeBody::StartSlip(int k, double lambda) {
  const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  if (std::abs(lambda) > d.friction.torque) {
    sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
    return false;
  }
  // Friction holds it where it was released.
  const double angle = Current(dynamics::Side::kRight).theta[k];
  st_->x = sys_.Lock(k, angle, st_->x);
  StartHold(k, Hold::Kind::kStick, 0);
  Record(HingeEvent::Kind::kStick, k, angle);
  return true;
}

void HingeBody::StartHold(int k, Hold::Kind kind, int side) {
  const std::size_t i = static_cast<std::size_t>(k);
  const schedule::Friction& f = plans_[i].drive.friction;
  const double mu = schedule::IsCoulomb(f) ? f.torque : 0.0;
  Hold h;
  h.kind = kind;
  h.side = side;
  h.offset = 1e-9 * (mu + std::abs(sys_.HoldingTorque(k, st_->t, st_->y.H_B, st_->x)));
  if (unheld_t_[i] == st_->t) h.offset = std::max(h.offset, 10.0 * unheld_offset_[i]);
  hold_[i] = h;
}

void HingeBody::Record(HingeEvent::Kind kind,
                       int k,
                       double angle,
                       const FreeHingeSystem::Impulse* imp) {
  HingeEvent ev;
  ev.kind = kind;
  ev.t = st_->t;
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
  st_->out.hinge_events.push_back(ev);
}

bool HingeBody::AnyHeld() const {
  for (const Hold& h : hold_) {
    if (h.kind != Hold::Kind::kNone) return true;
  }
  return false;
}

double HingeBody::HoldMargin(int k, double t, const Vec3& H_B, const Eigen::VectorXd& x) const {
  const Hold& h = hold_[static_cast<std::size_t>(k)];
  const schedule::Friction& f = plans_[static_cast<std::size_t>(k)].drive.friction;
  const double mu = schedule::IsCoulomb(f) ? f.torque : 0.0;
  const double lambda = sys_.HoldingTorque(k, t, H_B, x);
  // A stop holds one way (the max stop with lambda <= 0), friction both ways up to mu.
  const double need = h.kind == Hold::Kind::kStop ? h.side * lambda : std::abs(lambda);
  return need - mu - h.offset;
}

void HingeBody::CountInstant() {
  if (st_->t != instant_t_) {
    instant_t_ = st_->t;
    instant_events_ = 0;
  }
  if (++instant_events_ > kMaxEventsAtOneInstant) {
    throw std::runtime_error(
        where_ + ": hinge events repeat without end at t = " + math::FormatNumber(st_->t) + " s (" +
        std::to_string(kMaxEventsAtOneInstant) +
        " at one instant): the run cannot advance (please report it with "
        "the profile)");
  }
}

void HingeBody::Unhold(int k, HingeEvent::Kind kind) {
  const std::size_t i = static_cast<std::size_t>(k);
  const RunSample before = Current(dynamics::Side::kRight);
  const double lambda = sys_.HoldingTorque(k, st_->t, st_->y.H_B, st_->x);
  st_->rec().ClosePhase(before);
  Record(kind, k, before.theta[k]);
  unheld_t_[i] = st_->t;
  unheld_offset_[i] = hold_[i].offset;
  hold_[i] = Hold();
  st_->x = sys_.Free(k, st_->t, st_->y.H_B, st_->x, 0.0);
  if (schedule::IsCoulomb(plans_[i].drive.friction)) sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
  OpenPhase(Current(dynamics::Side::kRight));
}

// A rigid segment's end: the next release, or t1.
double HingeBody::NextChange(double t, double t1) const {
  double t_next = t1;
  for (double r : release_time_) {
    if (r > t) t_next = std::min(t_next, r);
  }
  return t_next;
}

// A free segment's end: also the next prescribed window boundary.
double HingeBody::NextFreeChange(double t, double t1) const {
  const double t_next = NextChange(t, t1);
  // windows_ ascends: the first boundary after t (a rotor may have 10^4 windows).
  const auto w = std::upper_bound(windows_.begin(), windows_.end(), t);
  return w != windows_.end() ? std::min(t_next, *w) : t_next;
}

const FreeHingeSystem::Snapshot& HingeBody::SnapOf(const integrators::ShapeState& y) const {
  if (!(memo_valid_ && y.t == memo_state_.t && y.H_B == memo_state_.H_B &&
        y.x.size() == memo_state_.x.size() && y.x == memo_state_.x)) {
    memo_snap_ = sys_.Snap(y.t, y.H_B, y.x);
    memo_state_ = y;
    memo_valid_ = true;
    memo_jdot_valid_ = false;
  }
  return memo_snap_;
}

Mat3 HingeBody::JdotOf(const integrators::ShapeState& y) const {
  SnapOf(y);  // the memo's state
  if (!memo_jdot_valid_) {
    memo_jdot_ = sys_.InertiaRate(y.t, y.H_B, y.x);
    memo_jdot_valid_ = true;
  }
  return memo_jdot_;
}

// The terminal events of the free hinges (latches, jams, stops) and the spin-axis events,
// each with its rate (a hinge angle's is the hinge rate).
void HingeBody::FreeEvents(std::vector<integrators::ShapeEventFunction>& events,
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
  SpinAxisEvents(events, tags);
}

void HingeBody::SpinAxisEvents(std::vector<integrators::ShapeEventFunction>& events,
                               std::vector<EventTag>& tags) const {
  const Vec3 s = st_->s;
  auto h_dot = [this](const integrators::ShapeState& y) {
    return Vec3(y.H_B.cross(SnapOf(y).w_NB_B));
  };
  events.push_back({"flip",
                    [this, s](const integrators::ShapeState& y) {
                      return analysis::FlipFunction(SnapOf(y).J_B, s, y.H_B);
                    },
                    0, false, options_.refine_events,
                    [this, s, h_dot](const integrators::ShapeState& y) {
                      return analysis::FlipFunctionRate(SnapOf(y).J_B, JdotOf(y), s, y.H_B,
                                                        h_dot(y));
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
SegmentEnd HingeBody::FreeSegment(RunState& st, double t_next) {
  st_ = &st;
  memo_valid_ = false;  // the free set may have changed
  std::vector<integrators::ShapeEventFunction> events;
  std::vector<EventTag> tags;
  FreeEvents(events, tags);
  auto point = [this](const integrators::ShapeState& y) {
    const Vec3 Hdot = y.H_B.cross(sys_.Snap(y.t, y.H_B, y.x).w_NB_B);
    const double rate = st_->s.dot(Hdot) / st_->M;
    return AxisPoint{y.t, st_->s.dot(y.H_B) / st_->M, rate, rate, y.H_B, Hdot, Hdot};
  };
  // The shape state carries the work of the free hinges' sources and of the prescribed
  // drives over this segment (FreeHingeSystem::kLedgerTerms accumulators, from 0).
  constexpr int kTerms = FreeHingeSystem::kLedgerTerms;
  const Eigen::Index nx = st_->x.size();
  auto work_at = [this, nx](const integrators::ShapeState& y) {
    WorkLedger w = st_->work;
    w.damper += y.x[nx];
    w.friction += y.x[nx + 1];
    w.motor += y.x[nx + 2];
    w.drive += y.x[nx + 3];
    return w;
  };
  integrators::ShapeState ys;
  ys.t = st_->t;
  ys.H_B = st_->y.H_B;
  ys.q_NB = st_->y.q_NB;
  ys.x.resize(nx + kTerms);
  ys.x << st_->x, Eigen::VectorXd::Zero(kTerms);
  AxisPoint prev = point(ys);
  const FreeHingeSystem::Snapshot start_snap = sys_.Snap(ys.t, ys.H_B, ys.x);
  const double e_start = start_snap.kinetic_energy + start_snap.spring_energy;
  const auto project = [this, e_start](integrators::ShapeState& y) { Project(y, e_start); };
  const integrators::ShapeIntegrationResult r = integrators::IntegrateShape(
      shape_method_, st_->settings, sys_, ys, t_next, *st_->grid, &st_->next_out, events,
      [&](const integrators::ShapeState& y) {
        RunSample o = SampleOf(y.t, y.H_B, y.q_NB, y.x, dynamics::Side::kRight);
        o.work = work_at(y);
        // On a prescribed rate jump at the segment's end the sample holds the state after
        // it: the drive's impulsive work there counts.
        if (y.t >= t_next && t_next < t1_) {
          o.work.drive +=
              o.kinetic - SampleOf(y.t, y.H_B, y.q_NB, y.x, dynamics::Side::kLeft).kinetic;
        }
        st_->rec().Sample(o);
      },
      [&](const integrators::ShapeState& y) {
        st_->rec().Progress(y.t);
        const AxisPoint p = point(y);
        st_->rec().SpinAxisStep(prev, p);
        prev = p;
      },
      project);
  st_->AddStats(r.stats);
  if (st_->settings.step <= 0.0 || r.next_step > 0.0) st_->settings.step = r.next_step;
  for (const integrators::ShapeEvent& e : r.events) {
    const EventTag& tag = tags[static_cast<std::size_t>(e.index)];
    if (tag.what == EventTag::What::kFlip) {
      st_->rec().CandidateFlip(e.t, sys_.Snap(e.t, e.state.H_B, e.state.x).J_B, e.state.H_B);
    } else if (tag.what == EventTag::What::kCross45) {
      st_->rec().Crossing45(e.t);
    } else if (tag.what == EventTag::What::kSeparatrix) {
      st_->rec().SeparatrixCrossing(e.t, e.direction);
    }
  }
  if (st_->Stopped(r.termination, r.message)) return SegmentEnd::kStopped;
  st_->rec().SpinAxisCos(Cos(r.final_state.H_B));
  // The segment's end, or the event; a segment shorter than the driver's time
  // resolution (kTimeEps) counts as reached, so the loop always advances.
  st_->t = r.stopped_at_event ? r.final_state.t : t_next;
  st_->y.t = st_->t;
  st_->y.H_B = r.final_state.H_B;
  st_->y.q_NB = r.final_state.q_NB;
  st_->work = work_at(r.final_state);
  st_->x = r.final_state.x.head(nx);
  if (!r.stopped_at_event) return SegmentEnd::kReached;
  OnHingeEvent(tags[static_cast<std::size_t>(r.events.back().index)], r.stuck);
  return SegmentEnd::kHingeEvent;
}

// Energy projection (Hairer, Lubich and Wanner, Geometric Numerical Integration, 2nd ed.,
// section IV.4), in a run whose hinges swing through more than kProjectionRadians: each
// step's end (theta_f, p_f) is moved onto E = E_start + W, W the sources' work the
// ledger integrates over the segment. A Runge-Kutta method's energy error grows with
// every step (an undamped 1e6 N m/rad spring over 84000 periods: 2.7e-7 of E at rtol
// 1e-11); projected, it stays at the steps' own error (5e-13). H_B and the attitude are
// kept. Shorter swings keep their energy to the tolerance unprojected (every shipped
// profile).
void HingeBody::Project(integrators::ShapeState& y, double e_start) const {
  const int m = sys_.free_count();
  if (!project_energy_ || m == 0) return;
  const auto energy = [&](const Eigen::VectorXd& x) {
    const FreeHingeSystem::Snapshot s = sys_.Snap(y.t, y.H_B, x);
    return s.kinetic_energy + s.spring_energy;
  };
  const FreeHingeSystem::Snapshot s = sys_.Snap(y.t, y.H_B, y.x);
  const double excess = s.kinetic_energy + s.spring_energy -
                        (e_start + y.x.tail<FreeHingeSystem::kLedgerTerms>().sum());
  // The move that changes E by -excess and is smallest in units of the tolerance of each
  // component (tol_i: atol scale + rtol |y_i|, as the error control weighs them):
  // delta_i = -excess tol_i^2 g_i / sum (tol_j g_j)^2, g = dE/d(theta_f, p_f) (theta'_f
  // for p_f; a central difference for theta_f). The move is at most kProjectionReach
  // tolerances long: a projection of the steps' error, never a jump (a larger excess,
  // where the hinges are nearly at rest, is taken up over the next steps).
  const integrators::Tolerances& tol = st_->settings.tolerances;
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
    w[m + a] = tol.atol * st_->M + tol.rtol * std::abs(y.x[m + a]);
  }
  const double reach2 = g.cwiseProduct(w).squaredNorm();
  if (!(reach2 > 0.0) || !std::isfinite(excess)) return;
  const double cap = kProjectionReach * std::sqrt(reach2);
  const double take = std::clamp(excess, -cap, cap);
  y.x.head(2 * m) -= (take / reach2) * w.cwiseProduct(w).cwiseProduct(g);
}

// A located hinge event at st_->t: a lift-off or slip of a held hinge; the end of a slip; a
// latch, jam or stop of free hinge tag.a: the impulse; a lock (latch, jam, coming to
// rest) ends the phase and may start after-latch releases; a bounce does not.
void HingeBody::OnHingeEvent(const EventTag& tag, bool stuck) {
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
  st_->x[tag.a] = tag.angle;
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
  const FreeHingeSystem::Impulse imp = sys_.ApplyImpulse(st_->t, st_->y.H_B, st_->x, tag.a, target);
  st_->work.impacts -= imp.energy_dissipated;
  st_->work.drive += imp.drive_work;
  Record(kind, k, tag.angle, &imp);
  if (kind == HingeEvent::Kind::kStop) return;
  st_->rec().ClosePhase(before);
  st_->x = sys_.Lock(k, tag.angle, st_->x);
  st_->out.latch_times[static_cast<std::size_t>(k)] = st_->t;
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
        release_time_[static_cast<std::size_t>(j)] = st_->t + p.drive.release.delay;
      }
    }
  }
  OpenPhase(Current(dynamics::Side::kRight));
}

// Exact Coulomb friction brought free hinge tag.a to rest: the impulse that makes its rate
// exactly 0 (a rounding error of the located state), then held if friction can hold it
// (or if it could not leave rest the other way: `stuck`), else it slips back.
bool HingeBody::Sticks(const EventTag& tag, bool stuck) {
  const int k = sys_.free_hinges()[static_cast<std::size_t>(tag.a)];
  const schedule::FreeDrive& d = plans_[static_cast<std::size_t>(k)].drive;
  const RunSample before = Current(dynamics::Side::kRight);
  const FreeHingeSystem::Impulse imp = sys_.ApplyImpulse(st_->t, st_->y.H_B, st_->x, tag.a, 0.0);
  st_->work.impacts -= imp.energy_dissipated;
  st_->work.drive += imp.drive_work;
  const double angle = st_->x[tag.a];
  Eigen::VectorXd held = sys_.Lock(k, angle, st_->x);
  const double lambda = sys_.HoldingTorque(k, st_->t, st_->y.H_B, held);
  if (!stuck && std::abs(lambda) > d.friction.torque) {
    // It slips on, the way the holding torque pulls it (back, or on after a touch of 0).
    st_->x = sys_.Free(k, st_->t, st_->y.H_B, held, 0.0);
    sys_.SetSlip(k, lambda > 0.0 ? -1 : 1);
    return false;
  }
  st_->rec().ClosePhase(before);
  st_->x = held;
  StartHold(k, Hold::Kind::kStick, 0);
  Record(HingeEvent::Kind::kStick, k, angle, &imp);
  OpenPhase(Current(dynamics::Side::kRight));
  return true;
}

bool HingeBody::RestsOnStop(const EventTag& tag, double rebound) {
  const int k = sys_.free_hinges()[static_cast<std::size_t>(tag.a)];
  const schedule::Stops& st = plans_[static_cast<std::size_t>(k)].drive.stops;
  const double v = std::abs(rebound);
  // A rattle: the impacts come faster than one contact lasts, or the rebound would reach
  // the other stop within it.
  double& last = last_impact_[static_cast<std::size_t>(k)];
  const bool rattle = st_->t - last < schedule::kContactTime;
  last = st_->t;
  if (rattle || st.max_angle - st.min_angle < v * schedule::kContactTime) return true;
  // The acceleration pressing the hinge onto the stop, at rest there without friction.
  Eigen::VectorXd at_rest = st_->x;
  sys_.ApplyImpulse(st_->t, st_->y.H_B, at_rest, tag.a, 0.0);
  const int slip = sys_.slip(k);
  sys_.SetSlip(k, 0);
  const double press = tag.side * sys_.Acceleration(tag.a, st_->t, st_->y.H_B, at_rest);
  sys_.SetSlip(k, slip);
  if (!(press > 0.0)) return false;
  const double angle_tol =
      st_->settings.tolerances.atol + st_->settings.tolerances.rtol * std::abs(tag.angle);
  return v < schedule::kRestSpeed || 2.0 * v / press < schedule::kContactTime ||
         v * v / (2.0 * press) <= angle_tol;
}

analysis::SteadySpin HingeBody::Steady(const RunSample& start, const PhaseInfo& /*info*/) const {
  const Eigen::VectorXd x = sys_.ShapeState(start.t, start.H_B, start.theta, start.theta_dot);
  Eigen::VectorXd y(3 + x.size());
  y << start.H_B, x;
  // The phase lasts to the next window boundary of a prescribed hinge (beyond the run's
  // end too: a rotor held through the run is one phase however short the run).
  const double length = sys_.NextBreakpoint(start.t) - start.t;
  analysis::SteadySpin s = analysis::LinearizeSteadySpin(
      analysis::FlowOf(sys_, start.t, length, RotorPeriod(start.t), WindingHinges(), WindingAxes()),
      y);
  if (s.orbit_rotor >= 0) s.orbit_rotor_panel = sys_.free_hinges()[s.orbit_rotor];
  return s;
}

std::vector<math::Vec3> HingeBody::WindingAxes() const {
  std::vector<math::Vec3> out;
  const std::vector<int>& free = sys_.free_hinges();
  for (int a : WindingHinges()) {
    const model::Panel& p = body_.panels[static_cast<std::size_t>(free[a])];
    out.push_back(p.parent < 0 ? p.hinge_axis_B
                               : math::Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  }
  return out;
}

double HingeBody::RotorPeriod(double t) const {
  double rate = 0.0;
  for (const HingePlan& p : plans_) {
    if (p.kind != HingePlan::Kind::kPrescribed) continue;
    for (const schedule::HingeMove& mv : p.moves) {
      if (mv.kind == schedule::HingeMove::Kind::kRate && mv.t_begin <= t && t < mv.t_end)
        rate = std::max(rate, std::abs(mv.rate));
    }
  }
  return rate > 0.0 ? math::kTwoPi / rate : 0.0;
}

std::vector<int> HingeBody::WindingHinges() const {
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

}  // namespace deploysim::run
