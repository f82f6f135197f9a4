// The full mission pipeline against the outcome-only path (issue 8, "dense output"):
// analysis::RunMission (schedule built, integration with the dense trajectory on the
// output grid, flip events, stage reports) against sweep::SimulateOutcome (the same
// schedule, stepper, tolerances and flip rule, no trajectory) for the same profile,
// each timed cold (everything a user's run builds is inside the timed region), best of
// the repetitions, and their ratio. Default profile: the main job,
// deployment_profiles/smallsat_three_stage.yaml (method exact, exact coupling,
// output dt 0.1 s). For `exact` it also times the closed form alone (H_B(t) and q_NB(t)
// at as many times as the trajectory has samples): the floor of a mission run whose
// dense output is the closed form itself.
//
// Usage: pipeline_bench [--quick] [--reps N] [--profile FILE] [--method NAME]
//        (--method overrides the profile's integrator, e.g. rkmk-rkf78 or dopri5)

#if defined(DEPLOYSIM_HAVE_SWEEP)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "bench_util.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/inertia.h"
#include "deploysim/schedule/deployment_schedule.h"
#include "deploysim/sweep/outcome.h"
#include "deploysim/sweep/sweep_spec.h"

namespace {

using namespace deploysim;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::string path =
      std::string(DEPLOYSIM_SOURCE_DIR) + "/deployment_profiles/smallsat_three_stage.yaml";
  std::string method;
  int reps = 5;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      reps = 2;
    } else if (std::strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
      reps = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--profile") == 0 && i + 1 < argc) {
      path = argv[++i];
    } else if (std::strcmp(argv[i], "--method") == 0 && i + 1 < argc) {
      method = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: pipeline_bench [--quick] [--reps N] [--profile FILE] [--method NAME]\n");
      return 2;
    }
  }
  schedule::Profile profile = io::LoadProfile(path);
  if (!method.empty()) profile.integrator.method = method;

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

  double best_mission = 1e300;
  double best_outcome = 1e300;
  analysis::MissionResult mission;
  sweep::CaseOutcome outcome;
  for (int r = 0; r < reps; ++r) {
    const Clock::time_point a = Clock::now();
    mission = analysis::RunMission(profile);
    const Clock::time_point b = Clock::now();
    best_mission = std::min(best_mission, Seconds(a, b));

    const Clock::time_point c = Clock::now();
    sweep::Case cs;
    cs.profile = outcome_profile;
    cs.schedule = std::make_shared<const schedule::DeploymentSchedule>(cs.profile);
    cs.spin_axis_B = sweep::BaseSpinAxis(cs.profile);
    outcome = sweep::SimulateOutcome(cs, sweep::OutcomeSettings{});
    const Clock::time_point d = Clock::now();
    best_outcome = std::min(best_outcome, Seconds(c, d));
  }

  std::printf("pipeline_bench: %s, method %s, %.0f s, output dt %g s (%zu samples)\n",
              profile.name.c_str(), profile.integrator.method.c_str(),
              profile.t_end() - profile.t_begin(), profile.output.dt, mission.trajectory.size());
  std::printf("machine: %s; best of %d cold runs each (setup included)\n",
              bench::CpuModel().c_str(), reps);
  std::printf("| path | wall [ms] | steps | flips |\n|---|---:|---:|---:|\n");
  std::printf("| RunMission (trajectory, events, stage reports) | %.2f | %ld | %zu |\n",
              1e3 * best_mission, mission.stats.steps, mission.flip_times.size());
  std::printf("| SimulateOutcome (outcome only) | %.2f | %lld | %lld |\n", 1e3 * best_outcome,
              static_cast<long long>(outcome.steps), static_cast<long long>(outcome.flip_count));
  std::printf("ratio RunMission / SimulateOutcome: %.2f\n", best_mission / best_outcome);

  // For context: the closed form alone at every output time (H_B(t) and q_NB(t), what
  // the `exact` method's dense output costs per sample), on the last rigid stage.
  if (profile.integrator.method == "exact") {
    const schedule::DeploymentSchedule sched(profile);
    const schedule::Stage& last = profile.stages.back();
    const dynamics::InertiaSample js = sched.Evaluate(last.t_end);
    const std::size_t n = mission.trajectory.size();
    const math::Vec3 H = mission.trajectory.H_B.back();
    const math::Quat q = mission.trajectory.q_NB.back();
    const analysis::FreeBodySolution sol(math::InertiaTensor::FromMatrix(js.J_B), H, q, last.t_end);
    double best = 1e300;
    double sink = 0.0;
    for (int r = 0; r < reps; ++r) {
      const Clock::time_point a = Clock::now();
      for (std::size_t i = 0; i < n; ++i) {
        const double t = last.t_begin + (last.t_end - last.t_begin) * static_cast<double>(i) /
                                            static_cast<double>(n);
        sink += sol.H_B(t).x() + sol.q_NB(t).w();
      }
      best = std::min(best, Seconds(a, Clock::now()));
    }
    std::printf(
        "closed form alone (H_B and q_NB at %zu times): %.2f ms = %.2f x the outcome path "
        "(checksum %.3g)\n",
        n, 1e3 * best, best / best_outcome, sink);
  }
  if (mission.stats.steps != outcome.steps ||
      static_cast<long long>(mission.flip_times.size()) != outcome.flip_count) {
    std::printf("note: the two paths took different steps or found different flips\n");
  }
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
