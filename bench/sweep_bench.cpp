// Sweep throughput (benchmark row 4): deployment simulations of 300 s
// per second with 1 and 2 worker threads (and 2 MPI ranks when built with MPI), and the
// parallel efficiency, measured side by side in one run. (The full mission pipeline
// against the sweep's outcome-only path is bench/pipeline_bench.cpp's table.)
// A free-hinge sweep (table 4b): the small satellite's spring deployment
// (deployment_profiles/smallsat_spring_deploy.yaml, 300 s) over spin rates x Monte Carlo
// samples of nutation, spring, damper and failure modes, on the outcome-only mission run
// (run::RunMission without output samples), at the sweep settings of
// table 4 (`exact`, rtol 1e-9, atol 1e-11) and at the profile's own integrator settings
// (rkmk-rkf78, rtol 1e-11, atol 1e-13); the outcomes of both against a reference at rtol
// 1e-13 on a subset of the cases.
//
// The sweep: the small satellite (models/smallsat.yaml) deploying its wings in two
// moves with exact coupling over 300 s, method exact, rtol 1e-9, atol 1e-11, over a grid
// of spin rates x Monte Carlo samples of nutation, panel mass and interpolation law.
// Each configuration is timed end to end through sweep::RunSweep (every case built from
// the sweep file, the journal, its fsyncs and the HDF5 results included): N cold runs per
// configuration, interleaved, the median (the machine may be shared: the CPU use column
// shows how much of its cores the run actually got).
//
// Usage: sweep_bench [--quick] [--markdown FILE] [--cases N] [--root REPO]
//        (--quick: 2,000 cases and 1 run per configuration instead of 8,000 and 3, the
//         free-hinge sweep 500 and 200 cases instead of 2,000 and 2,000;
//         --root: the repository, for models/smallsat.yaml; found from the working
//         directory or the executable's location otherwise)

#if defined(DEPLOYSIM_HAVE_SWEEP)

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "deploysim/sweep/mpi_session.h"
#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/runner.h"
#include "deploysim/sweep/sweep_file.h"
#include "deploysim/sweep/sweep_spec.h"

