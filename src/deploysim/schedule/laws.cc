#include "deploysim/schedule/laws.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

namespace deploysim::schedule {

namespace {

constexpr std::array<std::pair<Law, const char*>, 4> kLawNames{{
    {Law::kStep, "step"},
    {Law::kLinear, "linear"},
    {Law::kSmoothstep, "smoothstep"},
    {Law::kMinimumJerk, "minimum-jerk"},
}};

}  // namespace

LawValue EvaluateLaw(Law law, double tau) {
  const double x = std::clamp(tau, 0.0, 1.0);
  const double u = 1.0 - x;
  LawValue v;
  switch (law) {
    case Law::kStep:
      // The switch happens at tau = 0; the rate is an impulse, represented as zero
      // (the schedule treats the stage start as a breakpoint).
      v.s = x > 0.0 ? 1.0 : 0.0;
      break;
    case Law::kLinear:
      v.s = x;
      v.ds = 1.0;
      break;
    case Law::kSmoothstep:
      // s = 3x^2 - 2x^3, s' = 6x(1-x), s'' = 6 - 12x.
      v.s = x * x * (3.0 - 2.0 * x);
      v.ds = 6.0 * x * u;
      v.dds = 6.0 - 12.0 * x;
      break;
    case Law::kMinimumJerk:
      // s = 10x^3 - 15x^4 + 6x^5, s' = 30x^2(1-x)^2, s'' = 60x(1-x)(1-2x).
      v.s = x * x * x * (10.0 + x * (-15.0 + 6.0 * x));
      v.ds = 30.0 * x * x * u * u;
      v.dds = 60.0 * x * u * (1.0 - 2.0 * x);
      break;
  }
  return v;
}

std::string ToString(Law law) {
  for (const auto& [l, name] : kLawNames) {
    if (l == law) return name;
  }
  return "unknown";
}

Law ParseLaw(const std::string& name) {
  std::string valid;
  for (const auto& [l, n] : kLawNames) {
    if (name == n) return l;
    valid += (valid.empty() ? "" : ", ") + std::string(n);
  }
  throw std::invalid_argument("unknown law '" + name + "' (valid: " + valid + ")");
}

}  // namespace deploysim::schedule
