// The full mission pipeline against the outcome-only path:
// run::RunMission (schedule built, integration with the dense trajectory on the
// output grid, flip events, stage reports) against sweep::SimulateOutcome (the same
// schedule, stepper, tolerances and flip rule, no trajectory) for the same profile,
// each timed cold (everything a user's run builds is inside the timed region), best of
// the repetitions, and their ratio. Default profile: the main job,
// deployment_profiles/smallsat_three_stage.yaml (method exact, exact coupling,
// output dt 0.1 s). For `exact` it also times the closed form alone (H_B(t) and q_NB(t)
// at as many times as the trajectory has samples): the floor of a mission run whose
// dense output is the closed form itself.
//
// Usage: pipeline_bench [--quick] [--markdown FILE] [--profile FILE]
//        (methods exact, rkmk-rkf78, rkf78, dopri5, each with the profile's tolerances)

#if defined(DEPLOYSIM_HAVE_SWEEP)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_util.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_spec.h"

namespace {

using namespace deploysim;

struct Row {
  std::string method;
  double mission = 0.0;  // median [s]
  double outcome = 0.0;  // median [s]
  long steps = 0;
  std::size_t samples = 0;
  std::size_t flips = 0;
  long long outcome_flips = 0;
  double closed_form = -1.0;  // [s] the closed form alone at every sample (exact only)
};

Row Measure(const schedule::Profile& base, const std::string& method, int reps) {
  schedule::Profile profile = base;
  profile.integrator.method = method;
  // The outcome path takes the initial momentum (as the sweep's cases carry it).
  schedule::Profile outcome_profile = profile;
  {
    const schedule::DeploymentSchedule sched(profile);
    const dynamics::InertiaSample s0 = sched.Evaluate(profile.t_begin());
    if (!outcome_profile.initial.H_B) {
      outcome_profile.initial.H_B = math::Vec3(s0.J_B * *profile.initial.w_NB_B + s0.h_rel_B);
      outcome_profile.initial.w_NB_B.reset();
    }
  }
  Row row;
  row.method = method;
  run::MissionResult mission;
  sweep::CaseOutcome outcome;
  // Interleaved, so that both sides see the same machine load.
  bench::Timing tm, to;
  for (int r = 0; r < reps; ++r) {
    tm.seconds.push_back(
        bench::TimeCold(1, [&] { mission = run::RunMission(profile); }).seconds.front());
    to.seconds.push_back(bench::TimeCold(1, [&] {
                           sweep::Case cs;
                           cs.run = run::CompiledRun::Compile(outcome_profile);
                           cs.spin_axis_B = sweep::BaseSpinAxis(cs.profile());
                           outcome = sweep::SimulateOutcome(cs, sweep::OutcomeSettings{});
                         }).seconds.front());
  }
  row.mission = tm.median();
  row.outcome = to.median();
  row.steps = mission.stats.steps;
  row.samples = mission.trajectory.size();
  row.flips = mission.flip_times.size();
  row.outcome_flips = static_cast<long long>(outcome.flip_count);
  if (method == "exact") {
    // The closed form alone at as many times as the trajectory has samples, on the last
    // rigid stage: what evaluating the exact solution at every sample costs.
    const schedule::DeploymentSchedule sched(profile);
    const schedule::Stage& last = profile.stages.back();
    const dynamics::InertiaSample js = sched.Evaluate(last.t_end);
    const math::Vec3 H = mission.trajectory.H_B.back();
    const math::Quat q = mission.trajectory.q_NB.back();
    const std::size_t n = row.samples;
    double sink = 0.0;
    const bench::Timing tc = bench::TimeCold(reps, [&] {
      const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(js.J_B), H, q,
                                           last.t_end);
      for (std::size_t i = 0; i < n; ++i) {
        const double t = last.t_begin + (last.t_end - last.t_begin) * static_cast<double>(i) /
                                            static_cast<double>(n);
        math::Vec3 Hs;
        math::Quat qs;
        sol.StateAt(t, &Hs, &qs);
        sink += Hs.x() + qs.w();
      }
    });
    if (!(sink == sink)) std::printf("(checksum NaN)\n");
    row.closed_form = tc.median();
  }
  return row;
}

/// The dual-spin craft (deployment_profiles/dual_spin_rotor.yaml) with its rotor's held
/// rate cut into n prescribed windows over the run (alternately 10 and 9.5 rad/s), its
/// nutation damper free: each window's ends are phase boundaries and rate jumps.
schedule::Profile RotorWindows(const schedule::Profile& base, int n) {
  schedule::Profile p = base;
  const std::vector<model::Panel>& panels = p.model.hinged.panels;
  std::size_t rotor = 0;
  while (rotor < panels.size() && panels[rotor].name != "rotor") ++rotor;
  if (rotor == panels.size()) throw std::runtime_error("RotorWindows: no panel named rotor");
  std::vector<schedule::HingeMove>& moves = p.hinges[rotor].moves;
  moves.clear();
  const double t0 = p.t_begin();
  const double dt = (p.t_end() - t0) / n;
  for (int i = 0; i < n; ++i) {
    schedule::HingeMove mv;
    mv.kind = schedule::HingeMove::Kind::kRate;
    mv.rate = i % 2 == 0 ? 10.0 : 9.5;
    mv.t_begin = t0 + i * dt;
    mv.t_end = i + 1 == n ? p.t_end() : t0 + (i + 1) * dt;
    moves.push_back(mv);
  }
  return p;
}

