#pragma once

/// Symplectic Lie-Poisson splitting for the free rigid body of constant inertia
/// (McLachlan, Phys. Rev. Lett. 71 (1993) 3043; Touma & Wisdom, Astron. J. 107 (1994);
/// Fasso, SIAM J. Numer. Anal. 41 (2003)). The kinetic energy
/// T = sum_i H_i^2 / (2 I_i) in principal axes is split into three terms whose flows are
/// exact rotations about one principal axis (H_i and the rate H_i/I_i are constant).
/// The symmetric Strang product Phi1(h/2) Phi2(h/2) Phi3(h) Phi2(h/2) Phi1(h/2) is
/// second order; Yoshida's triple jump (Phys. Lett. A 150 (1990) 262) makes it fourth
/// order. Being symplectic and symmetric it keeps the energy error bounded (no drift);
/// being a product of rotations it keeps h_N and |H_B| to rounding.
/// Only for constant inertia with h_rel = 0: on other segments it takes an rkmk4 step.
/// Like the RKMK steppers it carries the attitude relative to the state it starts from
/// (rkmk.h), so H_B(t0) is the given momentum bit for bit. Dense output: cubic Hermite
/// in the Lie algebra, R(t0 + tau) = R0 Exp(u(tau)), u(0) = 0, u'(0) = w0,
/// u(h) = Log(R0^T R1), u'(h) = dexp^{-1}_{u(h)} w1 (fourth order, like the method).

#include "deploysim/integrators/rkmk.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class SplittingStepper final : public Stepper {
 public:
  SplittingStepper();
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
  RkmkStepper fallback_;
};

}  // namespace deploysim::integrators
