#pragma once

/// Sweep files (YAML, docs/sweeps.md) -> SweepSpec, read as strictly as deployment
/// profiles (docs/file_formats.md): unknown keys, missing required keys, wrong types,
/// non-finite numbers and values outside a parameter's range are errors, each thrown as
/// ONE line naming the file, the key path, the value as written and the rule:
///
///     sweeps/x.yaml: grid[1].values[2] = -3: spin_rate_rpm must be > 0
///
/// std::invalid_argument for bad content, std::runtime_error for files that cannot be
/// read. The base profile is read with io::LoadProfile (its errors name the profile).
/// Degrees and rpm in the file become radians and rad/s here.

#include <string>

#include "deploysim/sweep/sweep_spec.h"

namespace deploysim::sweep {

/// Reads and validates a sweep file: the file itself, its base profile (relative to the
/// sweep file's directory), and every case's profile (BuildCase), so that a sweep that
/// starts cannot fail on bad input half-way. SweepSpec::source = path.
SweepSpec LoadSweep(const std::string& path);

/// LoadSweep of a text that is no file (a document built in memory, e.g. from Python
/// dicts): messages name `source`; the `base:` profile file is resolved relative to
/// `base_dir` ("" = the current folder), or, if `base` is given, that profile is the base
/// and `base:` is only checked to be a string. SweepSpec::source = source.
SweepSpec LoadSweepText(const std::string& text,
                        const std::string& source,
                        const std::string& base_dir,
                        const schedule::Profile* base = nullptr);

/// LoadSweepText without ValidateCases.
SweepSpec ReadSweepText(const std::string& text,
                        const std::string& source,
                        const std::string& base_dir,
                        const schedule::Profile* base = nullptr);

/// LoadSweep without ValidateCases: the file and its base profile are read and checked,
/// the cases are not built (that takes time proportional to the number of cases, up to
/// kMaxCases). For tools that check many files quickly (the fuzz targets); a sweep that
/// is to be run is loaded with LoadSweep.
SweepSpec ReadSweep(const std::string& path);

/// Builds every case once (BuildCase) and throws the first case's error. LoadSweep calls
/// it; specs made in code can call it too.
void ValidateCases(const SweepSpec& spec);

/// Largest number of cases a sweep may have. An axis that takes the product of the axes
/// before it past this is refused before its values are made; Monte Carlo samples are at
/// most 1e6 and are never materialised. (The file itself passes io/yaml_fields.h's input
/// limits: a regular file of at most 1 MiB, 100,000 nodes.)
inline constexpr double kMaxCases = 1e8;

}  // namespace deploysim::sweep
