#include "deploysim/crosscheck/crosscheck.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::crosscheck {

namespace {

// Times within this (relative to max(1, |t|)) are the same instant.
constexpr double kSameTime = 1e-9;

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) { return math::FormatSignificant(x); }

/// The project's number formatting (math/number_format.h) under a short local name.
constexpr auto& Exact = math::FormatNumber;

}  // namespace

TrajectoryDifference CompareTrajectories(const run::Trajectory& reduced,
                                         const SimbodyTrajectory& simbody) {
  if (reduced.size() != simbody.size() || reduced.size() == 0) {
    throw std::invalid_argument("crosscheck: the trajectories have " +
                                std::to_string(reduced.size()) + " and " +
                                std::to_string(simbody.size()) + " samples (must be equal, > 0)");
  }
  TrajectoryDifference d;
  const double M = reduced.H_B.front().norm();
  for (std::size_t i = 0; i < reduced.size(); ++i) {
    if (std::abs(reduced.time[i] - simbody.time[i]) >
        kSameTime * std::max(1.0, std::abs(reduced.time[i]))) {
      throw std::invalid_argument("crosscheck: sample " + std::to_string(i) +
                                  " is at t = " + Exact(reduced.time[i]) + " s and " +
                                  Exact(simbody.time[i]) + " s");
    }
    d.H_B_relative.push_back((reduced.H_B[i] - simbody.H_B[i]).norm() / M);
    d.attitude.push_back(math::AngleBetween(reduced.q_NB[i], simbody.q_NB[i]));
    d.w.push_back((reduced.w_NB_B[i] - simbody.w_NB_B[i]).norm());
    d.max_H_B_relative = std::max(d.max_H_B_relative, d.H_B_relative.back());
    d.max_attitude = std::max(d.max_attitude, d.attitude.back());
    d.max_w = std::max(d.max_w, d.w.back());
    d.w_scale = std::max(d.w_scale, simbody.w_NB_B[i].norm());
  }
  return d;
}

double MaxFlipDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

schedule::Profile TruncateProfile(const schedule::Profile& profile, double t_end) {
  const double t0 = profile.t_begin();
  const double t1 = profile.t_end();
  const double tol = kSameTime * std::max(1.0, std::abs(t1));
  if (!(t_end > t0 && t_end <= t1 + tol)) {
    throw std::invalid_argument(profile.source + ": crosscheck end time " + Exact(t_end) +
                                " s: must lie in (" + Exact(t0) + ", " + Exact(t1) + "] s");
  }
  schedule::Profile p = profile;
  p.stages.clear();
  for (const schedule::Stage& st : profile.stages) {
    schedule::Stage s = st;
    if (s.t_begin >= t_end - tol) break;
    if (s.t_end > t_end + tol) {
      if (!s.is_hold()) {
        throw std::invalid_argument(profile.source + ": crosscheck end time " + Exact(t_end) +
                                    " s falls inside the move stage '" + s.name + "' [" +
                                    Exact(s.t_begin) + ", " + Exact(s.t_end) +
                                    "] s; end inside a hold or on a stage end");
      }
      s.t_end = t_end;
    }
    p.stages.push_back(s);
  }
  schedule::ValidateProfile(p);
  return p;
}

CrosscheckResult RunCrosscheck(const schedule::Profile& profile, const CrosscheckOptions& options) {
  if (!(options.accuracy > 0.0 && options.accuracy < 1.0)) {
    throw std::invalid_argument("crosscheck: accuracy = " + Exact(options.accuracy) +
                                ": must be in (0, 1)");
  }
  schedule::Profile p = options.t_end ? TruncateProfile(profile, *options.t_end) : profile;
  if (p.mode == schedule::Mode::kGeometry) p.coupling = schedule::Coupling::kExact;
  if (options.output_dt) {
    if (!(*options.output_dt > 0.0 && std::isfinite(*options.output_dt))) {
      throw std::invalid_argument("crosscheck: output dt = " + Exact(*options.output_dt) +
                                  ": must be finite and > 0");
    }
    p.output.dt = *options.output_dt;
  }

  CrosscheckResult r;
  r.accuracy = options.accuracy;
  r.reduced = run::RunMission(p);
  if (r.reduced.termination != integrators::Termination::kReachedEnd) {
    throw std::runtime_error(p.source + ": reduced model: integration " + r.reduced.message);
  }
  const std::vector<double> grid = integrators::UniformGrid(p.t_begin(), p.t_end(), p.output.dt);
  SimbodyOptions so;
  so.accuracy = options.accuracy;
  r.simbody = RunSimbodyPrescribed(p, grid, r.reduced.spin_axis_B, so);
  r.difference = CompareTrajectories(r.reduced.trajectory, r.simbody.trajectory);
  r.max_flip_difference = MaxFlipDifference(r.reduced.flip_times, r.simbody.flip_times);

  // Constant inertia: both against the closed-form solution.
  const schedule::DeploymentSchedule sched(p);
  if (sched.IsRigidOn(p.t_begin(), p.t_end())) {
    const run::Trajectory& tr = r.reduced.trajectory;
    const math::Mat3 J = sched.Evaluate(p.t_begin()).J_B;
    const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(J), tr.H_B.front(),
                                         tr.q_NB.front(), tr.time.front());
    r.has_analytic = true;
    if (analysis::LocateSpinAxis(J, r.reduced.spin_axis_B).role ==
        analysis::AxisRole::kIntermediate) {
      r.analytic_flip_times = sol.FlipTimes(p.t_begin(), p.t_end());
    }
    const double M = tr.H_B.front().norm();
    for (std::size_t i = 0; i < tr.size(); ++i) {
      const math::Vec3 H = sol.H_B(tr.time[i]);
      r.simbody_max_analytic_error =
          std::max(r.simbody_max_analytic_error, (r.simbody.trajectory.H_B[i] - H).norm() / M);
      r.reduced_max_analytic_error =
          std::max(r.reduced_max_analytic_error, (tr.H_B[i] - H).norm() / M);
    }
    r.max_flip_difference_simbody_analytic =
        MaxFlipDifference(r.simbody.flip_times, r.analytic_flip_times);
    r.max_flip_difference_reduced_analytic =
        MaxFlipDifference(r.reduced.flip_times, r.analytic_flip_times);
  }
  r.profile = std::move(p);
  return r;
}