namespace {

namespace fs = std::filesystem;
using namespace deploysim;

constexpr double kTargetRate = 2000.0;     // [simulations/s] on 2 cores
constexpr double kTargetEfficiency = 0.9;  // at 2 workers

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

fs::path FindRoot(const std::string& given, const char* argv0) {
  std::vector<fs::path> starts;
  if (!given.empty()) starts.push_back(given);
#ifdef DEPLOYSIM_SOURCE_DIR
  starts.push_back(DEPLOYSIM_SOURCE_DIR);
#endif
  starts.push_back(fs::current_path());
  std::error_code ec;
  starts.push_back(fs::canonical(fs::path(argv0), ec).parent_path());
  for (fs::path p : starts) {
    for (; !p.empty(); p = p.parent_path()) {
      if (fs::exists(p / "models" / "smallsat.yaml")) return p;
      if (p == p.parent_path()) break;
    }
  }
  std::fprintf(stderr, "sweep_bench: cannot find models/smallsat.yaml: pass --root REPO\n");
  std::exit(2);
}

/// Writes the 300 s profile and a sweep of about `cases` cases into `dir`.
std::string WriteSweep(const fs::path& dir, const fs::path& root, int cases) {
  std::ofstream(dir / "smallsat_300s.yaml")
      << "name: smallsat_300s\nmodel: " << (root / "models" / "smallsat.yaml").string()
      << "\nmode: geometry\ncoupling: exact\n"
         "initial: {angular_velocity: [0.0091, 0.5235988, 0.0091]}\n"
         "stages:\n"
         "  - {name: stowed spin, hold: closed, until: 30}\n"
         "  - {name: half deploy, to: half_open, law: minimum-jerk, until: 50}\n"
         "  - {name: half open, hold: half_open, until: 80}\n"
         "  - {name: full deploy, to: open, law: minimum-jerk, until: 100}\n"
         "  - {name: deployed, hold: open, until: 300}\n"
         "integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}\n";
  // 20 spin rates x samples (nutation, panel mass, law); no timing parameter, so that
  // every simulation spans exactly 300 s.
  const int samples = std::max(1, cases / 20);
  const fs::path sweep = dir / "bench_sweep.yaml";
  std::ofstream(sweep) << "name: sweep_bench\nbase: smallsat_300s.yaml\n"
                          "grid:\n"
                          "  - {parameter: spin_rate_rpm, linspace: [2, 10, 20]}\n"
                          "monte_carlo:\n  samples: "
                       << samples
                       << "\n  seed: 1\n  parameters:\n"
                          "    - {parameter: nutation_deg, uniform: [0.2, 3]}\n"
                          "    - {parameter: panel_mass_scale, normal: {mean: 1, sigma: 0.05, "
                          "min: 0.8, max: 1.2}}\n"
                          "    - {parameter: law, choice: [smoothstep, minimum-jerk]}\n";
  return sweep.string();
}

/// The spring deployment of the small satellite over 300 s (smallsat_spring_deploy.yaml
/// with `until: 300`) and a free-hinge sweep of about `cases` cases over it, with the
/// integrator `integrator` (a flow mapping, or empty: the profile's own).
std::string WriteHingeSweep(const fs::path& dir,
                            const fs::path& root,
                            int cases,
                            const std::string& name,
                            const std::string& integrator) {
  const char* const wing =
      "      spring: {stiffness: 1.0, rest_angle_deg: -30}\n"
      "      damper: {coefficient: 0.3}\n"
      "      friction: {torque: 0.02, regularization_speed_deg_s: 1.0}\n"
      "      stops: {min_deg: -2, max_deg: 92, restitution: 0.3}\n"
      "      latch: {angle_deg: 0}\n";
  std::ofstream(dir / "spring_300s.yaml")
      << "name: spring_300s\nmodel: " << (root / "models" / "smallsat.yaml").string() << "\n"
      << "initial:\n"
         "  configuration: closed\n"
         "  angular_velocity: [0.0091, 0.5235988, 0.0091]\n"
         "until: 300\n"
         "hinges:\n"
         "  wing_plus_x:\n"
         "    free:\n"
         "      release: {at: 60}\n"
      << wing
      << "  wing_minus_x:\n"
         "    free:\n"
         "      release: {after_latch: wing_plus_x, delay: 2.0}\n"
      << wing << "integrator: {method: rkmk-rkf78, rtol: 1.0e-11, atol: 1.0e-13}\n";
  const int samples = std::max(1, cases / 20);
  const fs::path sweep = dir / (name + ".yaml");
  std::ofstream(sweep) << "name: " << name << "\nbase: spring_300s.yaml\n"
                       << (integrator.empty() ? "" : "integrator: " + integrator + "\n")
                       << "grid:\n"
                          "  - {parameter: spin_rate_rpm, linspace: [2, 10, 20]}\n"
                          "monte_carlo:\n"
                          "  samples: "
                       << samples
                       << "\n"
                          "  seed: 1\n"
                          "  parameters:\n"
                          "    - {parameter: nutation_deg, uniform: [0.2, 3]}\n"
                          "    - {parameter: spring_stiffness_scale, normal: {mean: 1, sigma: "
                          "0.1, min: 0.5, max: 1.5}}\n"
                          "    - {parameter: damping, uniform: [0.1, 0.5]}\n"
                          "    - {parameter: stick_fraction, panel: wing_minus_x, choice: [0, "
                          "0.8], weights: [0.95, 0.05]}\n"
                          "    - {parameter: latch_fails, panel: wing_minus_x, choice: [no, "
                          "yes], weights: [0.95, 0.05]}\n";
  return sweep.string();
}

/// Largest differences of a sweep's outcomes from a reference run of the same cases.
struct Accuracy {
  std::size_t cases = 0;
  double shock_rel = 0.0;        // max |d max_latch_w_jump| / max_latch_w_jump
  double latch_time = 0.0;       // [s] max |d deploy_end_time|
  double flip_time = 0.0;        // [s] max |d first_flip_time|
  double flip_period_rel = 0.0;  // max |d predicted_flip_half_period| / itself
  bool same_counts = true;       // flip and latch counts identical
};

/// `stride`-spaced cases of `spec` against the same cases at rtol 1e-13, atol 1e-15.
Accuracy MeasureAccuracy(const sweep::SweepSpec& spec, std::size_t stride) {
  sweep::SweepSpec ref = spec;
  ref.base.integrator.rtol = 1e-13;
  ref.base.integrator.atol = 1e-15;
  Accuracy a;
  for (std::size_t i = 0; i < spec.case_count(); i += stride) {
    const sweep::CaseOutcome o = sweep::SimulateOutcome(sweep::BuildCase(spec, i), spec.outcome);
    const sweep::CaseOutcome r = sweep::SimulateOutcome(sweep::BuildCase(ref, i), ref.outcome);
    ++a.cases;
    a.same_counts =
        a.same_counts && o.flip_count == r.flip_count && o.latched_count == r.latched_count;
    a.shock_rel = std::max(a.shock_rel,
                           std::abs(o.max_latch_w_jump - r.max_latch_w_jump) / r.max_latch_w_jump);
    if (std::isfinite(r.deploy_end_time)) {
      a.latch_time = std::max(a.latch_time, std::abs(o.deploy_end_time - r.deploy_end_time));
    }
    if (r.flip_count > 0) {
      a.flip_time = std::max(a.flip_time, std::abs(o.first_flip_time - r.first_flip_time));
    }
    if (std::isfinite(r.predicted_flip_half_period)) {
      a.flip_period_rel = std::max(
          a.flip_period_rel, std::abs(o.predicted_flip_half_period - r.predicted_flip_half_period) /
                                 r.predicted_flip_half_period);
    }
  }
  return a;
}

struct Row {
  std::string name;
  std::size_t cases = 0;
  double wall = 0.0;      // [s] end to end
  double parallel = 0.0;  // [s] the worker phase
  double cpu = 0.0;       // [s] CPU time of the process (all threads)
  int workers = 1;
  double rate() const { return static_cast<double>(cases) / wall; }
  double cpu_use() const { return cpu / (wall * workers); }
};

/// The run of median wall time (N odd: the median).
Row MedianRow(std::vector<Row> runs) {
  std::sort(runs.begin(), runs.end(), [](const Row& a, const Row& b) { return a.wall < b.wall; });
  return runs[(runs.size() - 1) / 2];
}

/// One cold sweep run with `threads` workers (`label` before the thread count).
Row TimeSweep(const sweep::SweepSpec& spec,
              const fs::path& dir,
              int threads,
              const std::string& label = "sweep") {
  Row best;
  {
    sweep::RunOptions o;
    o.output = (dir / ("bench_" + std::to_string(threads) + ".h5")).string();
    o.threads = threads;
    const double cpu0 = CpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    const sweep::RunSummary s = sweep::RunSweep(spec, o);
    Row row;
    row.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.cpu = CpuSeconds() - cpu0;
    row.cases = s.cases;
    row.parallel = s.parallel_seconds;
    row.workers = threads;
    row.name = label + ", " + std::to_string(threads) + (threads == 1 ? " thread" : " threads");
    best = row;
    fs::remove(o.output);
  }
  return best;
}

/// 2 MPI ranks x 1 thread, through mpiexec running this program as the worker; the
/// wall time is rank 0's RunSweep (MPI start-up excluded), read from its output.
bool TimeMpi(const std::string& sweep_path,
             const fs::path& dir,
             const char* self,
             int repeats,
             std::size_t cases,
             Row& median) {
  if (!sweep::MpiBuilt() || sweep::MpiExecutable().empty()) return false;
  std::vector<Row> runs;
  for (int r = 0; r < repeats; ++r) {
    const fs::path out = dir / "bench_mpi.h5";
    const fs::path log = dir / "mpi.log";
    const std::string cmd =
        "'" + sweep::MpiExecutable() +
        "' --allow-run-as-root --oversubscribe -np 2 --mca btl self,vader,tcp '" + self +
        "' --mpi-worker '" + sweep_path + "' '" + out.string() + "' > '" + log.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream f(log);
    std::string line;
    double wall = 0.0, cpu = 0.0, parallel = 0.0;
    while (std::getline(f, line)) {
      if (std::sscanf(line.c_str(), "mpi-worker wall=%lf cpu=%lf parallel=%lf", &wall, &cpu,
                      &parallel) == 3) {
        break;
      }
    }
    if (!fs::exists(out) || wall <= 0.0) {
      std::fprintf(stderr, "sweep_bench: the MPI run failed (status %d); see %s\n", status,
                   log.string().c_str());
      return false;
    }
    fs::remove(out);
    Row row;
    row.name = "sweep, 2 MPI ranks x 1 thread";
    row.wall = wall;
    row.cpu = 2.0 * cpu;  // rank 0's CPU time, taken as typical of both
    row.parallel = parallel;
    row.cases = cases;
    row.workers = 2;
    runs.push_back(row);
  }
  median = MedianRow(runs);
  return true;
}

int MpiWorker(int* argc, char*** argv) {
  sweep::MpiSession mpi(argc, argv);
  const sweep::SweepSpec spec = sweep::LoadSweep((*argv)[2]);
  sweep::RunOptions o;
  o.output = (*argv)[3];
  o.threads = 1;
  o.mpi = &mpi;
  mpi.Barrier();
  const double cpu0 = CpuSeconds();
  const auto t0 = std::chrono::steady_clock::now();
  const sweep::RunSummary s = sweep::RunSweep(spec, o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (mpi.rank() == 0) {
    std::printf("mpi-worker wall=%.6f cpu=%.6f parallel=%.6f complete=%d\n", wall,
                CpuSeconds() - cpu0, s.parallel_seconds, s.complete ? 1 : 0);
  }
  return s.complete ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 4 && std::strcmp(argv[1], "--mpi-worker") == 0) return MpiWorker(&argc, &argv);
  const bench::Args args = bench::ParseArgs(argc, argv);
  int cases = args.quick ? 2000 : 8000;
  std::string root_arg;
  for (std::size_t i = 0; i < args.rest.size(); ++i) {
    if (args.rest[i] == "--cases" && i + 1 < args.rest.size()) {
      cases = std::max(100, std::atoi(args.rest[++i].c_str()));
    } else if (args.rest[i] == "--root" && i + 1 < args.rest.size()) {
      root_arg = args.rest[++i];
    } else {
      std::fprintf(stderr,
                   "usage: sweep_bench [--quick] [--markdown FILE] [--cases N] [--root REPO]\n");
      return 2;
    }
  }
  const fs::path root = FindRoot(root_arg, argv[0]);
  const fs::path dir =
      fs::temp_directory_path() / ("deploysim_sweep_bench." + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string sweep_path = WriteSweep(dir, root, cases);
  const sweep::SweepSpec spec = sweep::LoadSweep(sweep_path);
  const int hinge_cases = args.quick ? 500 : 2000;
  const int own_cases = args.quick ? 200 : 2000;
  const sweep::SweepSpec hinge = sweep::LoadSweep(WriteHingeSweep(
      dir, root, hinge_cases, "hinge_sweep", "{method: exact, rtol: 1.0e-9, atol: 1.0e-11}"));
  const sweep::SweepSpec own =
      sweep::LoadSweep(WriteHingeSweep(dir, root, own_cases, "hinge_sweep_own", ""));
  const int repeats = args.quick ? 1 : 3;
  const std::string load_before = bench::LoadAverage();

  // Interleave the configurations so that a change in the machine's load hits all.
  std::vector<Row> ones, twos, hinge_ones, hinge_twos, own_ones, own_twos;
  const std::string hinge_label = "free-hinge sweep (exact, rtol 1e-9)";
  const std::string own_label = "free-hinge sweep (rkmk-rkf78, rtol 1e-11)";
  for (int r = 0; r < repeats; ++r) {
    ones.push_back(TimeSweep(spec, dir, 1));
    twos.push_back(TimeSweep(spec, dir, 2));
    hinge_ones.push_back(TimeSweep(hinge, dir, 1, hinge_label));
    hinge_twos.push_back(TimeSweep(hinge, dir, 2, hinge_label));
    own_ones.push_back(TimeSweep(own, dir, 1, own_label));
    own_twos.push_back(TimeSweep(own, dir, 2, own_label));
  }
  const std::size_t stride = static_cast<std::size_t>(args.quick ? 25 : 20);
  const Accuracy hinge_accuracy = MeasureAccuracy(hinge, stride);
  const Accuracy own_accuracy = MeasureAccuracy(own, stride);
  std::vector<Row> rows = {MedianRow(ones), MedianRow(twos)};
  const Row one = rows[0], two = rows[1];
  Row mpi;
  const bool have_mpi = TimeMpi(sweep_path, dir, argv[0], repeats, spec.case_count(), mpi);
  if (have_mpi) rows.push_back(mpi);

  bench::Markdown md;
  md.Printf("### 4. Sweep throughput\n\n");
  md.Printf(
      "`build/release/bench/sweep_bench`: the small satellite's wing deployment "
      "(models/smallsat.yaml, two minimum-jerk or smoothstep moves), 300 s per simulation, "
      "exact coupling, `exact` flow, rtol 1e-9, atol 1e-11; %zu cases per configuration "
      "(20 spin rates x Monte Carlo samples of nutation, panel mass and law).\n\n",
      spec.case_count());
  md.Printf(
      "| configuration | cases | wall [s] | sims/s | CPU use | speed-up | efficiency | "
      "CPU-time eff | serial |\n");
  md.Printf("|---|---|---|---|---|---|---|---|---|\n");
  const double base = one.rate();
  const double cpu_per_case_1 = one.cpu / static_cast<double>(one.cases);
  for (const Row& r : rows) {
    const double speedup = r.rate() / base;
    char eff[32] = "-", work[32] = "-";
    if (r.workers > 1) {
      std::snprintf(eff, sizeof(eff), "%.2f", speedup / r.workers);
      std::snprintf(work, sizeof(work), "%.2f",
                    cpu_per_case_1 / (r.cpu / static_cast<double>(r.cases)));
    }
    md.Printf("| %s | %zu | %.3f | %.0f | %.0f%% | %.2fx | %s | %s | %.1f%% |\n", r.name.c_str(),
              r.cases, r.wall, r.rate(), 100.0 * r.cpu_use(), speedup, eff, work,
              100.0 * (1.0 - r.parallel / r.wall));
  }
  const double eff = two.rate() / (2.0 * one.rate());
  const double work_eff = one.cpu / two.cpu;
  md.Printf(
      "\n- Each run is one `sweep::RunSweep` of the whole sweep, end to end: every case built "
      "from the sweep file and integrated to 300 s on the outcome-only path (flips and "
      "spin-axis extrema located, no trajectory output), the journal with its fsyncs and the HDF5 "
      "results file included. "
      "MPI: rank 0's `RunSweep` (the start-up of `mpiexec` excluded).\n");
  md.Printf(
      "- Timing: each configuration %d cold run%s (the configurations interleaved), the run "
      "of median wall time reported.\n",
      repeats, repeats == 1 ? "" : "s");
  md.Printf(
      "- efficiency: speed-up / workers (wall clock). CPU-time eff: CPU time per case with 1 "
      "worker / with N (1.0: the workers do not slow each other down; the wall-clock figure "
      "also counts time the OS gave to other processes). serial: share of the wall time "
      "outside the worker phase (journal setup, HDF5 results).\n");
  md.Printf("- Target >= %.0f simulations/s on 2 cores: %s (%.0f/s, %.2fx the target).\n",
            kTargetRate, two.rate() >= kTargetRate ? "**met**" : "**missed**", two.rate(),
            two.rate() / kTargetRate);
  md.Printf(
      "- Target parallel efficiency >= %.2f at 2 threads: %s (%.2f wall clock, %.2f CPU time)%s.\n",
      kTargetEfficiency, eff >= kTargetEfficiency ? "**met**" : "**missed**", eff, work_eff,
      two.cpu_use() < 0.95 ? ("; the 2-thread run had only " +
                              std::to_string(static_cast<int>(100 * two.cpu_use())) +
                              "% of 2 cores: the machine is shared")
                                 .c_str()
                           : "");
  if (have_mpi) {
    md.Printf("- 2 MPI ranks: %.0f simulations/s, efficiency %.2f.\n", mpi.rate(),
              mpi.rate() / (2.0 * one.rate()));
  } else {
    md.Printf("- 2 MPI ranks: not measured (%s).\n",
              sweep::MpiBuilt() ? "mpiexec failed" : "built without DEPLOYSIM_WITH_MPI");
  }

  // ---- 4b. Free-hinge sweep ----
  const std::vector<Row> hrows = {MedianRow(hinge_ones), MedianRow(hinge_twos), MedianRow(own_ones),
                                  MedianRow(own_twos)};
  md.Printf("\n#### 4b. Free-hinge sweep throughput\n\n");
  md.Printf(
      "The small satellite's spring deployment (deployment_profiles/smallsat_spring_deploy.yaml "
      "with `until: 300`: two wings on torsion springs with dampers, friction, stops and latches, "
      "the second released 2 s after the first latches), 300 s per simulation on the "
      "outcome-only hinge mission (`run::RunMission` of a hinge profile without output "
      "samples: releases, "
      "latches, stop impacts, flips and the largest spin-axis angle located; no trajectory), "
      "20 spin rates x Monte Carlo samples of nutation, spring stiffness, damping, a jam and a "
      "failed latch of wing_minus_x (5 %% each). Two integrator settings: those of table 4 "
      "(`exact`: the closed form on the rigid phases, rkmk-rkf78 on the free ones; rtol 1e-9, "
      "atol 1e-11) and the profile's own (rkmk-rkf78 throughout, rtol 1e-11, atol 1e-13).\n\n");
  md.Printf(
      "| configuration | cases | wall [s] | sims/s | CPU use | speed-up | efficiency | serial |\n");
  md.Printf("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < hrows.size(); ++k) {
    const Row& r = hrows[k];
    const Row& base1 = hrows[k - k % 2];
    const double speedup = r.rate() / base1.rate();
    char heff[32] = "-";
    if (r.workers > 1) std::snprintf(heff, sizeof(heff), "%.2f", speedup / r.workers);
    md.Printf("| %s | %zu | %.3f | %.0f | %.0f%% | %.2fx | %s | %.1f%% |\n", r.name.c_str(),
              r.cases, r.wall, r.rate(), 100.0 * r.cpu_use(), speedup, heff,
              100.0 * (1.0 - r.parallel / r.wall));
  }
  md.Printf("\n");
  auto accuracy_line = [&md](const char* what, const Accuracy& a) {
    md.Printf(
        "- Outcomes at %s against the same cases at rtol 1e-13, atol 1e-15 (%zu cases): latch "
        "shock (max_latch_w_jump) within %.1e relative, last latch time within %.1e s, first "
        "flip time within %.1e s, predicted time between flips within %.1e relative; flip and "
        "latch counts %s.\n",
        what, a.cases, a.shock_rel, a.latch_time, a.flip_time, a.flip_period_rel,
        a.same_counts ? "identical" : "**differ**");
  };
  accuracy_line("table 4's settings", hinge_accuracy);
  accuracy_line("the profile's settings", own_accuracy);
  md.Printf(
      "- Timing as in table 4: one `sweep::RunSweep` per run, end to end, each configuration "
      "%d cold run%s interleaved with the others, the median reported.\n",
      repeats, repeats == 1 ? "" : "s");
  const Row& h2 = hrows[1];
  const Row& o2 = hrows[3];
  md.Printf(
      "- Target >= %.0f free-hinge simulations/s on 2 cores: %s at table 4's settings (%.0f/s, "
      "%.2fx the target); %s at the profile's own settings (%.0f/s, %.2fx the target).\n",
      kTargetRate, h2.rate() >= kTargetRate ? "**met**" : "**missed**", h2.rate(),
      h2.rate() / kTargetRate, o2.rate() >= kTargetRate ? "**met**" : "**missed**", o2.rate(),
      o2.rate() / kTargetRate);
  md.Printf("\nLoad average before the runs: %s.\n%s\n", load_before.c_str(),
            bench::MachineLine().c_str());
  fs::remove_all(dir);
  md.Emit(args.markdown);
  return 0;
}

#else  // !DEPLOYSIM_HAVE_SWEEP

#include <cstdio>

int main() {
  std::fprintf(stderr,
               "sweep_bench: built without the sweep library (bench/CMakeLists.txt must link "
               "deploysim_sweep to sweep_bench)\n");
  return 2;
}

#endif
