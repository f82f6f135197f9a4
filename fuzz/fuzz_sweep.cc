// libFuzzer target: sweep files as `deploysim sweep` loads them (sweep::LoadSweep: the
// sweep file, its base profile through io::LoadProfile, and every case built once).
#include <cstddef>
#include <cstdint>
#include <string>

#include "deploysim/sweep/sweep_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  deploysim::fuzz::Initialize();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  deploysim::fuzz::Run(data, size, [](const std::string& path) {
    const deploysim::sweep::SweepSpec spec = deploysim::sweep::LoadSweep(path);
    (void)spec;
  });
  return 0;
}
