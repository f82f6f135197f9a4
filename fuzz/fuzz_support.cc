#include "fuzz_support.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <typeinfo>
#include <vector>

namespace deploysim::fuzz {
namespace {

namespace fs = std::filesystem;

fs::path work_dir;
fs::path input_path;

[[noreturn]] void Fail(const std::string& what) {
  std::fprintf(stderr, "deploysim fuzz: %s\n", what.c_str());
  std::abort();
}

void RemoveWorkDir() {
  std::error_code ec;
  if (!work_dir.empty()) fs::remove_all(work_dir, ec);
}

void CopyYamlFiles(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  for (const fs::directory_entry& e : fs::directory_iterator(from)) {
    if (e.is_regular_file() && e.path().extension() == ".yaml") {
      fs::copy_file(e.path(), to / e.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
}

// The exception's text for a report: first 300 bytes, newlines shown as \n.
std::string Excerpt(const std::string& message) {
  std::string out;
  for (char c : message.substr(0, 300)) {
    out += c == '\n' ? std::string("<LF>") : c == '\r' ? std::string("<CR>") : std::string(1, c);
  }
  if (message.size() > 300) out += "... (" + std::to_string(message.size()) + " bytes)";
  return out;
}

void CheckMessage(const std::exception& e) {
  const std::string message = e.what();
  if (message.empty()) Fail(std::string("empty message from ") + typeid(e).name());
  if (message.find_first_of("\n\r") != std::string::npos) {
    Fail("error message of several lines: " + Excerpt(message));
  }
  if (message.size() > kMaxMessageBytes) {
    Fail("error message of " + std::to_string(message.size()) + " bytes (at most " +
         std::to_string(kMaxMessageBytes) + "): " + Excerpt(message));
  }
}

}  // namespace

void Initialize() {
  if (!work_dir.empty()) return;
  const char* env_source = std::getenv("DEPLOYSIM_SOURCE_DIR");
  const fs::path source = env_source != nullptr ? env_source : DEPLOYSIM_FUZZ_SOURCE_DIR;
  const char* env_tmp = std::getenv("TMPDIR");
  const fs::path tmp = env_tmp != nullptr && *env_tmp != '\0' ? env_tmp : "/dev/shm";
  std::string pattern = (tmp / "deploysim_fuzz.XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (mkdtemp(buffer.data()) == nullptr) Fail("cannot create a work folder in " + tmp.string());
  work_dir = buffer.data();
  std::atexit(RemoveWorkDir);
  try {
    CopyYamlFiles(source / "models", work_dir / "models");
    CopyYamlFiles(source / "deployment_profiles", work_dir / "deployment_profiles");
    CopyYamlFiles(source / "sweeps", work_dir / "sweeps");
    fs::create_directories(work_dir / "in");
    for (const char* name : {"ok_model.yaml", "ok_hinged.yaml"}) {
      fs::copy_file(source / "tests/io/bad_inputs" / name, work_dir / "in" / name);
    }
  } catch (const std::exception& e) {
    Fail(std::string("cannot copy the shipped files from ") + source.string() + ": " + e.what());
  }
  input_path = work_dir / "in" / "input.yaml";
}

void Run(const std::uint8_t* data,
         std::size_t size,
         const std::function<void(const std::string& path)>& load) {
  Initialize();
  {
    std::ofstream out(input_path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out.flush()) Fail("cannot write " + input_path.string());
  }
  try {
    load(input_path.string());
  } catch (const std::invalid_argument& e) {
    if (typeid(e) != typeid(std::invalid_argument)) {
      Fail(std::string("exception of type ") + typeid(e).name() +
           " (not std::invalid_argument): " + Excerpt(e.what()));
    }
    CheckMessage(e);
  } catch (const std::runtime_error& e) {
    if (typeid(e) != typeid(std::runtime_error)) {
      Fail(std::string("exception of type ") + typeid(e).name() +
           " (not std::runtime_error): " + Excerpt(e.what()));
    }
    CheckMessage(e);
  } catch (const std::exception& e) {
    Fail(std::string("exception of type ") + typeid(e).name() + ": " + Excerpt(e.what()));
  } catch (...) {
    Fail("exception not derived from std::exception");
  }
}

}  // namespace deploysim::fuzz
