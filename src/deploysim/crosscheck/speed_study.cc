#include "deploysim/crosscheck/speed_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "deploysim/run/mission.h"
#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/io/atomic_file.h"
#include "deploysim/math/number_format.h"

namespace deploysim::crosscheck {

namespace {

std::string Num(double x, int digits = 3) { return math::FormatSignificant(x, digits); }

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("speed study: " + what);
}

}  // namespace

schedule::Profile DeploymentProfile(const schedule::Profile& base,
                                    double duration,
                                    const SpeedStudyOptions& options,
                                    schedule::Coupling coupling) {
  Require(base.mode == schedule::Mode::kGeometry,
          base.source + ": the base profile must be in geometry mode");
  Require(duration > 0.0 && std::isfinite(duration),
          "duration = " + Num(duration) + " s: must be finite and > 0");
  Require(options.hold_before > 0.0 && std::isfinite(options.hold_before),
          "hold_before = " + Num(options.hold_before) + " s: must be finite and > 0");
  Require(options.hold_after > 0.0 && std::isfinite(options.hold_after),
          "hold_after = " + Num(options.hold_after) + " s: must be finite and > 0");
  Require(options.output_dt > 0.0 && std::isfinite(options.output_dt),
          "output_dt = " + Num(options.output_dt) + " s: must be finite and > 0");
  Require(options.law != schedule::Law::kStep, "law = step: a deployment needs a finite rate");
  const std::string from = base.stages.front().from;
  const std::string to = base.stages.back().to;
  Require(from != to,
          base.source + ": the first and last configurations are the same ('" + from + "')");
  schedule::Profile p = base;
  p.name = base.name + "_speed_" + Num(duration, 6) + "s";
  p.coupling = coupling;
  p.output.dt = options.output_dt;
  const double t0 = base.t_begin();
  const double t1 = t0 + options.hold_before;
  const double t2 = t1 + duration;
  const double t3 = t2 + options.hold_after;
  schedule::Stage hold0{"stowed spin", from, from, schedule::Law::kStep, t0, t1};
  schedule::Stage move{"deploy", from, to, options.law, t1, t2};
  schedule::Stage hold1{"deployed", to, to, schedule::Law::kStep, t2, t3};
  p.stages = {hold0, move, hold1};
  schedule::ValidateProfile(p);
  return p;
}

SpeedStudyResult SpeedStudy(const schedule::Profile& base, const SpeedStudyOptions& options) {
  Require(!options.durations.empty(), "no durations");
  SpeedStudyResult out;
  out.profile_name = base.name;
  out.from = base.stages.front().from;
  out.to = base.stages.back().to;
  out.options = options;
  for (double D : options.durations) {
    const schedule::Profile exact = DeploymentProfile(base, D, options, schedule::Coupling::kExact);
    const schedule::Profile quasi =
        DeploymentProfile(base, D, options, schedule::Coupling::kQuasiRigid);
    const run::MissionResult r_exact = run::RunMission(exact);
    const run::MissionResult r_quasi = run::RunMission(quasi);
    for (const run::MissionResult* r : {&r_exact, &r_quasi}) {
      if (r->termination != integrators::Termination::kReachedEnd) {
        throw std::runtime_error(base.source + ": speed study, D = " + Num(D) + " s: integration " +
                                 r->message);
      }
    }
    const std::vector<double> grid =
        integrators::UniformGrid(exact.t_begin(), exact.t_end(), exact.output.dt);
    SimbodyOptions so;
    so.accuracy = options.accuracy;
    so.locate_flips = false;
    const SimbodyRun sim = RunSimbodyPrescribed(exact, grid, r_exact.spin_axis_B, so);
    const TrajectoryDifference d_exact = CompareTrajectories(r_exact.trajectory, sim.trajectory);
    const TrajectoryDifference d_quasi = CompareTrajectories(r_quasi.trajectory, sim.trajectory);

    SpeedStudyRow row;
    row.duration = D;
    const double move_begin = exact.stages[1].t_begin;
    const double move_end = exact.stages[1].t_end;
    const double tol = 1e-9 * std::max(1.0, move_end);
    std::size_t end_index = 0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      const double t = grid[i];
      if (std::abs(t - move_end) < std::abs(grid[end_index] - move_end)) end_index = i;
      if (t >= move_begin - tol && t <= move_end + tol) {
        row.max_w_error_deploying = std::max(row.max_w_error_deploying, d_quasi.w[i]);
        row.w_scale = std::max(row.w_scale, sim.trajectory.w_NB_B[i].norm());
      }
      if (t > move_end + tol) {
        row.max_attitude_error_after = std::max(row.max_attitude_error_after, d_quasi.attitude[i]);
        row.max_w_error_after = std::max(row.max_w_error_after, d_quasi.w[i]);
      }
    }
    row.attitude_error_at_end = d_quasi.attitude[end_index];
    for (const run::DangerWindow& w : r_exact.danger_windows) {
      row.danger_time_deploying +=
          std::max(0.0, std::min(w.t_end, move_end) - std::max(w.t_begin, move_begin));
    }
    row.exact_max_attitude_error = d_exact.max_attitude;
    row.exact_max_H_B_relative = d_exact.max_H_B_relative;
    row.simbody_momentum_drift = sim.max_momentum_drift;
    row.simbody_wall_seconds = sim.stats.wall_seconds;
    row.reduced_wall_seconds = r_exact.wall_seconds + r_quasi.wall_seconds;
    out.rows.push_back(row);
  }
  return out;
}

