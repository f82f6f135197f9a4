// libFuzzer target: sweep files as `deploysim sweep` loads them: sweep::ReadSweep (the
// sweep file, its base profile through io::LoadProfile), then, for sweeps of at most
// kMaxValidatedCases cases, every case built and checked once (sweep::ValidateCases, the
// rest of LoadSweep). Validation takes time proportional to the number of cases (about
// 18 us per case natively, 100x that under ASan): a larger sweep is a correct but slow
// input, not a finding, so its cases are left out to keep each input under 1 s.
#include <cstddef>
#include <cstdint>
#include <string>

#include "deploysim/sweep/sweep_file.h"
#include "fuzz_support.h"

namespace {
constexpr std::size_t kMaxValidatedCases = 64;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  deploysim::fuzz::Initialize();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  deploysim::fuzz::Run(data, size, [](const std::string& path) {
    const deploysim::sweep::SweepSpec spec = deploysim::sweep::ReadSweep(path);
    if (spec.case_count() <= kMaxValidatedCases) deploysim::sweep::ValidateCases(spec);
  });
  return 0;
}
