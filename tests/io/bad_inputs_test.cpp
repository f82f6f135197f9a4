// The corpus of malformed and non-physical inputs in tests/io/bad_inputs/: every file
// must be rejected with ONE line that starts with the file's name and contains the text
// of its first line, `# expect: <text>`. Files whose first line is `# valid` are
// helpers (models the bad profiles refer to) and must load.
//
// A file is loaded as a profile if it has a top-level `stages:` or `model:` key, else as
// a model.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "deploysim/io/yaml_loader.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;

constexpr std::size_t kMinimumCorpusSize = 30;

fs::path CorpusDir() { return fs::path(DEPLOYSIM_SOURCE_DIR) / "tests/io/bad_inputs"; }

std::vector<std::string> CorpusFiles() {
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(CorpusDir())) {
    if (e.path().extension() == ".yaml") names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string ReadAll(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

// A profile names a model or has stages; a sweep file (base:) is read as one too, to be
// refused with a pointer to `deploysim sweep`.
bool IsProfile(const std::string& text) {
  static const std::regex kProfileKey("(^|\n)(stages|model|base)[ \t]*:");
  return std::regex_search(text, kProfileKey);
}

/// Loads the file the way the corpus rules say; returns the error message, or "" if it
/// loaded.
std::string LoadError(const std::string& path, bool profile) {
  try {
    if (profile) {
      (void)LoadProfile(path);
    } else {
      (void)LoadModel(path);
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string TestName(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = fs::path(info.param).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

class BadInputsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BadInputsTest, RejectedWithOneLineNamingTheFile) {
  const std::string path = (CorpusDir() / GetParam()).string();
  const std::string text = ReadAll(path);
  const std::string first = FirstLine(text);
  if (first.rfind("# valid", 0) == 0) {
    EXPECT_EQ(LoadError(path, IsProfile(text)), "") << "helper file " << path << " must load";
    return;
  }
  const std::string kExpect = "# expect: ";
  ASSERT_EQ(first.rfind(kExpect, 0), 0u)
      << path << ": the first line must be '# expect: <text>' or '# valid'";
  const std::string expected = first.substr(kExpect.size());
  ASSERT_FALSE(expected.empty()) << path;

  const std::string message = LoadError(path, IsProfile(text));
  ASSERT_NE(message, "") << path << " was accepted";
  EXPECT_NE(message.find(expected), std::string::npos)
      << "expected: " << expected << "\nmessage:  " << message;
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u)
      << "message does not start with the file: " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
  EXPECT_EQ(message.find('\r'), std::string::npos) << "message holds a CR: " << message;
  // Values are cut in messages: no message echoes a long value whole.
  EXPECT_LE(message.size(), path.size() + 400) << message.substr(0, 1000);
}

INSTANTIATE_TEST_SUITE_P(Corpus, BadInputsTest, ::testing::ValuesIn(CorpusFiles()), TestName);

TEST(BadInputsCorpusTest, HasEnoughCases) {
  std::size_t bad = 0;
  for (const std::string& name : CorpusFiles()) {
    if (FirstLine(ReadAll(CorpusDir() / name)).rfind("# expect: ", 0) == 0) ++bad;
  }
  EXPECT_GE(bad, kMinimumCorpusSize);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
