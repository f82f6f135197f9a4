// deploysim against Simbody 3.7 at matched accuracy (issue 5, benchmark rows 2 and 3):
//   A. the wing nut as a free rigid body over 40 s: Simbody's MobilizedBody::Free with
//      Runge-Kutta-Merson against deploysim's integrators and closed form;
//   B. the small satellite's deployment (models/smallsat.yaml), first 300 s: Simbody's
//      hinged model with prescribed hinge motion against deploysim with exact coupling.
// Errors are measured against the closed form (A) or a tight deploysim reference (B, the
// reduced model is exact for prescribed hinge motion: it agrees with Simbody to Simbody's
// accuracy, tests/crosscheck). Each Simbody run is matched with the fastest deploysim
// configuration that is at least as accurate; the table prints the wall-time ratio.
//
// Usage: simbody_bench [--quick]      (--quick: skips Simbody at accuracy 1e-14)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/analysis/mission.h"
#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/simbody_satellite.h"
#include "deploysim/dynamics/inertia_source.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/math/quaternion.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace {

using namespace deploysim;

struct Measured {
  std::string label;
  double error = 0.0;    // relative H_B error (max over the grid)
  double seconds = 0.0;  // wall time
};

template <class F>
double BestTime(F&& f, double min_total) {
  double best = 1e300, total = 0;
  for (int reps = 0; (total < min_total || reps < 3) && reps < 1000; ++reps) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, dt);
    total += dt;
  }
  return best;
}

