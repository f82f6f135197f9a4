#include "deploysim/analysis/exact_flow.h"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/integrators/carry_store.h"
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

namespace {

class ExactFlowWorkspace final : public integrators::StepperWorkspace {
 public:
  explicit ExactFlowWorkspace(std::unique_ptr<integrators::StepperWorkspace> fallback)
      : fallback_ws(std::move(fallback)) {}
  std::unique_ptr<integrators::StepperWorkspace> fallback_ws;
  /// The closed form of the current rigid segment, the state it was built from, and the
  /// states it returned (value: the generation of the solution that returned them).
  std::optional<FreeBodySolution> solution;
  long generation = 0;
  double segment_begin = 0.0;
  double segment_end = 0.0;
  integrators::State built_from;
  integrators::CarryStore<long> returned;
  bool last_by_fallback = false;
  bool accepted_by_fallback = false;
};

// The closed form through y on the current rigid segment: the cached one if y lies on
// it bit for bit, else one built from y.
const FreeBodySolution& SolutionFor(const integrators::Problem& problem,
                                    const integrators::State& y,
                                    ExactFlowWorkspace& ws) {
  if (ws.solution && ws.segment_begin == problem.segment_begin() &&
      ws.segment_end == problem.segment_end()) {
    if (integrators::SameBits(y, ws.built_from)) return *ws.solution;
    const long* g = ws.returned.Find(y);
    if (g != nullptr && *g == ws.generation) return *ws.solution;
  }
  const dynamics::InertiaSample s = problem.source().Evaluate(y.t);
  ws.solution.emplace(math::InertiaTensor::FromMatrix(s.J_B), y.H_B, y.q_NB, y.t);
  ++ws.generation;
  ws.segment_begin = problem.segment_begin();
  ws.segment_end = problem.segment_end();
  ws.built_from = y;
  return *ws.solution;
}

integrators::State ClosedFormAt(const FreeBodySolution& sol, double t) {
  integrators::State s;
  s.t = t;
  s.H_B = sol.H_B(t);
  s.q_NB = sol.q_NB(t).normalized();
  return s;
}

}  // namespace

std::unique_ptr<integrators::StepperWorkspace> ExactFlowStepper::NewWorkspace() const {
  return std::make_unique<ExactFlowWorkspace>(fallback_->NewWorkspace());
}

integrators::StepAttempt ExactFlowStepper::Step(const integrators::Problem& problem,
                                                const integrators::State& y,
                                                double h,
                                                const integrators::Tolerances& tol,
                                                integrators::StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExactFlowWorkspace&>(workspace);
  if (!problem.source().IsRigidOn(y.t, y.t + h)) {
    ws.last_by_fallback = true;
    return fallback_->Step(problem, y, h, tol, *ws.fallback_ws);
  }
  ws.last_by_fallback = false;
  const FreeBodySolution& sol = SolutionFor(problem, y, ws);
  integrators::StepAttempt out;
  out.result = ClosedFormAt(sol, y.t + h);
  out.error_norm = 0.0;
  ws.returned.Propose(out.result, ws.generation);
  return out;
}

void ExactFlowStepper::Accept(const integrators::Problem& problem,
                              const integrators::State& y0,
                              const integrators::State& y1,
                              integrators::StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExactFlowWorkspace&>(workspace);
  ws.step_begin = y0;
  ws.step_end = y1;
  ws.accepted_by_fallback = ws.last_by_fallback;
  if (ws.last_by_fallback) {
    fallback_->Accept(problem, y0, y1, *ws.fallback_ws);
  } else {
    ws.returned.Accept(y1);
  }
}

integrators::State ExactFlowStepper::Dense(const integrators::Problem& problem,
                                           double t,
                                           const integrators::Tolerances& tol,
                                           integrators::StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExactFlowWorkspace&>(workspace);
  if (ws.accepted_by_fallback) return fallback_->Dense(problem, t, tol, *ws.fallback_ws);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  return ClosedFormAt(SolutionFor(problem, ws.step_begin, ws), t);
}

bool ExactFlowStepper::DenseIsExact(const integrators::StepperWorkspace& workspace) const {
  return !static_cast<const ExactFlowWorkspace&>(workspace).accepted_by_fallback;
}

double ExactFlowStepper::MaxStep(const integrators::Problem& problem,
                                 const integrators::State& y,
                                 integrators::StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExactFlowWorkspace&>(workspace);
  const double end = problem.segment_end();
  if (!problem.source().IsRigidOn(y.t, end)) return fallback_->MaxStep(problem, y, *ws.fallback_ws);
  const double T = SolutionFor(problem, y, ws).period();
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

}  // namespace deploysim::analysis
