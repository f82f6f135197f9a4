#pragma once

/// Numerical steppers by name. The exact constant-inertia flow lives in the analysis
/// module (it needs the analytic solution); analysis/exact_flow.h extends this list.

#include <memory>
#include <string>
#include <vector>

#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

/// Names: "thesis-euler", "rk4", "dopri5", "rkf78", "rkmk4", "rkmk-dopri5", "rkmk-rkf78", "split4".
std::vector<std::string> NumericalStepperNames();

/// Throws std::invalid_argument listing the valid names for an unknown one.
std::unique_ptr<Stepper> MakeNumericalStepper(const std::string& name);

}  // namespace deploysim::integrators
