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

#include "deploysim/integrators/rkmk.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

class SplittingStepper final : public Stepper {
 public:
  SplittingStepper();
  const StepperInfo& info() const override { return info_; }
  StepAttempt Step(const Problem& problem,
                   const State& y,
                   double h,
                   const Tolerances& tol) const override;

 private:
  StepperInfo info_;
  RkmkStepper fallback_;
};

}  // namespace deploysim::integrators