// One Simbody run (prescribed hinges or a free body) at `accuracy`; its wall time in `sec`.
crosscheck::SimbodyRun TimedSimbody(const schedule::Profile& p,
                                    const std::vector<double>& grid,
                                    const math::Vec3& spin,
                                    double accuracy,
                                    double& sec) {
  crosscheck::SimbodyOptions o;
  o.accuracy = accuracy;
  o.locate_flips = false;
  const auto t0 = std::chrono::steady_clock::now();
  crosscheck::SimbodyRun run = crosscheck::RunSimbodyPrescribed(p, grid, spin, o);
  sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

// A deploysim run with `method` at `rtol` (atol = rtol/100); best wall time in `sec`.
integrators::IntegrationResult TimedDeploysim(const std::string& method,
                                              double rtol,
                                              const dynamics::InertiaSource& source,
                                              const integrators::State& s0,
                                              double t_end,
                                              const std::vector<double>& grid,
                                              double& sec) {
  integrators::IntegratorSettings st;
  st.tolerances = {rtol, rtol * 1e-2};
  const auto stepper = analysis::MakeStepper(method);
  integrators::IntegrationResult r;
  sec = BestTime([&] { r = integrators::Integrate(*stepper, st, source, s0, t_end, grid); }, 0.2);
  return r;
}

// Fastest deploysim row at least as accurate as `target` (nullptr if none); with
// `numerical_only`, rows of the closed-form flow are left out.
const Measured* Match(const std::vector<Measured>& ours, double target, bool numerical_only) {
  const Measured* best = nullptr;
  for (const Measured& m : ours) {
    if (numerical_only && m.label.rfind("exact (closed form", 0) == 0) continue;
    if (m.error <= target && (best == nullptr || m.seconds < best->seconds)) best = &m;
  }
  return best;
}

void PrintRows(const char* title,
               const std::vector<Measured>& simbody,
               const std::vector<Measured>& ours) {
  std::printf("\n%s\n\n", title);
  std::printf(
      "| Simbody run | Simbody error | Simbody [s] | matched deploysim run | deploysim error | "
      "deploysim [ms] | speed-up |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Measured& s : simbody) {
    for (bool numerical_only : {false, true}) {
      const Measured* m = Match(ours, s.error, numerical_only);
      if (m == nullptr) {
        std::printf("| %s | %.2e | %.3g | (none as accurate) | - | - | - |\n", s.label.c_str(),
                    s.error, s.seconds);
        continue;
      }
      if (numerical_only && m == Match(ours, s.error, false)) continue;  // same row
      std::printf("| %s | %.2e | %.3g | %s | %.2e | %.4g | %.0f |\n", s.label.c_str(), s.error,
                  s.seconds, m->label.c_str(), m->error, m->seconds * 1e3, s.seconds / m->seconds);
    }
  }
  std::printf("\ndeploysim configurations measured:\n");
  for (const Measured& m : ours) {
    std::printf("  %-28s error %.2e  %.4g ms\n", m.label.c_str(), m.error, m.seconds * 1e3);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const std::string src = DEPLOYSIM_SOURCE_DIR;
  std::printf("deploysim vs Simbody 3.7 (Runge-Kutta-Merson) at matched accuracy\n");
  std::printf("machine: %s; every time is wall clock, deploysim: best of repetitions\n",
              deploysim::bench::CpuModel().c_str());

  // ---- A. wing nut, free rigid body, 40 s ----
  {
    const schedule::Profile p = io::LoadProfile(src + "/deployment_profiles/wing_nut.yaml");
    const math::InertiaTensor J = math::InertiaTensor::FromMatrix(p.model.configurations[0].J_B);
    const math::Vec3 H0 = *p.initial.H_B;
    const double M = H0.norm();
    const analysis::FreeBodySolution exact(J, H0, math::Quat::Identity(), 0.0);
    const std::vector<double> grid = integrators::UniformGrid(0.0, 40.0, 1.0);
    auto error_of = [&](const std::vector<double>& t, const std::vector<math::Vec3>& H) {
      double e = 0;
      for (std::size_t i = 0; i < t.size(); ++i)
        e = std::max(e, (H[i] - exact.H_B(t[i])).norm() / M);
      return e;
    };
    std::vector<Measured> simbody;
    std::vector<double> accuracies = {1e-10, 1e-12};
    if (!quick) accuracies.push_back(1e-14);
    const math::Vec3 spin = analysis::InitialSpinAxis(J.matrix(), H0);
    for (double a : accuracies) {
      double sec = 0.0;
      const crosscheck::SimbodyRun run = TimedSimbody(p, grid, spin, a, sec);
      char label[64];
      std::snprintf(label, sizeof label, "Free body, accuracy %g", a);
      simbody.push_back({label, error_of(run.trajectory.time, run.trajectory.H_B), sec});
    }
    std::vector<Measured> ours;
    const dynamics::ConstantInertia source(J);
    const integrators::State s0{0.0, H0, math::Quat::Identity()};
    for (const auto& [method, rtol] :
         std::vector<std::pair<std::string, double>>{{"rkf78", 1e-6},
                                                     {"rkf78", 1e-8},
                                                     {"rkf78", 1e-10},
                                                     {"rkf78", 1e-12},
                                                     {"rkmk-rkf78", 1e-8},
                                                     {"rkmk-rkf78", 1e-10},
                                                     {"exact", 1e-12}}) {
      double sec = 0.0;
      const integrators::IntegrationResult r =
          TimedDeploysim(method, rtol, source, s0, 40.0, grid, sec);
      std::vector<double> t;
      std::vector<math::Vec3> H;
      for (const auto& y : r.samples) {
        t.push_back(y.t);
        H.push_back(y.H_B);
      }
      char label[64];
      std::snprintf(label, sizeof label, "%s rtol %g", method.c_str(), rtol);
      // The closed form is the reference itself here: its own error against a
      // long-double integration is 3.3e-12 (wing_nut_bench), which is what is shown.
      constexpr double kClosedFormError = 3.3e-12;
      ours.push_back({method == "exact" ? std::string("exact (closed form)") : label,
                      method == "exact" ? kClosedFormError : error_of(t, H), sec});
    }
    PrintRows(
        "A. Wing nut, free rigid body, 40 s (11 flips), output every 1 s; error: max |H_B - closed "
        "form| / |H|",
        simbody, ours);
  }

  // ---- B. small satellite deployment, 300 s ----
  {
    schedule::Profile p = io::LoadProfile(src + "/deployment_profiles/smallsat_three_stage.yaml");
    p = crosscheck::TruncateProfile(p, 300.0);
    const schedule::DeploymentSchedule sched(p);
    const math::Vec3 H0 = crosscheck::InitialMomentum(p);
    const integrators::State s0{0.0, H0, p.initial.q_NB};
    const double M = H0.norm();
    const std::vector<double> grid = {0.0, 300.0};
    const math::Vec3 spin = analysis::InitialSpinAxis(sched.Evaluate(0.0).J_B, H0);
    // Reference: deploysim exact flow + rkmk-rkf78 at rtol 1e-13.
    integrators::IntegratorSettings ref_st;
    ref_st.tolerances = {1e-13, 1e-15};
    const auto ref_stepper = analysis::MakeStepper("exact");
    const integrators::IntegrationResult ref =
        integrators::Integrate(*ref_stepper, ref_st, sched, s0, 300.0, grid);
    const math::Vec3 H_ref = ref.samples.back().H_B;
    std::vector<Measured> simbody;
    std::vector<double> accuracies = {1e-8, 1e-10, 1e-12};
    for (double a : accuracies) {
      double sec = 0.0;
      const crosscheck::SimbodyRun run = TimedSimbody(p, grid, spin, a, sec);
      char label[64];
      std::snprintf(label, sizeof label, "hinged, accuracy %g", a);
      simbody.push_back({label, (run.trajectory.H_B.back() - H_ref).norm() / M, sec});
    }
    std::vector<Measured> ours;
    for (const auto& [method, rtol] :
         std::vector<std::pair<std::string, double>>{{"exact", 1e-6},
                                                     {"exact", 1e-8},
                                                     {"exact", 1e-10},
                                                     {"exact", 1e-11},
                                                     {"rkmk-rkf78", 1e-8},
                                                     {"rkmk-rkf78", 1e-10},
                                                     {"rkf78", 1e-10}}) {
      double sec = 0.0;
      const integrators::IntegrationResult r =
          TimedDeploysim(method, rtol, sched, s0, 300.0, grid, sec);
      char label[64];
      std::snprintf(label, sizeof label, "%s rtol %g", method.c_str(), rtol);
      ours.push_back({label, std::max((r.samples.back().H_B - H_ref).norm() / M, 1e-16), sec});
    }
    PrintRows(
        "B. Small satellite, wings deployed in two stages, 300 s (2 flips), exact coupling; error: "
        "|H_B(300 s) - reference| / |H|",
        simbody, ours);
  }
  std::printf("\ntargets: A >= 10,000x, B >= 1,000x at matched accuracy\n");
  return 0;
}