CrosscheckVerdict Judge(const TrajectoryDifference& d,
                        double max_flip_difference,
                        bool events_same,
                        double max_event_time,
                        double duration,
                        double tolerance) {
  CrosscheckVerdict v;
  v.tolerance = tolerance;
  auto fail = [&v](const std::string& why) {
    if (v.agree) v.reason = why;
    v.agree = false;
  };
  if (!events_same) fail("the hinge events differ (kinds, panels or counts)");
  if (std::isinf(max_flip_difference)) fail("the flip counts differ");
  if (!(d.max_H_B_relative <= tolerance)) {
    fail("H_B differs by " + Num(d.max_H_B_relative) + " of |H|");
  }
  if (d.w_scale > 0.0 && !(d.max_w <= tolerance * d.w_scale)) {
    fail("w_NB_B differs by " + Num(d.max_w / d.w_scale) + " of its largest value");
  }
  const double t_tol = tolerance * duration;
  if (!std::isinf(max_flip_difference) && !(max_flip_difference <= t_tol)) {
    fail("a flip time differs by " + Num(max_flip_difference) + " s");
  }
  if (events_same && !(max_event_time <= t_tol)) {
    fail("an event time differs by " + Num(max_event_time) + " s");
  }
  return v;
}

std::string FormatVerdict(const CrosscheckVerdict& v) {
  const std::string rule = "(tolerance " + Num(v.tolerance) +
                           ": H_B and w relative, flip and event times relative to the run)";
  return v.agree ? "verdict: agree " + rule : "verdict: DISAGREE: " + v.reason + " " + rule;
}

std::string FormatCrosscheckTable(const CrosscheckResult& r) {
  std::ostringstream o;
  const schedule::Profile& p = r.profile;
  const TrajectoryDifference& d = r.difference;
  auto line = [&o](const std::string& what, const std::string& value) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "  %-44s %s\n", what.c_str(), value.c_str());
    o << buf;
  };
  o << "Simbody cross-check: " << p.name << " (" << p.source << ")\n";
  o << "  t = " << Num(p.t_begin()) << " .. " << Num(p.t_end()) << " s, "
    << r.reduced.trajectory.size() << " samples every " << Num(p.output.dt) << " s; mode "
    << schedule::ToString(p.mode) << ", reduced coupling " << schedule::ToString(p.coupling)
    << "\n";
  o << "  reduced: " << p.integrator.method << " rtol " << Num(p.integrator.rtol) << " atol "
    << Num(p.integrator.atol) << "; Simbody: RungeKuttaMerson accuracy " << Num(r.accuracy)
    << "\n\n";
  o << "  reduced vs Simbody                           max difference\n";
  line("H_B, relative to |H|", Num(d.max_H_B_relative));
  line("attitude [rad]", Num(d.max_attitude));
  line("angular velocity w_NB_B [rad/s]", Num(d.max_w) + "  (max |w| " + Num(d.w_scale) + ")");
  if (r.reduced.flip_times.size() == r.simbody.flip_times.size()) {
    line("flip times [s] (" + std::to_string(r.simbody.flip_times.size()) + " flips)",
         Num(r.max_flip_difference));
  } else {
    line("flip counts (reduced / Simbody)", std::to_string(r.reduced.flip_times.size()) + " / " +
                                                std::to_string(r.simbody.flip_times.size()) +
                                                "  MISMATCH");
  }
  o << "\n  own errors\n";
  line("Simbody momentum drift |dh_N|/|h_N|", Num(r.simbody.max_momentum_drift));
  line("reduced momentum drift |dh_N|/|h_N|", Num(r.reduced.max_h_N_drift));
  if (r.has_analytic) {
    line("Simbody H_B vs closed form (relative)", Num(r.simbody_max_analytic_error));
    line("reduced H_B vs closed form (relative)", Num(r.reduced_max_analytic_error));
    if (!r.analytic_flip_times.empty()) {
      line("Simbody flips vs closed form [s]", Num(r.max_flip_difference_simbody_analytic));
      line("reduced flips vs closed form [s]", Num(r.max_flip_difference_reduced_analytic));
    }
  }
  o << "\n  cost\n";
  line("reduced wall time [s]",
       Num(r.reduced.wall_seconds) + "  (" + std::to_string(r.reduced.stats.steps) + " steps)");
  line("Simbody wall time [s]", Num(r.simbody.stats.wall_seconds) + "  (" +
                                    std::to_string(r.simbody.stats.steps) + " steps)");
  return o.str();
}

}  // namespace deploysim::crosscheck
