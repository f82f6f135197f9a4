#pragma once

/// Warnings about a valid profile: inputs that are legal but almost certainly not what
/// the user meant (a release after the run's end, a spring that cannot carry its panel to
/// the latch, a spin rate typed in deg/s where the key takes rad/s, ...). A warning never
/// changes a run; the CLI prints each on stderr, and the trajectory file and the mission
/// report carry them (docs/file_formats.md, "Warnings").

#include <string>
#include <vector>

#include "deploysim/schedule/profile.h"

namespace deploysim::schedule {

/// Spin faster than this [rad/s] (60 rpm) is taken for a rate typed in the wrong unit:
/// spin-stabilised spacecraft spin at a few to some tens of rpm.
inline constexpr double kMaxPlausibleSpin = 2.0 * 3.14159265358979323846;
/// A run sampled fewer times than this is too coarse to show a deployment.
inline constexpr double kMinOutputSamples = 100.0;

/// One line per warning, in the form of the profile's errors: "<file>: <key path> =
/// <value>: <what it does> (<what was probably meant>)". `p` must be valid
/// (ValidateProfile). Empty when nothing looks wrong.
std::vector<std::string> ProfileWarnings(const Profile& p);

/// ProfileWarnings(p) as a JSON array of strings (the trajectory file's `warnings`
/// attribute and `analyze --json`).
std::string ProfileWarningsJson(const Profile& p);

}  // namespace deploysim::schedule
