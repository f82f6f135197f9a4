#pragma once

/// Runge-Kutta-Munthe-Kaas methods on SO(3) for R_NB' = R_NB [w]x (docs/design.md 2.1).
/// The attitude is the whole state: H_B = R_NB^T h_N with h_N fixed, so h_N and |H_B|
/// are conserved to rounding by construction, for constant and time-varying J alike.
/// With R = R0 Exp(u), u' = J_r^{-1}(u) w(R0 Exp(u)) is solved by the tableau's RK
/// method; with the exact inverse Jacobian the Lie-group method keeps the tableau's
/// order. Reference: H. Munthe-Kaas, "High order Runge-Kutta methods on manifolds",
/// Appl. Numer. Math. 29 (1999) 115-127; Iserles et al., Acta Numerica 9 (2000).
///
/// State: the attitude relative to the state a run starts from (its anchor), in the
/// run's workspace: R_NB(t) = R_NB(t0) dR(t), H_B(t) = dR(t)^T H_B(t0), so h_N is
/// conserved to rounding and H_B(t0) is the given momentum bit for bit. dR carries its
/// rounding error in extended precision (the next step folds it in). A state the
/// workspace did not produce becomes a new anchor: Step advances exactly the state it
/// is given.
///
/// Dense output: Hermite interpolation of the Lie-algebra coordinate u of the step (the
/// spin about h_N is exact), R(t0 + tau) = Exp(sigma tau h_N) R0 Exp(u(tau)):
/// the Dormand-Prince continuous extension for rkmk-dopri5, cubic Hermite on
/// (u, u') at both ends for rkmk4, Hermite of degree 9 on five nodes (the interior ones
/// from partial steps) for rkmk-rkf78 (see explicit_rk.h for the measured errors).

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class RkmkStepper final : public Stepper {
 public:
  RkmkStepper(const ButcherTableau& tableau, std::string name, std::string summary);
  const StepperInfo& info() const override { return info_; }
  std::unique_ptr<StepperWorkspace> NewWorkspace() const override;
  StepAttempt Step(const Problem& problem,
                   const State& y,
                   double h,
                   const Tolerances& tol,
                   StepperWorkspace& ws) const override;
  void Accept(const Problem& problem,
              const State& y0,
              const State& y1,
              StepperWorkspace& ws) const override;
  State Dense(const Problem& problem,
              double t,
              const Tolerances& tol,
              StepperWorkspace& ws) const override;

  /// Nodes (ends included, equispaced) of the Hermite interpolant of the high-order methods.
  static constexpr int kHighOrderHermiteNodes = kStepHermiteNodes;

 private:
  const ButcherTableau& tableau_;
  StepperInfo info_;
  DenseKind dense_;
};

}  // namespace deploysim::integrators
