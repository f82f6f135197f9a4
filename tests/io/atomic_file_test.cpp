// AtomicFile: the target changes only on Commit(); a temporary never outlives it.

#include "deploysim/io/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "temp_dir_test.h"

namespace deploysim::io {
namespace {

namespace fs = std::filesystem;

std::string Contents(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class AtomicFileTest : public testing::TempDirTest {};

TEST_F(AtomicFileTest, CommitReplacesTheTarget) {
  const std::string target = Write("out.txt", "old");
  {
    AtomicFile f(target);
    EXPECT_EQ(fs::path(f.temporary_path()).parent_path(), fs::path(target).parent_path());
    std::ofstream(f.temporary_path()) << "new";
    EXPECT_EQ(Contents(target), "old") << "untouched before Commit";
    f.Commit();
  }
  EXPECT_EQ(Contents(target), "new");
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, WithoutCommitNothingChanges) {
  const std::string target = Write("out.txt", "old");
  {
    AtomicFile f(target);
    std::ofstream(f.temporary_path()) << "half written";
  }
  EXPECT_EQ(Contents(target), "old");
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, TemporariesAreDistinct) {
  AtomicFile a(Path("out.txt"));
  AtomicFile b(Path("out.txt"));
  EXPECT_NE(a.temporary_path(), b.temporary_path());
}

TEST_F(AtomicFileTest, MissingDirectoryThrows) {
  const std::string target = Path("missing/out.txt");
  try {
    AtomicFile f(target);
    FAIL() << "created a file in a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(target + ": cannot create a temporary file", 0), 0u)
        << e.what();
  }
  EXPECT_TRUE(Entries().empty());
}

TEST_F(AtomicFileTest, FailedRenameKeepsNoTemporary) {
  fs::create_directory(Path("dir"));
  Write("dir/inside", "x");  // a non-empty directory cannot be replaced by a file
  {
    AtomicFile f(Path("dir"));
    EXPECT_THROW(f.Commit(), std::runtime_error);
  }
  EXPECT_EQ(Entries(), std::vector<std::string>{"dir"});
}

}  // namespace
}  // namespace deploysim::io
