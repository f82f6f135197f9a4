#pragma once

/// Explicit Runge-Kutta on the vector state y = (H_B, q_NB) in R^7:
///   H_B' = H_B x w,  q_NB' = 1/2 q_NB (0, w),  w = J_B(t)^-1 (H_B - h_rel_B(t)).
/// The quaternion is renormalized after every step (a projection that keeps the
/// method's order). |H_B| and h_N are conserved only to the method's accuracy.

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class ExplicitRkStepper final : public Stepper {
 public:
  /// `tableau` must outlive the stepper (the library's tableaus are static).
  ExplicitRkStepper(const ButcherTableau& tableau, std::string name, std::string summary);
  const StepperInfo& info() const override { return info_; }
  StepAttempt Step(const Problem& problem,
                   const State& y,
                   double h,
                   const Tolerances& tol) const override;

 private:
  const ButcherTableau& tableau_;
  StepperInfo info_;
};

}  // namespace deploysim::integrators
