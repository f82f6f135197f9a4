#include "deploysim/crosscheck/free_hinge_crosscheck.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "deploysim/integrators/integrate.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"

namespace deploysim::crosscheck {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kQuarterPi = 0.78539816339744831;

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) { return math::FormatSignificant(x); }

/// The events after the start (releases at t_begin are the initial condition).
std::vector<run::HingeEvent> AfterStart(const std::vector<run::HingeEvent>& e, double t_begin) {
  std::vector<run::HingeEvent> out;
  for (const run::HingeEvent& ev : e) {
    if (ev.kind == run::HingeEvent::Kind::kRelease && ev.t == t_begin) continue;
    out.push_back(ev);
  }
  return out;
}

TrajectoryDifference CompareSimbody(const SimbodyTrajectory& a, const SimbodyTrajectory& b) {
  run::Trajectory ta;
  ta.time = a.time;
  ta.H_B = a.H_B;
  ta.q_NB = a.q_NB;
  ta.w_NB_B = a.w_NB_B;
  return CompareTrajectories(ta, b);
}

std::vector<double> Crossings45(const SimbodyFreeHingeRun& run) {
  std::vector<double> t;
  for (const SpinAxisCrossing& c : run.spin_axis_crossings) {
    if (std::abs(c.angle - kQuarterPi) < 1e-15) t.push_back(c.t);
  }
  return t;
}

}  // namespace

EventComparison CompareEvents(const std::vector<run::HingeEvent>& a_all,
                              const std::vector<double>& a_latch_times,
                              const std::vector<run::HingeEvent>& b_all,
                              const std::vector<double>& b_latch_times,
                              double t_begin) {
  const std::vector<run::HingeEvent> a = AfterStart(a_all, t_begin);
  const std::vector<run::HingeEvent> b = AfterStart(b_all, t_begin);
  EventComparison c;
  c.same_sequence = a.size() == b.size();
  double impulse_scale = 0.0, w_scale = 0.0, energy_scale = 0.0;
  for (const run::HingeEvent& e : b) {
    impulse_scale = std::max(impulse_scale, std::abs(e.impulse));
    w_scale = std::max(w_scale, e.w_jump_B.norm());
    energy_scale = std::max(energy_scale, std::abs(e.energy_dissipated));
  }
  for (std::size_t i = 0; c.same_sequence && i < a.size(); ++i) {
    if (a[i].kind != b[i].kind || a[i].panel != b[i].panel) {
      c.same_sequence = false;
      break;
    }
    c.max_time = std::max(c.max_time, std::abs(a[i].t - b[i].t));
    if (impulse_scale > 0.0) {
      c.max_impulse =
          std::max(c.max_impulse, std::abs(a[i].impulse - b[i].impulse) / impulse_scale);
    }
    if (w_scale > 0.0) {
      c.max_w_jump = std::max(c.max_w_jump, (a[i].w_jump_B - b[i].w_jump_B).norm() / w_scale);
    }
    if (energy_scale > 0.0) {
      c.max_energy = std::max(
          c.max_energy, std::abs(a[i].energy_dissipated - b[i].energy_dissipated) / energy_scale);
    }
  }
  if (!c.same_sequence) {
    c.max_time = c.max_impulse = c.max_w_jump = c.max_energy = kInf;
  }
  for (std::size_t k = 0; k < std::min(a_latch_times.size(), b_latch_times.size()); ++k) {
    const double ta = a_latch_times[k], tb = b_latch_times[k];
    if (std::isnan(ta) && std::isnan(tb)) continue;
    c.max_latch_time =
        std::max(c.max_latch_time, std::isnan(ta) != std::isnan(tb) ? kInf : std::abs(ta - tb));
  }
  return c;
}

double MaxCrossingDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return kInf;
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    m = std::max(m, std::abs(a[i] - b[i]) / std::max(std::abs(b[i]), 1e-300));
  }
  return m;
}

