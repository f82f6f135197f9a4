// libFuzzer target: model files (io::LoadModel), as `deploysim` reads a profile's model.
#include <cstddef>
#include <cstdint>
#include <string>

#include "deploysim/io/yaml_reader.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  deploysim::fuzz::Initialize();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  deploysim::fuzz::Run(data, size, [](const std::string& path) {
    const deploysim::model::Model model = deploysim::io::LoadModel(path);
    (void)model;
  });
  return 0;
}
