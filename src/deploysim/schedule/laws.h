#pragma once

/// Interpolation laws of a deployment stage (docs/design.md 2.6). A law maps the stage's
/// normalized time tau in [0, 1] to a fraction s(tau) in [0, 1] with s(0) = 0, s(1) = 1.

#include <string>

namespace deploysim::schedule {

enum class Law {
  kStep,         ///< s = 1 for tau > 0: the configuration switches at the stage start.
  kLinear,       ///< s = tau: rate jumps at both ends (breakpoints).
  kSmoothstep,   ///< s = 3 tau^2 - 2 tau^3: C1.
  kMinimumJerk,  ///< s = 10 tau^3 - 15 tau^4 + 6 tau^5: C2 (Flash & Hogan 1985).
};

/// s, ds/dtau, d2s/dtau2 at tau (clamped to [0, 1]).
struct LawValue {
  double s = 0.0;
  double ds = 0.0;
  double dds = 0.0;
};

LawValue EvaluateLaw(Law law, double tau);

/// "step", "linear", "smoothstep", "minimum-jerk".
std::string ToString(Law law);
/// Parses the names of ToString; throws std::invalid_argument listing them.
Law ParseLaw(const std::string& name);

}  // namespace deploysim::schedule
