#pragma once

/// The seed thesis's scheme, kept as the baseline every method is compared to
/// (docs/design.md 2.2; thesis eqs. 3.13-3.15 and 2.66-2.70): explicit Euler on H_B,
///   H(t+h) = H(t) + h H(t) x w(t),
/// and rotation reconstruction with the midpoint angular velocity held constant,
///   R(t+h) = R(t) Exp(h (w(t) + w(t+h)) / 2)   (Rodrigues, thesis 2.68).
/// First order. It does NOT conserve |H_B|: for the wing nut at h = 2e-5 s over 40 s
/// |H_B| drifts by about 9e-4 relative. Dense output: cubic Hermite on (H_B, q_NB) with
/// the derivatives at both ends (more accurate than the method itself).

#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class ThesisEulerStepper final : public Stepper {
 public:
  ThesisEulerStepper();
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

 private:
  StepperInfo info_;
};

}  // namespace deploysim::integrators
