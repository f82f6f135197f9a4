#include "deploysim/analysis/exact_flow.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/integrators/factory.h"

namespace deploysim::analysis {

namespace {
// Steps per period of H_B on rigid segments: 8 keeps every flip (each half period) in a
// step of its own with a margin; the closed form has no truncation error at any step.
constexpr double kStepsPerPeriod = 8.0;
}  // namespace

ExactFlowStepper::ExactFlowStepper(std::unique_ptr<integrators::Stepper> fallback)
    : fallback_(std::move(fallback)) {
  info_.name = "exact";
  info_.summary = "closed-form constant-inertia flow (elliptic functions); " +
                  fallback_->info().name + " where the inertia changes";
  info_.reference =
      "Jacobi elliptic solution (Wittenburg 2008; thesis 2.22-2.64); attitude: Celledoni, "
      "Fasso, Safstrom, Zanna, SIAM J. Sci. Comput. 30(4) 2008";
  info_.order = fallback_->info().order;
  info_.error_order = fallback_->info().error_order;
  info_.adaptive = true;
  info_.lie_group = fallback_->info().lie_group;
}

const FreeBodySolution& ExactFlowStepper::SolutionFor(const integrators::Problem& problem,
                                                      const integrators::State& y) const {
  const double begin = problem.segment_begin();
  const bool same_segment = cache_.solution && cache_.source == &problem.source() &&
                            cache_.begin == begin && y.t >= begin;
  // A state at the segment start (the first step, or a new run) rebuilds the solution;
  // later states of the same segment are the cached solution's own values.
  const bool at_start = y.t == begin;
  const bool new_start =
      at_start && (y.H_B != cache_.H_B0 || y.q_NB.coeffs() != cache_.q_NB0.coeffs());
  if (!same_segment || new_start) {
    const dynamics::InertiaSample s = problem.source().Evaluate(y.t);
    cache_.begin = begin;
    cache_.source = &problem.source();
    cache_.H_B0 = y.H_B;
    cache_.q_NB0 = y.q_NB;
    cache_.solution.emplace(math::InertiaTensor::FromMatrix(s.J_B), y.H_B, y.q_NB, y.t);
  }
  return *cache_.solution;
}

integrators::StepAttempt ExactFlowStepper::Step(const integrators::Problem& problem,
                                                const integrators::State& y,
                                                double h,
                                                const integrators::Tolerances& tol) const {
  if (!problem.source().IsRigidOn(y.t, y.t + h)) return fallback_->Step(problem, y, h, tol);
  const FreeBodySolution& sol = SolutionFor(problem, y);
  integrators::StepAttempt out;
  out.result.t = y.t + h;
  out.result.H_B = sol.H_B(out.result.t);
  out.result.q_NB = sol.q_NB(out.result.t).normalized();
  out.error_norm = 0.0;
  return out;
}

double ExactFlowStepper::MaxStep(const integrators::Problem& problem,
                                 const integrators::State& y) const {
  const double end = problem.segment_end();
  if (!problem.source().IsRigidOn(y.t, end)) return fallback_->MaxStep(problem, y);
  const double T = SolutionFor(problem, y).period();
  return std::isfinite(T) ? T / kStepsPerPeriod : std::numeric_limits<double>::infinity();
}

std::vector<std::string> StepperNames() {
  std::vector<std::string> names = integrators::NumericalStepperNames();
  names.push_back("exact");
  return names;
}

std::unique_ptr<integrators::Stepper> MakeStepper(const std::string& name) {
  if (name == "exact") {
    return std::make_unique<ExactFlowStepper>(integrators::MakeNumericalStepper("rkmk-rkf78"));
  }
  return integrators::MakeNumericalStepper(name);
}

integrators::EventFunction FlipEvent(const math::InertiaTensor& J_B) {
  const math::PrincipalAxes p = J_B.Principal();
  const double spread = p.moments[2] - p.moments[0];
  if (!(p.moments[1] - p.moments[0] > 1e-12 * spread &&
        p.moments[2] - p.moments[1] > 1e-12 * spread)) {
    throw std::invalid_argument(
        "flip event: two principal moments are equal, so there is no intermediate axis "
        "and no Dzhanibekov flip");
  }
  const math::Vec3 e = p.axes.col(1);
  return {"flip", [e](const integrators::State& s) { return s.H_B.dot(e); }};
}

}  // namespace deploysim::analysis
