#pragma once

/// Explicit Runge-Kutta on the vector state y = (H_B, q_NB) in R^7:
///   H_B' = H_B x w,  q_NB' = 1/2 q_NB (0, w),  w = J_B(t)^-1 (H_B - h_rel_B(t)).
/// The quaternion is renormalized after every step (a projection that keeps the
/// method's order). |H_B| and h_N are conserved only to the method's accuracy.
/// The momentum is updated with compensated (Kahan) summation; its carry lives in the
/// run's workspace, keyed on the state it belongs to (StepperWorkspace).
///
/// Dense output (continuous extension of an accepted step, on the 7-vector, the
/// quaternion renormalized):
///   - Dormand-Prince 5(4): its own fourth-order continuous extension (dense_output.h),
///     free (the seven stages of the step, FSAL);
///   - methods of order <= 4 (rk4): cubic Hermite on (y, f) at both ends, O(h^4)
///     locally like the method's own error, one extra right-hand side per step;
///   - higher orders (Fehlberg 7(8)): Hermite of degree 9 on (y, f) at the five nodes
///     theta = 0, 1/4, 1/2, 3/4, 1, the three interior ones from partial steps (three
///     per accepted step that has output samples, instead of one per sample), O(h^10)
///     locally. Measured against the method's own partial steps over a tumbling run at
///     rtol 1e-10 (tests/integrators/dense_output_test.cpp): 4e-14 |H| (3e-13 rad) for
///     rkf78, 6e-13 for rkmk-rkf78; the quintic Hermite (midpoint only) is 2.8e-9 and
///     1.4e-8, degree 7 (four nodes) 1.7e-12 and 2.4e-11: not enough at rtol 1e-10.
///     DOPRI5's extension: 7e-12 |H|, 2e-11 rad; cubic Hermite for rk4 (h = 0.01 s)
///     3e-11.

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/dense_output.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class ExplicitRkStepper final : public Stepper {
 public:
  /// `tableau` must outlive the stepper (the library's tableaus are static).
  ExplicitRkStepper(const ButcherTableau& tableau, std::string name, std::string summary);
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
