#pragma once

/// Numerical steppers by name. The exact constant-inertia flow lives in the analysis
/// module (it needs the analytic solution); analysis/exact_flow.h extends this list.

#include <memory>
#include <string>
#include <vector>

#include "deploysim/integrators/butcher_tableau.h"
#include "deploysim/integrators/stepper.h"

namespace deploysim::integrators {

/// Names: "thesis-euler", "rk4", "dopri5", "rkf78", "rkmk4", "rkmk-dopri5", "rkmk-rkf78", "split4".
std::vector<std::string> NumericalStepperNames();

/// Throws std::invalid_argument listing the valid names for an unknown one.
std::unique_ptr<Stepper> MakeNumericalStepper(const std::string& name);

/// One numerical method of the registry: the one table of names, steppers and which
/// methods integrate free hinges.
struct MethodEntry {
  const char* name;
  const char* description;  ///< kExplicitRk and kRkmk (the others describe themselves).
  enum class Family { kThesisEuler, kExplicitRk, kRkmk, kSplitting } family;
  const ButcherTableau& (*tableau)();  ///< kExplicitRk and kRkmk; null otherwise.
};

/// The registry, in the order `deploysim methods` lists it. The RKMK entries are the
/// methods that integrate free hinges (shape_integrate.h, ShapeMethodNames).
const std::vector<MethodEntry>& NumericalMethods();

}  // namespace deploysim::integrators