FreeHingeCrosscheckResult RunFreeHingeCrosscheck(const schedule::Profile& profile,
                                                 const FreeHingeCrosscheckOptions& options) {
  if (!profile.is_hinge_profile()) {
    throw std::invalid_argument(profile.source + ": RunFreeHingeCrosscheck: not a hinge profile");
  }
  if (!(options.accuracy > 0.0 && options.accuracy < 1.0)) {
    throw std::invalid_argument("crosscheck: accuracy = " + math::FormatNumber(options.accuracy) +
                                ": must be in (0, 1)");
  }
  if (!(options.own_error_accuracy >= 0.0 && options.own_error_accuracy < 1.0)) {
    throw std::invalid_argument(
        "crosscheck: own-error accuracy = " + math::FormatNumber(options.own_error_accuracy) +
        ": must be 0 (none) or in (0, 1)");
  }
  schedule::Profile p = profile;
  if (options.t_end) {
    if (!(*options.t_end > p.t_begin() && *options.t_end <= p.t_end())) {
      throw std::invalid_argument(p.source + ": crosscheck end time " +
                                  math::FormatNumber(*options.t_end) + " s: must lie in (" +
                                  math::FormatNumber(p.t_begin()) + ", " +
                                  math::FormatNumber(p.t_end()) + "] s");
    }
    p.until = *options.t_end;
  }
  if (options.output_dt) {
    if (!(*options.output_dt > 0.0 && std::isfinite(*options.output_dt))) {
      throw std::invalid_argument(
          "crosscheck: output dt = " + math::FormatNumber(*options.output_dt) +
          ": must be finite and > 0");
    }
    p.output.dt = *options.output_dt;
  }

  FreeHingeCrosscheckResult r;
  r.accuracy = options.accuracy;
  r.reduced = run::RunMission(p);
  if (r.reduced.termination != integrators::Termination::kReachedEnd) {
    throw std::runtime_error(p.source + ": reduced model: integration " + r.reduced.message);
  }
  const std::vector<double>& grid = r.reduced.trajectory.time;
  SimbodyFreeHingeOptions so;
  so.accuracy = options.accuracy;
  so.spin_axis_angles = {kQuarterPi};
  r.simbody = RunSimbodyFreeHinges(p, grid, r.reduced.spin_axis_B, so);
  r.difference = CompareTrajectories(r.reduced.trajectory, r.simbody.trajectory);
  r.max_flip_difference = MaxFlipDifference(r.reduced.flip_times, r.simbody.flip_times);
  r.events = CompareEvents(r.reduced.hinge_events, r.reduced.latch_times, r.simbody.events,
                           r.simbody.latch_times, p.t_begin());
  r.simbody_45_crossings = Crossings45(r.simbody);
  r.max_45_crossing_difference =
      MaxCrossingDifference(r.reduced.spin_axis_45_crossings, r.simbody_45_crossings);
  const run::Trajectory& tr = r.reduced.trajectory;
  const double E0 = r.simbody.total_energy.front();
  for (std::size_t i = 0; i < tr.size(); ++i) {
    r.max_energy_difference =
        std::max(r.max_energy_difference,
                 std::abs(tr.energy[i] + tr.energy_spring[i] - r.simbody.total_energy[i]) / E0);
  }
  if (options.own_error_accuracy > 0.0) {
    SimbodyFreeHingeOptions lo = so;
    lo.accuracy = options.own_error_accuracy;
    const SimbodyFreeHingeRun loose = RunSimbodyFreeHinges(p, grid, r.reduced.spin_axis_B, lo);
    r.has_reference = true;
    r.own_error_accuracy = options.own_error_accuracy;
    r.simbody_self = CompareSimbody(loose.trajectory, r.simbody.trajectory);
    r.simbody_self_flip_difference = MaxFlipDifference(loose.flip_times, r.simbody.flip_times);
    r.simbody_self_events = CompareEvents(loose.events, loose.latch_times, r.simbody.events,
                                          r.simbody.latch_times, p.t_begin());
    r.simbody_self_45_crossing_difference =
        MaxCrossingDifference(Crossings45(loose), r.simbody_45_crossings);
  }
  r.profile = std::move(p);
  return r;
}

CrosscheckResult AsCrosscheckResult(const FreeHingeCrosscheckResult& r) {
  CrosscheckResult c;
  c.profile = r.profile;
  c.accuracy = r.accuracy;
  c.reduced = r.reduced;
  c.simbody.trajectory = r.simbody.trajectory;
  c.simbody.flip_times = r.simbody.flip_times;
  c.simbody.max_momentum_drift = r.simbody.max_momentum_drift;
  c.simbody.accuracy = r.simbody.accuracy;
  c.simbody.stats.steps = r.simbody.stats.steps;
  c.simbody.stats.attempts = r.simbody.stats.attempts;
  c.simbody.stats.realizations = r.simbody.stats.realizations;
  c.simbody.stats.restarts = r.simbody.stats.restarts;
  c.simbody.stats.wall_seconds = r.simbody.stats.wall_seconds;
  c.difference = r.difference;
  c.max_flip_difference = r.max_flip_difference;
  return c;
}

