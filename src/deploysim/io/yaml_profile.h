#pragma once

/// Deployment-profile files (YAML) -> schedule::Profile, by the strict rules of
/// yaml_reader.h; the mode and coupling names.

#include <optional>
#include <string>

#include "deploysim/model/model.h"
#include "deploysim/schedule/profile.h"

namespace deploysim::io {
/// Reads a deployment profile and the model it names (`model:`, relative to the
/// profile's directory). Profile::source = path, Profile::text = the file's text.
/// The attitude quaternion is normalized; stages get contiguous [t_begin, t_end] and
/// their `from` configuration (the previous stage's `to`). A hinge profile (`hinges:`
/// instead of `stages:`, docs/file_formats.md "Hinge profiles") gets one HingePlan per
/// panel in the model's panel order (panels it leaves out are locked), panel names
/// resolved to indices, angles and rates in rad and rad/s, mode geometry and coupling
/// exact, and Profile::start / until / initial.configuration. The result has passed
/// schedule::ValidateProfile; the integrator settings are read but not checked against
/// the integrators (use io::LoadProfile for a profile that is to be run).
schedule::Profile ReadProfile(const std::string& path);

/// ReadProfile without the cross-field rules: the keys, types and per-key ranges are
/// checked, schedule::ValidateProfile is not run and `initial.spin` is not resolved. For a
/// profile that is compiled next (run::CompiledRun::Compile validates it once).
schedule::Profile ParseProfile(const std::string& path);

/// ReadProfile of a text that is no file: messages name `source`; the `model:` file is
/// resolved relative to `base_dir` ("" = the current folder). If `model` is given, it is
/// the profile's model and `model:` is only checked to be a string (its name). The same
/// rules and messages as ReadProfile otherwise. Profile::source = source.
schedule::Profile ReadProfileText(const std::string& text,
                                  const std::string& source,
                                  const std::string& base_dir,
                                  const model::Model* model = nullptr);

/// ParseProfile of a text that is no file (the arguments of ReadProfileText).
schedule::Profile ParseProfileText(const std::string& text,
                                   const std::string& source,
                                   const std::string& base_dir,
                                   const model::Model* model = nullptr);

/// "tensor" | "geometry" -> Mode, "quasi-rigid" | "exact" -> Coupling (the names of
/// schedule::ToString). Throw std::invalid_argument "<name>: unknown mode (valid: ...)".
schedule::Mode ParseMode(const std::string& name);
schedule::Coupling ParseCoupling(const std::string& name);

/// The same look-ups without throwing (nullopt for an unknown name), and the valid names
/// as "a, b" for messages.
std::optional<schedule::Mode> FindMode(const std::string& name);
std::optional<schedule::Coupling> FindCoupling(const std::string& name);
std::string ModeNames();
std::string CouplingNames();

}  // namespace deploysim::io
