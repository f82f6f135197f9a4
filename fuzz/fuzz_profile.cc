// libFuzzer target: deployment profiles as `deploysim simulate` loads them
// (io::LoadProfile: the profile, its model, schedule::ValidateProfile and the run-setting
// checks; then io::ApplyOverrides with no overrides, which re-validates as the CLI does).
#include <cstddef>
#include <cstdint>
#include <string>

#include "deploysim/io/yaml_loader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  deploysim::fuzz::Initialize();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  deploysim::fuzz::Run(data, size, [](const std::string& path) {
    deploysim::schedule::Profile profile = deploysim::io::LoadProfile(path);
    deploysim::io::ApplyOverrides(profile, deploysim::io::ProfileOverrides{});
  });
  return 0;
}