/// The cost of a run against its number of prescribed windows: linear.
void WindowsTable(bench::Markdown& md, int reps) {
  const schedule::Profile base = io::LoadProfile(std::string(DEPLOYSIM_SOURCE_DIR) +
                                                 "/deployment_profiles/dual_spin_rotor.yaml");
  const std::vector<int> counts = {2500, 5000, 10000};
  std::vector<double> wall;
  std::vector<long> steps;
  for (int n : counts) {
    const schedule::Profile p = RotorWindows(base, n);
    run::MissionResult r;
    wall.push_back(bench::TimeCold(reps, [&] {
                     run::NullSink sink;
                     r = run::RunMission(p, sink);
                   }).median());
    steps.push_back(r.stats.steps);
  }
  md.Printf(
      "\n### 5b. Prescribed windows: a run's cost is linear in their number\n\n"
      "The dual-spin craft (deployment_profiles/dual_spin_rotor.yaml, %.0f s, rtol %g, its "
      "damper free) with the rotor's held rate cut into n windows (alternately 10 and 9.5 "
      "rad/s): every window's ends are phase boundaries and rate jumps. `run::RunMission` "
      "timed from the parsed profile (compiled, run; samples to a sink that keeps none).\n\n"
      "| windows | wall [s] | per window [ms] | steps | wall / wall of %d windows |\n"
      "|---:|---:|---:|---:|---:|\n",
      base.t_end() - base.t_begin(), base.integrator.rtol, counts.front());
  for (std::size_t i = 0; i < counts.size(); ++i) {
    md.Printf("| %d | %.3g | %.3g | %ld | %.2f |\n", counts[i], wall[i], 1e3 * wall[i] / counts[i],
              steps[i], wall[i] / wall.front());
  }
  // A cost quadratic in the windows would double the cost per window with each doubling.
  const double per_first = wall.front() / counts.front();
  const double per_last = wall.back() / counts.back();
  md.Printf(
      "\nThe cost per window: %.3g ms with %d windows, %.3g ms with %d: %s (the steps grow "
      "where the windows become shorter than the steps the tolerance allows).\n",
      1e3 * per_first, counts.front(), 1e3 * per_last, counts.back(),
      per_last <= per_first ? "it does not grow, the cost is linear in the windows"
                            : "it grows: the cost is worse than linear in the windows");
}

}  // namespace

int main(int argc, char** argv) {
  const bench::Args args = bench::ParseArgs(argc, argv);
  std::string path =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml";
  for (std::size_t i = 0; i < args.rest.size(); ++i) {
    if (args.rest[i] == "--profile" && i + 1 < args.rest.size()) {
      path = args.rest[++i];
    } else {
      std::fprintf(stderr, "usage: pipeline_bench [--quick] [--markdown FILE] [--profile FILE]\n");
      return 2;
    }
  }
  const int reps = args.quick ? 3 : 11;
  const schedule::Profile profile = io::LoadProfile(path);
  std::vector<Row> rows;
  for (const char* m : {"exact", "rkmk-rkf78", "rkf78", "dopri5"}) {
    rows.push_back(Measure(profile, m, reps));
  }

  bench::Markdown md;
  md.Printf("### 5. Full mission pipeline against the outcome-only path (%s, %.0f s)\n\n",
            profile.name.c_str(), profile.t_end() - profile.t_begin());
  md.Printf(
      "`run::RunMission` (the trajectory on the %g s output grid: %zu samples of H_B, "
      "w, q, J_B, h_N, energies, Euler angles; flip events; stage reports) against "
      "`sweep::SimulateOutcome` (the same schedule, stepper, tolerances and flip rule; no "
      "trajectory) for the main job's profile, per method (rtol %g). Target: the full "
      "pipeline within 2x of the outcome-only path.\n\n",
      profile.output.dt, rows.front().samples, profile.integrator.rtol);
  md.Add(
      "| method | RunMission [ms] | SimulateOutcome [ms] | ratio | steps | flips (mission / "
      "outcome) | target <= 2x |\n|---|---:|---:|---:|---:|---|---|\n");
  for (const Row& r : rows) {
    md.Printf("| %s | %.3g | %.3g | %.3g | %ld | %zu / %lld | %s |\n", r.method.c_str(),
              1e3 * r.mission, 1e3 * r.outcome, r.mission / r.outcome, r.steps, r.flips,
              r.outcome_flips, r.mission <= 2.0 * r.outcome ? "met" : "missed");
  }
  for (const Row& r : rows) {
    if (r.closed_form < 0.0) continue;
    md.Printf(
        "\nFor `exact`, evaluating the closed form alone (H_B and q_NB from one evaluation) at "
        "%zu times takes %.3g ms = %.3gx the whole outcome path, so with the exact solution at "
        "every sample the 2x target is out of reach; the dense output of `exact` therefore "
        "samples a Chebyshev fit of the closed form (exact at steps and events; within 1.4x "
        "of the closed form's own error), and the mission takes %.3g ms.\n",
        r.samples, 1e3 * r.closed_form, r.closed_form / r.outcome, 1e3 * r.mission);
  }
  md.Printf("\n%s %s\n",
            bench::TimingRule(reps,
                              "loads nothing but builds the schedule, stepper "
                              "and every cache from the parsed profile")
                .c_str(),
            "The two sides run interleaved.");
  WindowsTable(md, args.quick ? 1 : 3);
  md.Printf("\n%s\n", bench::MachineLine().c_str());
  md.Emit(args.markdown);
  return 0;
}

#else  // !DEPLOYSIM_HAVE_SWEEP

#include <cstdio>

int main() {
  std::fprintf(stderr,
               "pipeline_bench: built without the sweep library (bench/CMakeLists.txt must link "
               "deploysim_sweep to pipeline_bench)\n");
  return 2;
}

#endif
