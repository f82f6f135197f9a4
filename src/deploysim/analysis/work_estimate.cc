#include "deploysim/analysis/work_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/math/inertia.h"
#include "deploysim/math/number_format.h"
#include "deploysim/schedule/deployment_schedule.h"

namespace deploysim::analysis {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// Largest |w|^2 = sum h_i^2 / I_i^2 of a rigid body with principal moments I (ascending)
// over every h with |h|^2 = M2 and sum h_i^2 / I_i = two_T: a linear programme in
// x_i = h_i^2 >= 0, whose optimum lies on a vertex (two x_i nonzero, or one).
double MaxRateSquaredOnEllipsoid(const math::Vec3& I, double M2, double two_T) {
  double best = 0.0;
  bool any = false;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double ai = 1.0 / I[i];
      const double aj = 1.0 / I[j];
      if (!(ai > aj)) continue;  // equal moments: the pair is one direction
      const double xi = (two_T - M2 * aj) / (ai - aj);
      // Rounding of two_T may put a vertex a hair outside: clamp it back.
      const double tol = 1e-9 * M2;
      if (!(xi >= -tol && xi <= M2 + tol)) continue;
      const double x = std::clamp(xi, 0.0, M2);
      best = std::max(best, x * ai * ai + (M2 - x) * aj * aj);
      any = true;
    }
  }
  // All moments equal (or no vertex found by rounding): |w| = M / I.
  if (!any) best = M2 / (I[0] * I[0]);
  return best;
}

// Three significant digits: the messages' numbers are estimates.
std::string Num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace

WorkEstimate EstimateWork(const schedule::Profile& profile) {
  WorkEstimate out;
  if (profile.stages.empty()) return out;
  const schedule::DeploymentSchedule sched(profile);
  const double t0 = profile.t_begin();
  const dynamics::InertiaSample s0 = sched.Evaluate(t0);
  const math::Vec3 H0 =
      profile.initial.H_B
          ? *profile.initial.H_B
          : math::Vec3(s0.J_B * profile.initial.w_NB_B.value_or(math::Vec3::Zero()) + s0.h_rel_B);
  const double M = H0.norm();
  out.momentum = M;
  const bool adaptive = MakeStepper(profile.integrator.method)->info().adaptive;

  for (std::size_t k = 0; k < profile.stages.size(); ++k) {
    const schedule::Stage& st = profile.stages[k];
    StageWork w;
    w.duration = st.t_end - st.t_begin;
    const bool rigid = sched.IsRigidOn(st.t_begin, st.t_end);
    double rate2 = 0.0;
    if (rigid && k == 0) {
      // The initial state is known: the exact largest |w| on its energy ellipsoid.
      const dynamics::InertiaSample js = sched.Evaluate(st.t_begin, dynamics::Side::kRight);
      const math::PrincipalAxes pa = math::PrincipalDecomposition(js.J_B);
      const math::Vec3 h = pa.axes.transpose() * H0;
      const math::Vec3 I = pa.moments;
      const double two_T = h[0] * h[0] / I[0] + h[1] * h[1] / I[1] + h[2] * h[2] / I[2];
      rate2 = MaxRateSquaredOnEllipsoid(I, h.squaredNorm(), two_T);
    } else {
      const int n = rigid ? 1 : kMoveSamples;
      for (int i = 0; i < n; ++i) {
        const double t =
            rigid ? st.t_begin
                  : st.t_begin + (st.t_end - st.t_begin) * (static_cast<double>(i) / (n - 1));
        const dynamics::InertiaSample js = sched.Evaluate(
            t, i + 1 == n && !rigid ? dynamics::Side::kLeft : dynamics::Side::kRight);
        const double I_min = math::PrincipalDecomposition(js.J_B).moments[0];
        const double r = (M + js.h_rel_B.norm()) / I_min;
        rate2 = std::max(rate2, r * r);
      }
    }
    w.max_rate = std::sqrt(rate2);
    w.turns = w.max_rate * w.duration / kTwoPi;
    if (!adaptive && profile.integrator.step > 0.0) {
      w.fixed_steps = std::ceil(w.duration / profile.integrator.step);
    }
    out.finite = out.finite && std::isfinite(w.turns) && std::isfinite(w.fixed_steps);
    out.turns += w.turns;
    out.fixed_steps += w.fixed_steps;
    out.stages.push_back(w);
  }
  return out;
}

void CheckWork(const schedule::Profile& profile) {
  const WorkEstimate e = EstimateWork(profile);
  if (!e.finite || e.stages.empty()) return;
  const std::string where =
      profile.source.empty() ? "profile '" + profile.name + "'" : profile.source;
  // The stage that asks the most, for the message.
  std::size_t worst = 0;
  for (std::size_t k = 1; k < e.stages.size(); ++k) {
    if (e.stages[k].turns > e.stages[worst].turns) worst = k;
  }
  if (!(e.turns <= kMaxTurns)) {
    const StageWork& w = e.stages[worst];
    throw std::invalid_argument(where + ": the run asks for up to " + Num(e.turns) +
                                " turns of the body (stage '" + profile.stages[worst].name +
                                "': |w| up to " + Num(w.max_rate) + " rad/s for " +
                                Num(w.duration) + " s; rule: at most " + Num(kMaxTurns) +
                                " turns per run: shorten the stages or lower the spin)");
  }
  if (!(e.fixed_steps <= kMaxFixedSteps)) {
    throw std::invalid_argument(where + ": integrator.step = " + Num(profile.integrator.step) +
                                ": gives " + Num(e.fixed_steps) + " steps over " +
                                Num(profile.t_end() - profile.t_begin()) + " s (rule: at most " +
                                Num(kMaxFixedSteps) + " steps of a fixed-step method per run)");
  }
}

}  // namespace deploysim::analysis