std::string FormatFreeHingeCrosscheckTable(const FreeHingeCrosscheckResult& r) {
  std::ostringstream o;
  const schedule::Profile& p = r.profile;
  const bool self = r.has_reference;
  // simbody_self NaN: not a figure Simbody's own-error run gives ("-").
  auto line = [&](const std::string& what, double value, double simbody_self) {
    char buf[200];
    if (self) {
      std::snprintf(buf, sizeof(buf), "  %-42s %-12s %s\n", what.c_str(), Num(value).c_str(),
                    std::isnan(simbody_self) ? "-" : Num(simbody_self).c_str());
    } else {
      std::snprintf(buf, sizeof(buf), "  %-42s %s\n", what.c_str(), Num(value).c_str());
    }
    o << buf;
  };
  o << "Simbody cross-check (free hinges): " << p.name << " (" << p.source << ")\n";
  o << "  t = " << Num(p.t_begin()) << " .. " << Num(p.t_end()) << " s, "
    << r.reduced.trajectory.size() << " samples every " << Num(p.output.dt) << " s\n";
  o << "  reduced: " << p.integrator.method << " rtol " << Num(p.integrator.rtol) << " atol "
    << Num(p.integrator.atol) << "; Simbody: RungeKuttaMerson accuracy " << Num(r.accuracy);
  if (self) o << " (its own error: accuracy " << Num(r.own_error_accuracy) << " against it)";
  o << "\n\n";
  if (self) {
    char buf[200];
    std::snprintf(buf, sizeof(buf), "  %-42s %-12s %s\n", "reduced vs Simbody", "max diff",
                  "Simbody's own");
    o << buf;
  } else {
    o << "  reduced vs Simbody                         max difference\n";
  }
  line("H_B, relative to |H|", r.difference.max_H_B_relative, r.simbody_self.max_H_B_relative);
  line("attitude [rad]", r.difference.max_attitude, r.simbody_self.max_attitude);
  line("angular velocity w_NB_B [rad/s]", r.difference.max_w, r.simbody_self.max_w);
  line("total energy T + V, relative to E(t0)", r.max_energy_difference, kNaN);
  const std::size_t events = AfterStart(r.simbody.events, p.t_begin()).size();
  if (r.events.same_sequence) {
    line("event times [s] (" + std::to_string(events) + " events)", r.events.max_time,
         r.simbody_self_events.max_time);
    line("latch times [s]", r.events.max_latch_time, r.simbody_self_events.max_latch_time);
    line("impulses, relative", r.events.max_impulse, r.simbody_self_events.max_impulse);
    line("hub w jumps, relative", r.events.max_w_jump, r.simbody_self_events.max_w_jump);
    line("energy dissipated, relative", r.events.max_energy, r.simbody_self_events.max_energy);
  } else {
    o << "  events (reduced / Simbody): " << AfterStart(r.reduced.hinge_events, p.t_begin()).size()
      << " / " << events << "  MISMATCH (kinds, panels or counts differ)\n";
  }
  if (r.reduced.flip_times.size() == r.simbody.flip_times.size()) {
    line("flip times [s] (" + std::to_string(r.simbody.flip_times.size()) + " flips)",
         r.max_flip_difference, r.simbody_self_flip_difference);
  } else {
    o << "  flip counts (reduced / Simbody): " << r.reduced.flip_times.size() << " / "
      << r.simbody.flip_times.size() << "  MISMATCH\n";
  }
  if (!r.simbody_45_crossings.empty() || !r.reduced.spin_axis_45_crossings.empty()) {
    line("45-deg spin-axis crossings, relative (" + std::to_string(r.simbody_45_crossings.size()) +
             ")",
         r.max_45_crossing_difference, r.simbody_self_45_crossing_difference);
  }
  o << "\n  own errors\n";
  line("Simbody momentum drift |dh_N|/|h_N|", r.simbody.max_momentum_drift, kNaN);
  line("reduced momentum drift |dh_N|/|h_N|", r.reduced.max_h_N_drift, kNaN);
  o << "\n  cost\n";
  o << "  reduced wall time [s]                      " << Num(r.reduced.wall_seconds) << "  ("
    << r.reduced.stats.steps << " steps)\n";
  o << "  Simbody wall time [s]                      " << Num(r.simbody.stats.wall_seconds) << "  ("
    << r.simbody.stats.steps << " steps)\n";
  return o.str();
}

}  // namespace deploysim::crosscheck
