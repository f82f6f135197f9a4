// RunHingeMission: the hybrid run of a hinge profile (issue 9, DESIGN.md 2.7).
//
// The run is cut into segments at every time the system changes: a release, a latch, a
// jam, a stop impact, a panel coming to rest, a prescribed window's start or end. Between
// them the hinges are each locked, prescribed or free:
//   - with free hinges, integrators::IntegrateShape (Lie-group RKMK on SO(3) x R^2m)
//     advances (R_NB, theta_f, p_f), stopping at the first located latch, jam or stop;
//   - with none, the body is a hub with locked and prescribed hinges: the existing
//     rigid-body path (integrators::Integrate with the FreeHingeSystem as the inertia
//     source), so `exact` uses the closed form wherever nothing moves.
// At an event the impulse of DESIGN.md 2.7 changes only p_k (H_B and every other p_j
// unchanged); the event is reported with its impulse, the hub's angular-velocity jump and
// the energy dissipated. The stage table is made of the phases between these changes.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/dynamics/rigid_body.h"
#include "deploysim/integrators/shape_integrate.h"
#include "deploysim/math/cubic_hermite.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/schedule/free_hinge_system.h"

namespace deploysim::analysis {

namespace {

using math::Mat3;
using math::Vec3;
using schedule::FreeHingeSystem;
using schedule::HingePlan;

constexpr double kCos45 = 0.70710678118654752440;

/// A window [begin, end) of the output grid's indices.
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

/// First index of `grid` whose time is > t.
std::size_t FirstAfter(const integrators::OutputTimes& grid, double t) {
  std::size_t lo = 0, hi = grid.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (grid.at(mid) <= t) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

/// What the output and the reports need of one state.
struct Sample {
  double t = 0.0;
  Vec3 H_B = Vec3::Zero();
  math::Quat q_NB = math::Quat::Identity();
  Vec3 w = Vec3::Zero();
  Mat3 J_B = Mat3::Zero();
  Vec3 h_rel_B = Vec3::Zero();
  double kinetic = 0.0;
  double spring = 0.0;
  Eigen::VectorXd theta, theta_dot;
};

std::string PanelName(const schedule::Profile& p, int k) {
  return p.model.hinged.panels[static_cast<std::size_t>(k)].name;
}

/// The spring energy of every hinge with a free plan at angles theta.
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

}  // namespace

MissionResult RunHingeMission(const schedule::Profile& profile,
                              SampleSink& sink,
                              const std::function<void(double)>& progress,
                              const HingeRunOptions& options) {
  const auto wall0 = std::chrono::steady_clock::now();
  schedule::ValidateProfile(profile);
  const std::string where = profile.source.empty() ? profile.name : profile.source;
  const model::Model& model = profile.model;
  if (model.kind != model::ModelKind::kHinged) {
    throw std::invalid_argument(where + ": hinges: the model is not a hinged model");
  }
  const model::HingedBody body = model::ValidatedHingedBody(
      model.hinged, model.source.empty() ? where + ": model" : model.source);
  const int n = static_cast<int>(body.panels.size());
  const Eigen::VectorXd theta0 = model.configuration(profile.initial.configuration).hinge_angles;
  const std::vector<HingePlan>& plans = profile.hinges;
  const double t0 = profile.t_begin();
  const double t1 = profile.t_end();

  bool any_free = false;
  for (const HingePlan& p : plans) any_free = any_free || p.kind == HingePlan::Kind::kFree;
  const std::string& method = profile.integrator.method;
  const std::string shape_method = method == "exact" ? "rkmk-rkf78" : method;
  if (any_free && !integrators::IsShapeMethod(shape_method)) {
    std::string list;
    for (const std::string& m : integrators::ShapeMethodNames()) list += m + ", ";
    throw std::invalid_argument(where + ": integrator.method = " + method +
                                ": free hinges need a Lie-group method (rule: one of " + list +
                                "exact)");
  }

  FreeHingeSystem sys(body, plans, theta0);

  MissionResult out;
  out.profile = profile;
  out.latch_times.assign(static_cast<std::size_t>(n), std::numeric_limits<double>::quiet_NaN());

  // Initial state: every free hinge at rest (held until its release).
  integrators::State y;
  y.t = t0;
  y.q_NB = math::ValidateUnitQuaternion(profile.initial.q_NB, where + ": initial attitude");
  const dynamics::InertiaSample s0 = sys.Evaluate(t0);
  y.H_B = profile.initial.H_B ? *profile.initial.H_B
                              : Vec3(s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B);
  const Vec3 h_N0 = y.q_NB * y.H_B;
  const double M = h_N0.norm();
  if (!(M > 0.0)) throw std::invalid_argument(where + ": initial: zero angular momentum");
  const Vec3 spin_axis_B = InitialSpinAxis(s0.J_B, y.H_B);
  out.spin_axis_B = spin_axis_B;

  // Releases: time-based ones now; after-latch ones when their latch happens.
  std::vector<double> release_time(static_cast<std::size_t>(n),
                                   std::numeric_limits<double>::infinity());
  std::vector<double> release_angle = std::vector<double>(theta0.data(), theta0.data() + n);
  for (int k = 0; k < n; ++k) {
    const HingePlan& p = plans[static_cast<std::size_t>(k)];
    if (p.kind != HingePlan::Kind::kFree) continue;
    if (p.drive.release.kind == schedule::Release::Kind::kAtStart) {
      release_time[static_cast<std::size_t>(k)] = t0;
    } else if (p.drive.release.kind == schedule::Release::Kind::kAtTime) {
      release_time[static_cast<std::size_t>(k)] = std::max(t0, p.drive.release.time);
    }
  }
  std::vector<char> done(static_cast<std::size_t>(n), 0);  // released and locked again
  // Prescribed window boundaries: segment ends (phase boundaries).
  std::vector<double> windows = sys.Breakpoints(t0, t1);

  integrators::IntegratorSettings settings;
  settings.step = profile.integrator.step;
  settings.tolerances = {profile.integrator.rtol, profile.integrator.atol};
  settings.max_step = profile.integrator.max_step;
  const auto rigid_stepper = MakeStepper(method);

  const integrators::UniformGridTimes full_grid(t0, t1, profile.output.dt);
  const WindowTimes no_samples(full_grid, 0, 0);
  const integrators::OutputTimes& grid =
      options.sample_trajectory ? static_cast<const integrators::OutputTimes&>(full_grid)
                                : no_samples;
  std::size_t next_out = 0;
  // The largest spin-axis angle: min of s . H_B / |H| over the segment ends and the
  // located extrema (zeros of its rate s . (H_B x w)).
  double min_cos = spin_axis_B.dot(y.H_B) / M;
  auto track_angle = [&](const Vec3& H_B) {
    min_cos = std::min(min_cos, spin_axis_B.dot(H_B) / H_B.norm());
  };

  // ---- Output -------------------------------------------------------------------------
  Trajectory block;
  bool have_principal = false;
  Mat3 principal_J = Mat3::Zero();
  math::PrincipalAxes principal{};
  bool in_window = false;
  auto add_sample = [&](const Sample& s) {
    if (!have_principal || s.J_B != principal_J) {
      principal = math::PrincipalDecomposition(s.J_B);
      principal_J = s.J_B;
      have_principal = true;
    }
    const Vec3 h_N = s.q_NB * s.H_B;
    block.time.push_back(s.t);
    block.H_B.push_back(s.H_B);
    block.w_NB_B.push_back(s.w);
    block.q_NB.push_back(s.q_NB);
    block.J_B.push_back(s.J_B);
    block.principal_moments.push_back(principal.moments);
    block.h_rel_B.push_back(s.h_rel_B);
    block.h_N.push_back(h_N);
    block.energy.push_back(s.kinetic);
    block.energy_rigid.push_back(0.5 * s.w.dot(s.J_B * s.w));
    block.energy_spring.push_back(s.spring);
    block.euler_313.push_back(Euler313RelativeToMomentum(s.q_NB, h_N));
    block.spin_axis_angle.push_back(
        std::acos(std::clamp(spin_axis_B.dot(s.H_B) / s.H_B.norm(), -1.0, 1.0)));
    block.hinge_angles.push_back(s.theta);
    block.hinge_rates.push_back(s.theta_dot);
    out.max_h_N_drift = std::max(out.max_h_N_drift, (h_N - h_N0).norm() / M);
    const bool danger = LocateSpinAxis(principal, spin_axis_B).role == AxisRole::kIntermediate;
    if (danger && !in_window) out.danger_windows.push_back({s.t, s.t});
    if (danger) out.danger_windows.back().t_end = s.t;
    in_window = danger;
    if (block.size() == kSampleBlock) {
      sink.Append(block);
      block = Trajectory();
    }
  };
  // A state of the free-hinge path (shape state x), or of the rigid path (no hinge free:
  // x empty).
  auto make_sample = [&](double ts, const Vec3& H_B, const math::Quat& q_NB,
                         const Eigen::VectorXd& x, dynamics::Side side) {
    const FreeHingeSystem::Snapshot snap = sys.Snap(ts, H_B, x, side);
    Sample o;
    o.t = ts;
    o.H_B = H_B;
    o.q_NB = q_NB;
    o.w = snap.w_NB_B;
    o.J_B = snap.J_B;
    o.h_rel_B = snap.h_rel_B;
    o.kinetic = snap.kinetic_energy;
    o.theta = snap.theta;
    o.theta_dot = snap.theta_dot;
    o.spring = SpringEnergyAll(plans, snap.theta);
    return o;
  };
  auto shape_sample = [&](const integrators::ShapeState& s) {
    return make_sample(s.t, s.H_B, s.q_NB, s.x, dynamics::Side::kRight);
  };
  const Eigen::VectorXd no_shape;
  auto rigid_sample = [&](const integrators::State& s, dynamics::Side side) {
    return make_sample(s.t, s.H_B, s.q_NB, no_shape, side);
  };

  // ---- Phases (the stage table) ------------------------------------------------------
  struct Phase {
    double t_begin = 0.0;
    Sample start;
    std::string name, law;
    bool rigid = false, dissipative = false;
  };
  auto describe = [&](double t) {
    Phase ph;
    std::string free_list, moving;
    for (int k : sys.free_hinges()) {
      free_list += (free_list.empty() ? "" : ", ") + PanelName(profile, k);
      ph.dissipative = ph.dissipative || Dissipates(plans[static_cast<std::size_t>(k)].drive);
    }
    for (int k = 0; k < n; ++k) {
      const HingePlan& p = plans[static_cast<std::size_t>(k)];
      if (p.kind != HingePlan::Kind::kPrescribed) continue;
      for (const schedule::HingeMove& mv : p.moves) {
        if (mv.t_begin <= t && t < mv.t_end) {
          moving += (moving.empty() ? "" : ", ") + PanelName(profile, k);
          break;
        }
      }
    }
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
  };
  std::vector<Phase> phases;
  std::vector<Sample> phase_ends;
  auto open_phase = [&](const Sample& start) {
    Phase ph = describe(start.t);
    ph.t_begin = start.t;
    ph.start = start;
    if (!phases.empty() && phases.back().t_begin == start.t) {
      phases.back() = ph;  // zero-length phase: replaced
      phase_ends.pop_back();
      return;
    }
    phases.push_back(ph);
  };
  auto close_phase = [&](const Sample& end) { phase_ends.push_back(end); };

  // ---- Events common to both paths ---------------------------------------------------
  std::vector<integrators::Event> flips_and_45;  // from the rigid path (index 0 flip, 1: 45)
  auto record_flip = [&](double t, const Mat3& J_B, const Vec3& H_B) {
    if (IsFlip(J_B, spin_axis_B, H_B)) out.flip_times.push_back(t);
  };

  double last_reported = -1.0;
  auto report = [&](double t) {
    if (!progress) return;
    const double f = (t - t0) / (t1 - t0);
    if (f - last_reported >= 0.01 || f >= 1.0) {
      last_reported = f;
      progress(f);
    }
  };

  // ---- The run -----------------------------------------------------------------------
  integrators::State state = y;  // H_B, q_NB at `t`
  Eigen::VectorXd x;             // shape state of the free set
  Eigen::VectorXd theta_now = theta0, rate_now = Eigen::VectorXd::Zero(n);
  double t = t0;
  bool first_phase = true;
  integrators::Statistics stats;
  integrators::Termination termination = integrators::Termination::kReachedEnd;
  std::string message = integrators::ToString(termination);

  auto current_sample = [&](dynamics::Side side) {
    if (sys.free_count() > 0) {
      integrators::ShapeState s;
      s.t = t;
      s.H_B = state.H_B;
      s.q_NB = state.q_NB;
      s.x = x;
      return shape_sample(s);
    }
    return rigid_sample(state, side);
  };

  while (true) {
    // Releases due now.
    bool changed = false;
    for (int k = 0; k < n; ++k) {
      if (release_time[static_cast<std::size_t>(k)] <= t && !sys.IsFree(k) &&
          !done[static_cast<std::size_t>(k)]) {
        const Sample before = current_sample(dynamics::Side::kRight);
        if (!changed && !first_phase) close_phase(before);
        changed = true;
        // The new free hinge starts at rest; the others keep theta and p.
        const int m_old = sys.free_count();
        sys.Free(k);
        const Eigen::VectorXd full = sys.ShapeState(t, state.H_B, before.theta, before.theta_dot);
        Eigen::VectorXd nx(2 * (m_old + 1));
        nx.head(m_old) = x.head(m_old);
        nx[m_old] = full[m_old];
        nx.segment(m_old + 1, m_old) = x.tail(m_old);
        nx[2 * m_old + 1] = full[2 * m_old + 1];
        x = nx;
        release_angle[static_cast<std::size_t>(k)] = before.theta[k];
        release_time[static_cast<std::size_t>(k)] = std::numeric_limits<double>::infinity();
        HingeEvent ev;
        ev.kind = HingeEvent::Kind::kRelease;
        ev.t = t;
        ev.panel = k;
        ev.angle = before.theta[k];
        out.hinge_events.push_back(ev);
      }
    }
    if (first_phase || changed) {
      const Sample start = current_sample(dynamics::Side::kRight);
      if (first_phase) out.energy_initial = start.kinetic + start.spring;
      open_phase(start);
      first_phase = false;
    }
    if (!(t < t1)) break;

    // The segment's end: the next release, prescribed window boundary, or t1.
    double t_next = t1;
    for (double r : release_time) {
      if (r > t) t_next = std::min(t_next, r);
    }
    for (double w : windows) {
      if (w > t) t_next = std::min(t_next, w);
    }
    const std::size_t out_end = FirstAfter(grid, t_next);

    if (sys.free_count() > 0) {
      // ---- Free hinges: the shape integrator, to the first latch / jam / stop ---------
      const std::vector<int> free = sys.free_hinges();
      const int m = static_cast<int>(free.size());
      std::vector<integrators::ShapeEventFunction> events;
      struct EventInfo {
        HingeEvent::Kind kind;
        int a;           // free index
        double angle;    // the angle of the event
        double e = 0.0;  // restitution (stops)
      };
      std::vector<EventInfo> info;
      for (int a = 0; a < m; ++a) {
        const int k = free[static_cast<std::size_t>(a)];
        const schedule::FreeDrive& d = plans[static_cast<std::size_t>(k)].drive;
        const double theta_r = release_angle[static_cast<std::size_t>(k)];
        const std::string name = PanelName(profile, k);
        if (d.latch.enabled) {
          const double sense = d.latch.angle >= theta_r ? 1.0 : -1.0;
          if (d.latch.jam_fraction > 0.0) {
            const double jam = theta_r + d.latch.jam_fraction * (d.latch.angle - theta_r);
            events.push_back({"jam " + name,
                              [a, sense, jam](const integrators::ShapeState& s) {
                                return sense * (s.x[a] - jam);
                              },
                              1, true});
            info.push_back({HingeEvent::Kind::kJam, a, jam});
          }
          const double latch = d.latch.angle;
          events.push_back({"latch " + name,
                            [a, sense, latch](const integrators::ShapeState& s) {
                              return sense * (s.x[a] - latch);
                            },
                            1, true});
          info.push_back({HingeEvent::Kind::kLatch, a, latch});
        }
        if (std::isfinite(d.stops.max_angle)) {
          const double mx = d.stops.max_angle;
          events.push_back({"stop max " + name,
                            [a, mx](const integrators::ShapeState& s) { return s.x[a] - mx; }, 1,
                            true});
          info.push_back({HingeEvent::Kind::kStop, a, mx, d.stops.restitution});
        }
        if (std::isfinite(d.stops.min_angle)) {
          const double mn = d.stops.min_angle;
          events.push_back({"stop min " + name,
                            [a, mn](const integrators::ShapeState& s) { return mn - s.x[a]; }, 1,
                            true});
          info.push_back({HingeEvent::Kind::kStop, a, mn, d.stops.restitution});
        }
      }
      // Events finished on partial steps (to the steps' accuracy), or, in outcome-only runs,
      // on the dense output alone (its own error, ~1e-13 of the state for rkmk-rkf78:
      // latch times shift by ~1e-12 s, and each event costs ~100 fewer evaluations).
      for (integrators::ShapeEventFunction& ev : events) ev.refine = options.refine_events;
      const std::size_t first_free_event = events.size();
      events.push_back({"flip",
                        [&](const integrators::ShapeState& s) {
                          return FlipFunction(sys.Snap(s.t, s.H_B, s.x).J_B, spin_axis_B, s.H_B);
                        },
                        0, false, options.refine_events});
      events.push_back({"spin axis 45 deg",
                        [&](const integrators::ShapeState& s) {
                          return kCos45 - spin_axis_B.dot(s.H_B) / s.H_B.norm();
                        },
                        0, false, options.refine_events});
      // The largest spin-axis angle: f = s . H_B / M and its rate at every accepted step's
      // end, a minimum of f inside a step from the cubic Hermite interpolant of f (no extra
      // right-hand sides; the error control keeps steps short against the nutation, as in
      // the sweep's outcome path).
      struct AnglePoint {
        double t, f, rate;
      };
      auto angle_point = [&](const integrators::ShapeState& s) {
        const Vec3 w = sys.Snap(s.t, s.H_B, s.x).w_NB_B;
        return AnglePoint{s.t, spin_axis_B.dot(s.H_B) / M, spin_axis_B.dot(s.H_B.cross(w)) / M};
      };
      integrators::ShapeState start_state;
      start_state.t = t;
      start_state.H_B = state.H_B;
      start_state.q_NB = state.q_NB;
      start_state.x = x;
      AnglePoint prev_point = angle_point(start_state);

      integrators::ShapeState ys;
      ys.t = t;
      ys.H_B = state.H_B;
      ys.q_NB = state.q_NB;
      ys.x = x;
      const integrators::ShapeIntegrationResult r = integrators::IntegrateShape(
          shape_method, settings, sys, ys, t_next, grid, &next_out, events,
          [&](const integrators::ShapeState& s) { add_sample(shape_sample(s)); },
          [&](const integrators::ShapeState& s) {
            report(s.t);
            const AnglePoint p = angle_point(s);
            if (prev_point.rate < 0.0 && p.rate > 0.0) {
              min_cos =
                  std::min(min_cos, math::CubicHermiteMinimum(prev_point.t, prev_point.f,
                                                              prev_point.rate, p.t, p.f, p.rate));
            }
            min_cos = std::min(min_cos, p.f);
            prev_point = p;
          });
      stats.steps += r.stats.steps;
      stats.rejected += r.stats.rejected;
      stats.evaluations += r.stats.evaluations;
      stats.dense_steps += r.stats.dense_steps;
      if (settings.step <= 0.0 || r.next_step > 0.0) settings.step = r.next_step;
      for (const integrators::ShapeEvent& e : r.events) {
        if (static_cast<std::size_t>(e.index) == first_free_event) {
          record_flip(e.t, sys.Snap(e.t, e.state.H_B, e.state.x).J_B, e.state.H_B);
        } else if (static_cast<std::size_t>(e.index) == first_free_event + 1) {
          out.spin_axis_45_crossings.push_back(e.t);
        }
      }
      if (r.termination != integrators::Termination::kReachedEnd) {
        termination = r.termination;
        message = r.message;
        break;
      }
      track_angle(r.final_state.H_B);
      // The segment's end, or the event; a segment shorter than the driver's time
      // resolution (kTimeEps) counts as reached, so the loop always advances.
      t = r.stopped_at_event ? r.final_state.t : t_next;
      state.t = t;
      state.H_B = r.final_state.H_B;
      state.q_NB = r.final_state.q_NB;
      x = r.final_state.x;
      if (r.stopped_at_event) {
        const integrators::ShapeEvent& e = r.events.back();
        const EventInfo& ei = info[static_cast<std::size_t>(e.index)];
        const int k = free[static_cast<std::size_t>(ei.a)];
        // Snap the hinge onto the event's angle (the located state is within the event
        // location tolerance of it).
        x[ei.a] = ei.angle;
        const Sample before = current_sample(dynamics::Side::kRight);
        HingeEvent ev;
        ev.t = t;
        ev.panel = k;
        ev.angle = ei.angle;
        const schedule::FreeDrive& d = plans[static_cast<std::size_t>(k)].drive;
        HingeEvent::Kind kind = ei.kind;
        // A stop at the latch angle is the latch.
        if (kind == HingeEvent::Kind::kStop && d.latch.enabled && d.latch.angle == ei.angle) {
          kind = HingeEvent::Kind::kLatch;
        }
        // Stuck: the panel could not leave the stop it just rebounded off (its rebound is
        // shorter than integrators::kMinLeaveStep): it rests there.
        if (r.stuck) kind = HingeEvent::Kind::kRest;
        double target = 0.0;
        if (kind == HingeEvent::Kind::kStop) target = -ei.e * before.theta_dot[k];
        const FreeHingeSystem::Impulse imp = sys.ApplyImpulse(t, state.H_B, x, ei.a, target);
        ev.rate_before = imp.rate_before;
        ev.rate_after = imp.rate_after;
        ev.impulse = imp.lambda;
        ev.w_jump_B = imp.w_jump_B;
        ev.energy_dissipated = imp.energy_dissipated;
        bool lock = kind != HingeEvent::Kind::kStop;  // latch, jam, rest
        if (kind == HingeEvent::Kind::kStop && std::abs(imp.rate_after) < schedule::kRestSpeed) {
          kind = HingeEvent::Kind::kRest;
          lock = true;
        }
        ev.kind = kind;
        out.hinge_events.push_back(ev);
        // A lock ends the phase (the set of free hinges changes); a bounce does not.
        if (lock) close_phase(before);
        if (lock) {
          // Remove hinge k's entries; the other momenta stay as they are.
          Eigen::VectorXd nx(2 * (m - 1));
          int j = 0;
          for (int a = 0; a < m; ++a) {
            if (a == ei.a) continue;
            nx[j] = x[a];
            nx[m - 1 + j] = x[m + a];
            ++j;
          }
          x = nx;
          sys.Lock(k, ei.angle);
          done[static_cast<std::size_t>(k)] = 1;
          out.latch_times[static_cast<std::size_t>(k)] = t;
          if (kind == HingeEvent::Kind::kLatch) {
            for (int j2 = 0; j2 < n; ++j2) {
              const HingePlan& p = plans[static_cast<std::size_t>(j2)];
              if (p.kind == HingePlan::Kind::kFree &&
                  p.drive.release.kind == schedule::Release::Kind::kAfterLatch &&
                  p.drive.release.panel == k) {
                release_time[static_cast<std::size_t>(j2)] = t + p.drive.release.delay;
              }
            }
          }
        }
        if (lock) open_phase(current_sample(dynamics::Side::kRight));
        continue;
      }
    } else {
      // ---- No free hinge: locked and prescribed hinges, the rigid-body path -----------
      const WindowTimes times(grid, next_out, out_end);
      integrators::EventFunction flip{"flip", [&](const integrators::State& s) {
                                        return FlipFunction(sys.Evaluate(s.t).J_B, spin_axis_B,
                                                            s.H_B);
                                      }};
      integrators::EventFunction cross45{"spin axis 45 deg", [&](const integrators::State& s) {
                                           return kCos45 - spin_axis_B.dot(s.H_B) / s.H_B.norm();
                                         }};
      integrators::EventFunction extremum{"spin axis extremum", [&](const integrators::State& s) {
                                            const dynamics::InertiaSample js = sys.Evaluate(s.t);
                                            const Vec3 w = js.J_inv_B * (s.H_B - js.h_rel_B);
                                            return spin_axis_B.dot(s.H_B.cross(w)) / M;
                                          }};
      const integrators::IntegrationResult r = integrators::Integrate(
          *rigid_stepper, settings, sys, state, t_next, times, {flip, cross45, extremum},
          [&](const integrators::State& s) { report(s.t); },
          [&](const integrators::State& s) {
            add_sample(
                rigid_sample(s, s.t >= t_next ? dynamics::Side::kLeft : dynamics::Side::kRight));
          });
      next_out = out_end;
      stats.steps += r.stats.steps;
      stats.rejected += r.stats.rejected;
      stats.evaluations += r.stats.evaluations;
      stats.dense_steps += r.stats.dense_steps;
      for (const integrators::Event& e : r.events) {
        if (e.index == 0) {
          record_flip(e.t, sys.Evaluate(e.t).J_B, e.state.H_B);
        } else if (e.index == 1) {
          out.spin_axis_45_crossings.push_back(e.t);
        } else {
          track_angle(e.state.H_B);
        }
      }
      if (r.termination != integrators::Termination::kReachedEnd) {
        termination = r.termination;
        message = r.message;
        break;
      }
      t = t_next;
      state = r.final_state;
      state.t = t;
      track_angle(state.H_B);
    }
    // A prescribed window boundary or a release time: a phase boundary.
    if (t < t1) {
      bool boundary = false;
      for (double w : windows) boundary = boundary || w == t;
      if (boundary) {
        close_phase(current_sample(dynamics::Side::kLeft));
        open_phase(current_sample(dynamics::Side::kRight));
      }
    }
  }
  // A run that stopped early: the remaining times get its last state.
  if (termination != integrators::Termination::kReachedEnd && options.sample_trajectory) {
    const Sample last = current_sample(dynamics::Side::kRight);
    while (next_out < grid.size()) {
      Sample s = last;
      s.t = grid.at(next_out++);
      add_sample(s);
    }
  }
  if (!block.time.empty()) sink.Append(block);
  const Sample final_sample = current_sample(dynamics::Side::kLeft);
  close_phase(final_sample);
  out.final_state = state;
  out.final_J_B = final_sample.J_B;
  out.energy_final = final_sample.kinetic + final_sample.spring;
  out.max_spin_axis_angle = std::acos(std::clamp(min_cos, -1.0, 1.0));
  if (!options.sample_trajectory) {
    out.max_h_N_drift = ((state.q_NB * state.H_B) - h_N0).norm() / M;
  }
  out.stats = stats;
  out.termination = termination;
  out.message = message;
  std::sort(out.flip_times.begin(), out.flip_times.end());

  // ---- Phase reports ----------------------------------------------------------------
  for (std::size_t i = 0; i < phases.size(); ++i) {
    const Phase& ph = phases[i];
    const Sample& end = phase_ends[std::min(i, phase_ends.size() - 1)];
    StageReport rep;
    rep.index = static_cast<int>(i);
    rep.name = ph.name;
    rep.law = ph.law;
    rep.t_begin = ph.t_begin;
    rep.t_end = i + 1 < phases.size() ? phases[i + 1].t_begin : end.t;
    rep.rigid = ph.rigid;
    const math::PrincipalAxes p = math::PrincipalDecomposition(end.J_B);
    rep.moments_end = p.moments;
    rep.spin_axis_end = LocateSpinAxis(end.J_B, spin_axis_B).role;
    const double two_T = end.w.dot(end.J_B * end.w);
    const double D = end.H_B.squaredNorm() / two_T;
    rep.separatrix_distance = (D - p.moments[1]) / (p.moments[2] - p.moments[0]);
    for (double tf : out.flip_times) {
      if (tf >= rep.t_begin && tf < rep.t_end) rep.observed_flips.push_back(tf);
    }
    rep.predicted_flip_half_period = std::numeric_limits<double>::infinity();
    if (rep.rigid) {
      SetRigidPrediction(rep, ph.start.J_B, ph.start.H_B, ph.start.q_NB, spin_axis_B);
    }
    SetRigidBodyCaveat(rep, ph.dissipative);
    out.stages.push_back(rep);
  }

  out.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return out;
}

}  // namespace deploysim::analysis
