#pragma once

/// The exact flow of the torque-free rigid body, as a stepper: on every segment where
/// the inertia source is rigid (constant J_B, h_rel_B = 0) the state is advanced with
/// the closed-form solution (FreeBodySolution: Jacobi elliptic functions for H_B, the
/// elliptic integral of the third kind for the attitude), so a piecewise-constant
/// inertia schedule is integrated without truncation error. Elsewhere it delegates to a
/// numerical fallback stepper (default rkmk-rkf78).
///
/// The closed-form solution is built from the state a rigid segment starts from and
/// evaluated at every later time of the segment: restarting it from each step's end
/// state would add a rounding error per step, which the near-separatrix motion
/// amplifies. The solution is a per-run cache in the run's workspace (never in the
/// stepper, which is const and may be shared between threads), keyed by value: it is
/// used for a state only if that state is bit for bit the one it was built from or one
/// it returned (StepperWorkspace's keying rule), and rebuilt from any other state, so
/// Step always advances exactly the state it is given. Dense output is the closed form
/// itself; output samples (DenseSample) may come from a Chebyshev interpolant of it
/// accurate to rounding, when a step has many of them.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "deploysim/analysis/flip_rule.h"
#include "deploysim/analysis/free_body_solution.h"
#include "deploysim/integrators/integrate.h"
#include "deploysim/integrators/stepper.h"
#include "deploysim/math/inertia.h"

namespace deploysim::analysis {

class ExactFlowStepper final : public integrators::Stepper {
 public:
  explicit ExactFlowStepper(std::unique_ptr<integrators::Stepper> fallback);
  const integrators::StepperInfo& info() const override { return info_; }
  std::unique_ptr<integrators::StepperWorkspace> NewWorkspace() const override;
  integrators::StepAttempt Step(const integrators::Problem& problem,
                                const integrators::State& y,
                                double h,
                                const integrators::Tolerances& tol,
                                integrators::StepperWorkspace& ws) const override;
  void Accept(const integrators::Problem& problem,
              const integrators::State& y0,
              const integrators::State& y1,
              integrators::StepperWorkspace& ws) const override;
  integrators::State Dense(const integrators::Problem& problem,
                           double t,
                           const integrators::Tolerances& tol,
                           integrators::StepperWorkspace& ws) const override;
  /// Output samples on rigid steps: when the step has at least kMinFitSamples of them,
  /// a piecewise Chebyshev interpolant (chebyshev.h) of the closed form's H_B and unit
  /// q_NB (renormalised after evaluation), built on the first sample of the step from at
  /// most 3/4 as many closed-form values as there are samples; otherwise, or if no such
  /// fit is found, the closed form itself (Dense). The interpolant agrees with the
  /// closed form to the closed form's own rounding (which grows with t - t0 like
  /// eps lambda |t - t0| |H| and eps |w| |t - t0| rad) and is as accurate against an
  /// independent reference (tests/analysis/exact_flow_test.cpp). Events, event states
  /// and step results keep using the closed form (Dense, Step).
  integrators::State DenseSample(const integrators::Problem& problem,
                                 double t,
                                 std::size_t samples,
                                 const integrators::Tolerances& tol,
                                 integrators::StepperWorkspace& ws) const override;
  bool DenseIsExact(const integrators::StepperWorkspace& ws) const override;
  /// Fewest output samples in one rigid step for which DenseSample fits an interpolant.
  static constexpr std::size_t kMinFitSamples = 40;
  /// An eighth of the period of H_B on rigid segments, so that every flip (every half
  /// period) is seen by the event detection; the fallback's limit elsewhere.
  double MaxStep(const integrators::Problem& problem,
                 const integrators::State& y,
                 integrators::StepperWorkspace& ws) const override;

 private:
  std::unique_ptr<integrators::Stepper> fallback_;
  integrators::StepperInfo info_;
};

/// The closed-form method's name, and the numerical method it hands every segment the
/// closed form cannot take (a moving stage, a free hinge): the one statement of that
/// fallback (MakeStepper, the free-hinge runs and the work estimate use it).
inline constexpr const char* kExactMethod = "exact";
inline constexpr const char* kExactFallback = "rkmk-rkf78";

/// True for the closed-form method.
inline bool IsExact(const std::string& method) { return method == kExactMethod; }

/// The numerical method that integrates `method`'s non-rigid segments: `method` itself,
/// or kExactFallback for exact.
inline std::string NumericalMethodOf(const std::string& method) {
  return IsExact(method) ? kExactFallback : method;
}

/// All stepper names: the numerical ones and "exact".
std::vector<std::string> StepperNames();

/// A stepper by name ("exact" uses kExactFallback on non-rigid segments).
std::unique_ptr<integrators::Stepper> MakeStepper(const std::string& name);

/// The rules on `integrator.method` and `integrator.step`, as the text a message puts after
/// the key ("unknown integrator (valid: ...)", "the fixed-step method rk4 needs
/// integrator.step > 0 [s]"); empty when kept. The one statement of them, for profiles
/// (CheckRunSettings) and sweep files.
std::string MethodRuleViolated(const std::string& method);
std::string StepRuleViolated(const std::string& method, double step);

/// True when `method` can run a profile with free hinges: a Lie-group method
/// (integrators::ShapeMethodNames: h_N exact by construction) or exact (closed form while
/// every hinge is locked, rkmk-rkf78 while one is free).
bool RunsFreeHinges(const std::string& method);

/// The rule RunsFreeHinges decides, for messages: "free hinges need a Lie-group method
/// (rule: one of rkmk4, rkmk-dopri5, rkmk-rkf78, exact: ...)".
std::string FreeHingeMethodRule();

/// FlipEvent (the flip of a body of constant inertia) is in flip_rule.h.

}  // namespace deploysim::analysis
