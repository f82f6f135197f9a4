#pragma once

/// Model and deployment-profile files (YAML) -> validated structs, strictly
/// (docs/file_formats.md, docs/design.md 5): unknown keys, missing required keys, wrong types,
/// non-finite numbers and non-physical values are errors. Every error is thrown as ONE
/// line naming the file, the key path, the value as written and the rule:
///
///     deployment_profiles/x.yaml: stages[2].until = 40: stage end times must increase (previous
///     stage ends at 60)
///
/// std::invalid_argument for bad content, std::runtime_error for files that cannot be
/// read. Degrees in files (`..._deg`) become radians here; nothing downstream sees them.
/// Every file passes the input limits of yaml_fields.h (regular files of at most 1 MiB,
/// UTF-8 text, at most 100,000 nodes nested at most 32 deep with aliases expanded, names
/// of at most 200 bytes); long values are cut in messages.
///
/// Library deploysim::io_yaml: it depends on model and schedule only (not on the
/// integrators, analysis or HDF5), so a program that only reads models and profiles links
/// none of those. A profile read here has not been checked against the integrator
/// registry; io::LoadProfile (yaml_loader.h, deploysim::io) adds those run-setting rules.
/// The readers: yaml_model.h (models), yaml_profile.h (profiles).

#include "deploysim/io/yaml_model.h"
#include "deploysim/io/yaml_profile.h"
