#pragma once

/// The exact flow of the torque-free rigid body, as a stepper: on every segment where
/// the inertia source is rigid (constant J_B, h_rel_B = 0) the state is advanced with
/// the closed-form solution (FreeBodySolution: Jacobi elliptic functions for H_B, the
/// elliptic integral of the third kind for the attitude), so a piecewise-constant
/// inertia schedule is integrated without truncation error. Elsewhere it delegates to a
/// numerical fallback stepper (default rkmk-rkf78).

#include <memory>
#include <string>
#include <vector>

#include "integrators/integrate.h"
#include "integrators/stepper.h"
#include "math/inertia.h"

namespace deploysim::analysis {

class ExactFlowStepper final : public integrators::Stepper {
 public:
  explicit ExactFlowStepper(std::unique_ptr<integrators::Stepper> fallback);
  const integrators::StepperInfo& info() const override { return info_; }
  integrators::StepAttempt Step(const integrators::Problem& problem,
                                const integrators::State& y,
                                double h,
                                const integrators::Tolerances& tol) const override;
  /// An eighth of the period of H_B on rigid segments, so that every flip (every half
  /// period) is seen by the event detection; the fallback's limit elsewhere.
  double MaxStep(const integrators::Problem& problem,
                 const integrators::State& y) const override;

 private:
  std::unique_ptr<integrators::Stepper> fallback_;
  integrators::StepperInfo info_;
};

/// All stepper names: the numerical ones and "exact".
std::vector<std::string> StepperNames();

/// A stepper by name ("exact" uses rkmk-rkf78 on non-rigid segments).
std::unique_ptr<integrators::Stepper> MakeStepper(const std::string& name);

/// The Dzhanibekov flip of a body of constant inertia: the sign of the momentum
/// component along the intermediate principal axis. Throws std::invalid_argument when
/// two principal moments are equal (no intermediate axis, no flip).
integrators::EventFunction FlipEvent(const math::InertiaTensor& J_B);

}  // namespace deploysim::analysis
