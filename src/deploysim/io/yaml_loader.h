#pragma once

/// Profiles that are to be run: io_yaml's ReadProfile (yaml_reader.h) plus the rules
/// on the run settings that need the integrator registry, and command-line overrides.
/// Errors are thrown as ONE line naming the file, the key, the value and the rule
/// (std::invalid_argument for bad content, std::runtime_error for unreadable files).
/// Library deploysim::io.

#include <memory>
#include <optional>
#include <string>

#include "deploysim/run/compiled_run.h"
#include "deploysim/io/yaml_reader.h"

namespace deploysim::io {

/// ReadProfile (yaml_reader.h), then the run-setting rules (run::CheckRunSettings):
/// a profile that can be run. A run compiles it (LoadRun validates once instead).
schedule::Profile LoadProfile(const std::string& path);

/// LoadProfile of a text that is no file (ReadProfileText, then the run-setting rules).
schedule::Profile LoadProfileText(const std::string& text,
                                  const std::string& source,
                                  const std::string& base_dir,
                                  const model::Model* model = nullptr);

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
  /// The run's end [s]: a hinge profile's `until`; a stage profile is cut inside a hold
  /// stage or at a stage end, or held in its last configuration up to it.
  std::optional<double> until;
};

/// Applies the overrides and re-validates the whole profile (ValidateProfile and
/// run::CheckRunSettings); throws std::invalid_argument "<profile source>: <key> =
/// <value>: <rule>" for an unknown method, mode or coupling or a combination that is not
/// valid. `profile` is modified only if the result is valid.
void ApplyOverrides(schedule::Profile& profile, const ProfileOverrides& overrides);

/// The run of a profile file with the overrides, compiled (what `deploysim simulate` and
/// `analyze` run): parsed (ParseProfile), overridden, then validated once and compiled
/// (run::CompiledRun::Compile). Throws as LoadProfile and ApplyOverrides.
std::shared_ptr<const run::CompiledRun> LoadRun(const std::string& path,
                                                     const ProfileOverrides& overrides = {});

}  // namespace deploysim::io
