#include "deploysim/integrators/factory.h"

#include <stdexcept>

#include "deploysim/integrators/explicit_rk.h"
#include "deploysim/integrators/rkmk.h"
#include "deploysim/integrators/splitting.h"
#include "deploysim/integrators/thesis_euler.h"

namespace deploysim::integrators {

std::vector<std::string> NumericalStepperNames() {
  return {"thesis-euler", "rk4", "dopri5", "rkf78", "rkmk4", "rkmk-dopri5", "rkmk-rkf78", "split4"};
}

std::unique_ptr<Stepper> MakeNumericalStepper(const std::string& name) {
  if (name == "thesis-euler") return std::make_unique<ThesisEulerStepper>();
  if (name == "rk4") {
    return std::make_unique<ExplicitRkStepper>(ClassicRk4(), name,
                                               "classic fourth-order Runge-Kutta, fixed step");
  }
  if (name == "dopri5") {
    return std::make_unique<ExplicitRkStepper>(DormandPrince54(), name,
                                               "Dormand-Prince 5(4), adaptive, on (H_B, q_NB)");
  }
  if (name == "rkf78") {
    return std::make_unique<ExplicitRkStepper>(Fehlberg78(), name,
                                               "Fehlberg 7(8), adaptive, on (H_B, q_NB)");
  }
  if (name == "rkmk4") {
    return std::make_unique<RkmkStepper>(
        ClassicRk4(), name, "Runge-Kutta-Munthe-Kaas 4 on SO(3), fixed step (Lie group)");
  }
  if (name == "rkmk-dopri5") {
    return std::make_unique<RkmkStepper>(
        DormandPrince54(), name, "Runge-Kutta-Munthe-Kaas with Dormand-Prince 5(4), adaptive");
  }
  if (name == "rkmk-rkf78") {
    return std::make_unique<RkmkStepper>(Fehlberg78(), name,
                                         "Runge-Kutta-Munthe-Kaas with Fehlberg 7(8), adaptive");
  }
  if (name == "split4") return std::make_unique<SplittingStepper>();
  std::string list;
  for (const auto& n : NumericalStepperNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown integrator '" + name + "' (valid: " + list + ", exact)");
}

}  // namespace deploysim::integrators
