#include "deploysim/integrators/factory.h"

#include <stdexcept>

#include "deploysim/integrators/explicit_rk.h"
#include "deploysim/integrators/rkmk.h"
#include "deploysim/integrators/splitting.h"
#include "deploysim/integrators/thesis_euler.h"

namespace deploysim::integrators {

const std::vector<MethodEntry>& NumericalMethods() {
  using F = MethodEntry::Family;
  static const std::vector<MethodEntry> methods{
      {"thesis-euler", "", F::kThesisEuler, nullptr},
      {"rk4", "classic fourth-order Runge-Kutta, fixed step", F::kExplicitRk, &ClassicRk4},
      {"dopri5", "Dormand-Prince 5(4), adaptive, on (H_B, q_NB)", F::kExplicitRk, &DormandPrince54},
      {"rkf78", "Fehlberg 7(8), adaptive, on (H_B, q_NB)", F::kExplicitRk, &Fehlberg78},
      {"rkmk4", "Runge-Kutta-Munthe-Kaas 4 on SO(3), fixed step (Lie group)", F::kRkmk,
       &ClassicRk4},
      {"rkmk-dopri5", "Runge-Kutta-Munthe-Kaas with Dormand-Prince 5(4), adaptive", F::kRkmk,
       &DormandPrince54},
      {"rkmk-rkf78", "Runge-Kutta-Munthe-Kaas with Fehlberg 7(8), adaptive", F::kRkmk, &Fehlberg78},
      {"split4", "", F::kSplitting, nullptr},
  };
  return methods;
}

std::vector<std::string> NumericalStepperNames() {
  std::vector<std::string> names;
  for (const MethodEntry& m : NumericalMethods()) names.emplace_back(m.name);
  return names;
}

std::unique_ptr<Stepper> MakeNumericalStepper(const std::string& name) {
  for (const MethodEntry& m : NumericalMethods()) {
    if (name != m.name) continue;
    switch (m.family) {
      case MethodEntry::Family::kThesisEuler:
        return std::make_unique<ThesisEulerStepper>();
      case MethodEntry::Family::kExplicitRk:
        return std::make_unique<ExplicitRkStepper>(m.tableau(), name, m.description);
      case MethodEntry::Family::kRkmk:
        return std::make_unique<RkmkStepper>(m.tableau(), name, m.description);
      case MethodEntry::Family::kSplitting:
        return std::make_unique<SplittingStepper>();
    }
  }
  std::string list;
  for (const auto& n : NumericalStepperNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown integrator '" + name + "' (valid: " + list + ", exact)");
}

}  // namespace deploysim::integrators
