#pragma once

/// Shared part of the libFuzzer targets (fuzz/README.md): each target writes the fuzz
/// input to a file in a per-process work folder and calls the real loader on that path,
/// so the file-reading path is exercised as the CLI uses it.
///
/// The work folder ($TMPDIR, else /dev/shm, + deploysim_fuzz.XXXXXX) is laid out so that
/// the shipped files are reachable by the relative paths they use:
///
///     <work>/models/*.yaml                the shipped models (copies)
///     <work>/deployment_profiles/*.yaml   the shipped profiles (copies)
///     <work>/sweeps/*.yaml                the shipped sweeps (copies)
///     <work>/in/ok_model.yaml, ok_hinged.yaml   models of tests/io/bad_inputs/
///     <work>/in/input.yaml                the fuzz input
///
/// so `model: ../models/wing_nut.yaml`, `model: ok_model.yaml` and
/// `base: ../deployment_profiles/smallsat_three_stage.yaml` all resolve.
/// The shipped files are read from DEPLOYSIM_SOURCE_DIR (environment), else from the
/// source tree the target was built from.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace deploysim::fuzz {

/// Creates the work folder and copies the shipped files in (once per process; the
/// folder is removed at normal exit). Aborts if that fails: a fuzzer without its files
/// would fuzz nothing useful.
void Initialize();

/// Writes `data` to <work>/in/input.yaml and calls `load` on that path. The documented
/// outcomes of bad input — exactly std::invalid_argument or std::runtime_error (not a
/// subclass such as YAML::Exception), with a message of one line of at most
/// kMaxMessageBytes bytes — return normally; anything else (another exception type, a
/// message of several lines or an over-long one) is reported and aborts, which libFuzzer
/// records as a crash with the input that caused it.
void Run(const std::uint8_t* data,
         std::size_t size,
         const std::function<void(const std::string& path)>& load);

/// Longest error message accepted: messages name the file, key, value and rule and must
/// never echo a long value whole (the rule of docs/file_formats.md).
inline constexpr std::size_t kMaxMessageBytes = 1024;

}  // namespace deploysim::fuzz
