#include "deploysim/analysis/exact_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "deploysim/analysis/chebyshev.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/integrators/carry_store.h"
#include "deploysim/integrators/factory.h"
#include "deploysim/integrators/shape_integrate.h"

namespace deploysim::analysis {

namespace {
// Steps per period of H_B on rigid segments: 8 keeps every flip (each half period) in a
// step of its own with a margin; the closed form has no truncation error at any step.
constexpr double kStepsPerPeriod = 8.0;
}  // namespace

ExactFlowStepper::ExactFlowStepper(std::unique_ptr<integrators::Stepper> fallback)
    : fallback_(std::move(fallback)) {
  info_.name = kExactMethod;
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
  /// Interpolant of the closed form over the last accepted rigid step for output samples
  /// (tried once per step, on its first sample).
  ChebyshevFit fit;
  bool fit_tried = false;
  bool fit_ok = false;
  std::vector<double> fit_scale, fit_noise;
  /// The rotation taken out of the fitted attitude: about spin_axis_N (unit, h_N) by
  /// spin_rate (t - spin_mid).
  math::Vec3 spin_axis_N = math::Vec3::UnitZ();
  double spin_rate = 0.0;
  double spin_mid = 0.0;
};

math::Quat SpinAbout(const ExactFlowWorkspace& ws, double t) {
  const double half = 0.5 * ws.spin_rate * (t - ws.spin_mid);
  const double s = std::sin(half);
  return math::Quat(std::cos(half), s * ws.spin_axis_N.x(), s * ws.spin_axis_N.y(),
                    s * ws.spin_axis_N.z());
}

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
  sol.StateAt(t, &s.H_B, &s.q_NB);
  s.q_NB.normalize();
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
  ws.fit_tried = false;
  ws.fit_ok = false;
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

integrators::State ExactFlowStepper::DenseSample(const integrators::Problem& problem,
                                                 double t,
                                                 std::size_t samples,
                                                 const integrators::Tolerances& tol,
                                                 integrators::StepperWorkspace& workspace) const {
  auto& ws = static_cast<ExactFlowWorkspace&>(workspace);
  if (ws.accepted_by_fallback)
    return fallback_->DenseSample(problem, t, samples, tol, *ws.fallback_ws);
  if (t <= ws.step_begin.t) return ws.step_begin;
  if (t >= ws.step_end.t) return ws.step_end;
  const FreeBodySolution& sol = SolutionFor(problem, ws.step_begin, ws);
  if (!ws.fit_tried) {
    ws.fit_tried = true;
    ws.fit_ok = false;
    const double M = sol.momentum_magnitude();
    if (samples >= kMinFitSamples && M > 0.0 && std::isfinite(M)) {
      // Rounding of the closed form's values: H_B depends on the elliptic argument
      // u = lambda (t - t0) + u0, rounded to eps |u| (|u0| <= 2 K, K = lambda T / 4, and
      // K < 40 for any 1 - k^2 >= 1e-30), with |dH/du| <= M; q_NB on the angle gamma about h_N,
      // rounded to eps |gamma|, |gamma'| <= 2 M / I1 (free_body_solution.h).
      constexpr double eps = std::numeric_limits<double>::epsilon();
      const double tau = std::max(std::abs(ws.step_begin.t - ws.built_from.t),
                                  std::abs(ws.step_end.t - ws.built_from.t));
      const double I1 = sol.principal_axes().moments[0];
      const double K = std::isfinite(sol.period()) ? 0.25 * sol.lambda() * sol.period() : 40.0;
      const double noise_H = eps * M * (1.0 + 2.0 * K + sol.lambda() * tau);
      const double noise_q = I1 > 0.0 ? eps * (2.0 + 2.0 * M / I1 * tau) : eps;
      ws.fit_scale.assign({M, M, M, 1.0, 1.0, 1.0, 1.0});
      ws.fit_noise.assign({noise_H, noise_H, noise_H, noise_q, noise_q, noise_q, noise_q});
      // The attitude is fitted with a uniform rotation about h_N at about its mean rate
      // taken out (SpinAbout, multiplied back after evaluation): the fitted components
      // then vary more slowly (measured: ~10% smaller attitude differences).
      const math::Vec3 h_N = ws.step_begin.q_NB * ws.step_begin.H_B;
      ws.spin_axis_N = h_N / h_N.norm();
      ws.spin_rate = 2.0 * sol.energy() / M;  // w . H / |H|: near the mean rate
      ws.spin_mid = 0.5 * (ws.step_begin.t + ws.step_end.t);
      auto f = [&sol, &ws](double s, double* out) {
        math::Vec3 H;
        math::Quat q_cf;
        sol.StateAt(s, &H, &q_cf);
        const math::Quat q = SpinAbout(ws, s).conjugate() * q_cf.normalized();
        out[0] = H.x();
        out[1] = H.y();
        out[2] = H.z();
        out[3] = q.w();
        out[4] = q.x();
        out[5] = q.y();
        out[6] = q.z();
      };
      ws.fit_ok = ws.fit.Build(f, ws.step_begin.t, ws.step_end.t, ws.fit_scale, ws.fit_noise,
                               3 * samples / 4);
    }
  }
  if (!ws.fit_ok) return ClosedFormAt(sol, t);
  double v[7];
  ws.fit.Evaluate(t, v);
  integrators::State s;
  s.t = t;
  s.H_B = math::Vec3(v[0], v[1], v[2]);
  s.q_NB = (SpinAbout(ws, t) * math::Quat(v[3], v[4], v[5], v[6])).normalized();
  return s;
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
  names.push_back(kExactMethod);
  return names;
}

std::string MethodRuleViolated(const std::string& method) {
  const std::vector<std::string> names = StepperNames();
  std::string list;
  for (const std::string& n : names) {
    if (n == method) return "";
    list += (list.empty() ? "" : ", ") + n;
  }
  return "unknown integrator (valid: " + list + ")";
}

std::string StepRuleViolated(const std::string& method, double step) {
  if (MakeStepper(method)->info().adaptive || step > 0.0) return "";
  return "the fixed-step method " + method + " needs integrator.step > 0 [s]";
}

bool RunsFreeHinges(const std::string& method) {
  return IsExact(method) || integrators::IsShapeMethod(method);
}

std::string FreeHingeMethodRule() {
  std::string list;
  for (const std::string& m : integrators::ShapeMethodNames()) list += m + ", ";
  return "free hinges need a Lie-group method (rule: one of " + list +
         "exact: closed form while every hinge is locked)";
}

std::unique_ptr<integrators::Stepper> MakeStepper(const std::string& name) {
  if (IsExact(name)) {
    return std::make_unique<ExactFlowStepper>(
        integrators::MakeNumericalStepper(NumericalMethodOf(name)));
  }
  return integrators::MakeNumericalStepper(name);
}

}  // namespace deploysim::analysis