std::string FormatSpeedStudyTable(const SpeedStudyResult& r) {
  std::ostringstream o;
  o << "Deployment-speed study: quasi-rigid coupling vs Simbody (" << r.profile_name << ", "
    << r.from << " -> " << r.to << ", " << schedule::ToString(r.options.law) << ", holds "
    << Num(r.options.hold_before) << " s before and " << Num(r.options.hold_after)
    << " s after; Simbody accuracy " << Num(r.options.accuracy) << ")\n";
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%8s %9s %12s %9s %13s %13s %12s | %10s %10s %8s\n", "D [s]",
                "danger", "dw deploy", "|w| max", "dattitude end", "dattitude aft", "dw after",
                "exact datt", "exact dH_B", "Simbody");
  o << buf;
  std::snprintf(buf, sizeof(buf), "%8s %9s %12s %9s %13s %13s %12s | %10s %10s %8s\n", "", "[s]",
                "[rad/s]", "[rad/s]", "[rad]", "[rad] max", "[rad/s] max", "[rad] max", "rel. max",
                "wall [s]");
  o << buf;
  for (const SpeedStudyRow& w : r.rows) {
    std::snprintf(buf, sizeof(buf),
                  "%8g %9.4g %12.4e %9.4g %13.6f %13.4g %12.4e | %10.2e %10.2e %8.2f\n", w.duration,
                  w.danger_time_deploying, w.max_w_error_deploying, w.w_scale,
                  w.attitude_error_at_end, w.max_attitude_error_after, w.max_w_error_after,
                  w.exact_max_attitude_error, w.exact_max_H_B_relative, w.simbody_wall_seconds);
    o << buf;
  }
  return o.str();
}

void WriteSpeedStudyCsv(const std::string& path, const SpeedStudyResult& r) {
  io::AtomicFile out(path);
  {
    std::ofstream f(out.temporary_path());
    f << "# deploysim speed study: quasi-rigid coupling vs Simbody; profile " << r.profile_name
      << ", " << r.from << " -> " << r.to << ", law " << schedule::ToString(r.options.law)
      << ", hold_before " << r.options.hold_before << " s, hold_after " << r.options.hold_after
      << " s, Simbody accuracy " << r.options.accuracy << "\n";
    f << "duration [s],danger_time_deploying [s],max_w_error_deploying [rad/s],w_scale "
         "[rad/s],attitude_error_at_end [rad],"
         "max_attitude_error_after [rad],max_w_error_after [rad/s],exact_max_attitude_error [rad],"
         "exact_max_H_B_relative [1],simbody_momentum_drift [1],simbody_wall_seconds [s],"
         "reduced_wall_seconds [s]\n";
    for (const SpeedStudyRow& w : r.rows) {
      const double v[] = {w.duration,
                          w.danger_time_deploying,
                          w.max_w_error_deploying,
                          w.w_scale,
                          w.attitude_error_at_end,
                          w.max_attitude_error_after,
                          w.max_w_error_after,
                          w.exact_max_attitude_error,
                          w.exact_max_H_B_relative,
                          w.simbody_momentum_drift,
                          w.simbody_wall_seconds,
                          w.reduced_wall_seconds};
      for (std::size_t i = 0; i < std::size(v); ++i)
        f << (i ? "," : "") << math::FormatNumber(v[i]);
      f << "\n";
    }
    f.flush();
    if (!f) throw std::runtime_error(path + ": cannot write the speed-study CSV");
  }
  out.Commit();
}

}  // namespace deploysim::crosscheck
