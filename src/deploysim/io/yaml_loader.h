#pragma once

/// Model and deployment-profile files (YAML) -> validated structs, strictly
/// (docs/file_formats.md, DESIGN.md 5): unknown keys, missing required keys, wrong types,
/// non-finite numbers and non-physical values are errors. Every error is thrown as ONE
/// line naming the file, the key path, the value as written and the rule:
///
///     deployment_profiles/x.yaml: stages[2].until = 40: stage end times must increase (previous
///     stage ends at 60)
///
/// std::invalid_argument for bad content, std::runtime_error for files that cannot be
/// read. Degrees in files (`..._deg`) become radians here; nothing downstream sees them.

#include <optional>
#include <string>

#include "deploysim/model/model.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::io {

/// Reads a model file (`kind: tensors` or `kind: hinged`). Model::source = path,
/// Model::text = the file's text.
/// Hinged models have their hinge axes normalized (model::ValidatedHingedBody).
model::Model LoadModel(const std::string& path);

/// Reads a deployment profile and the model it names (`model:`, relative to the
/// profile's directory). Profile::source = path, Profile::text = the file's text.
/// The attitude quaternion is normalized; stages get contiguous [t_begin, t_end] and
/// their `from` configuration (the previous stage's `to`). The result has passed
/// schedule::ValidateProfile and CheckRunSettings.
schedule::Profile LoadProfile(const std::string& path);

/// Settings a user may override for one run (e.g. on the command line); unset fields
/// keep the profile's values. Names as in profile files: method "rk4", mode "geometry",
/// coupling "quasi-rigid", ...
struct ProfileOverrides {
  std::optional<std::string> method;    ///< integrator.method
  std::optional<double> rtol;           ///< integrator.rtol
  std::optional<double> atol;           ///< integrator.atol (relative to |H_B(0)|)
  std::optional<double> step;           ///< integrator.step [s]
  std::optional<double> output_dt;      ///< output.dt [s]
  std::optional<std::string> coupling;  ///< quasi-rigid | exact
  std::optional<std::string> mode;      ///< tensor | geometry
};

/// Applies the overrides and re-validates the whole profile (ValidateProfile and
/// CheckRunSettings); throws std::invalid_argument "<profile source>: <key> = <value>:
/// <rule>" for an unknown method, mode or coupling or a combination that is not valid.
/// `profile` is modified only if the result is valid.
void ApplyOverrides(schedule::Profile& profile, const ProfileOverrides& overrides);

/// The io-level rules on a profile's run settings that schedule::ValidateProfile leaves
/// to the reader: the integrator method exists (analysis::StepperNames), fixed-step
/// methods have integrator.step > 0, and the output grid has at most
/// kMaxOutputSamples samples. Throws std::invalid_argument naming the key.
void CheckRunSettings(const schedule::Profile& profile);

/// Largest number of output samples a profile may ask for ((t_end - t_begin)/dt + 1).
inline constexpr double kMaxOutputSamples = 1e7;

/// "tensor" | "geometry" -> Mode, "quasi-rigid" | "exact" -> Coupling (the names of
/// schedule::ToString). Throw std::invalid_argument "<name>: unknown mode (valid: ...)".
schedule::Mode ParseMode(const std::string& name);
schedule::Coupling ParseCoupling(const std::string& name);

}  // namespace deploysim::io
