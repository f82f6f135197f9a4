#include "deploysim/integrators/factory.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "deploysim/integrators/shape_integrate.h"

namespace deploysim::integrators {
namespace {

// The registry is the one table of methods: every entry builds a stepper of its name,
// and the methods that integrate free hinges are exactly its Lie-group (RKMK) entries.
TEST(MethodRegistryTest, EveryEntryBuildsItsStepperAndTheRkmkOnesRunFreeHinges) {
  std::vector<std::string> rkmk;
  for (const MethodEntry& m : NumericalMethods()) {
    const auto stepper = MakeNumericalStepper(m.name);
    EXPECT_EQ(stepper->info().name, m.name);
    const bool has_tableau =
        m.family == MethodEntry::Family::kExplicitRk || m.family == MethodEntry::Family::kRkmk;
    EXPECT_EQ(m.tableau != nullptr, has_tableau) << m.name;
    if (m.family == MethodEntry::Family::kRkmk) rkmk.emplace_back(m.name);
    EXPECT_EQ(IsShapeMethod(m.name), m.family == MethodEntry::Family::kRkmk) << m.name;
  }
  EXPECT_EQ(ShapeMethodNames(), rkmk);
  EXPECT_EQ(ShapeMethodNames(), (std::vector<std::string>{"rkmk4", "rkmk-dopri5", "rkmk-rkf78"}));
  EXPECT_EQ(NumericalStepperNames().size(), NumericalMethods().size());
  EXPECT_THROW(MakeNumericalStepper("exact"), std::invalid_argument);  // analysis adds it
}

}  // namespace
}  // namespace deploysim::integrators
