#pragma once

/// Runge-Kutta-Munthe-Kaas methods on SO(3) for R_NB' = R_NB [w]x (DESIGN.md 2.1).
/// The attitude is the whole state: H_B = R_NB^T h_N with h_N fixed, so h_N and |H_B|
/// are conserved to rounding by construction, for constant and time-varying J alike.
/// With R = R0 Exp(u), u' = J_r^{-1}(u) w(R0 Exp(u)) is solved by the tableau's RK
/// method; with the exact inverse Jacobian the Lie-group method keeps the tableau's
/// order. Reference: H. Munthe-Kaas, "High order Runge-Kutta methods on manifolds",
/// Appl. Numer. Math. 29 (1999) 115-127; Iserles et al., Acta Numerica 9 (2000).

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class RkmkStepper final : public Stepper {
 public:
  RkmkStepper(const ButcherTableau& tableau, std::string name, std::string summary);
  const StepperInfo& info() const override { return info_; }
  /// The input y.H_B is ignored: the momentum is R_NB^T h_N of problem.h_N().
  StepAttempt Step(const Problem& problem,
                   const State& y,
                   double h,
                   const Tolerances& tol) const override;

 private:
  const ButcherTableau& tableau_;
  StepperInfo info_;
};

}  // namespace deploysim::integrators
