// AtomicFile: the target changes only on Commit(); a temporary never outlives it.

#include "deploysim/io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "temp_dir_test.h"

namespace deploysim::io {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

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
    // In the target's folder: anonymous there (O_TMPFILE), or named next to it.
    if (!f.anonymous()) {
      EXPECT_EQ(fs::path(f.temporary_path()).parent_path(), fs::path(target).parent_path());
    }
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

TEST_F(AtomicFileTest, AnAnonymousTemporaryHasNoNameUntilCommit) {
  const std::string target = Path("out.txt");
  AtomicFile f(target);
  if (!f.anonymous()) GTEST_SKIP() << "no O_TMPFILE here";
  std::ofstream(f.temporary_path()) << "new";
  EXPECT_TRUE(Entries().empty()) << "a kill -9 now leaves nothing";
  f.Commit();
  EXPECT_EQ(Contents(target), "new");
  EXPECT_EQ(Entries(), std::vector<std::string>{"out.txt"});
}

TEST_F(AtomicFileTest, NamesUpToNameMax) {
  for (std::size_t length : {253u, 254u, 255u}) {
    for (bool anonymous : {true, false}) {
      const std::string name(length, anonymous ? 'a' : 'n');
      {
        AtomicFile f(Path(name), anonymous);
        std::ofstream(f.temporary_path()) << "x";
        f.Commit();
      }
      EXPECT_EQ(Contents(Path(name)), "x") << length;
      fs::remove(Path(name));
    }
  }
  EXPECT_TRUE(Entries().empty());
  EXPECT_EQ(TemporaryStem("short"), ".short.");
  const std::string a = TemporaryStem(std::string(250, 'x') + "a");
  const std::string b = TemporaryStem(std::string(250, 'x') + "b");
  EXPECT_NE(a, b) << "long names that share a prefix get their own temporaries";
  EXPECT_LE(a.size() + 35, 255u);
  try {
    AtomicFile f(Path(std::string(256, 'l')));
    FAIL() << "a 256-byte name";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("File name too long"), std::string::npos) << e.what();
  }
}

TEST_F(AtomicFileTest, StaleTemporariesOfDeadProcessesGo) {
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ::waitpid(dead, nullptr, 0);
  const std::string d = std::to_string(dead), live = std::to_string(::getppid());
  Write(".out.txt." + d + ".0.tmp", "left by kill -9");
  Write(".out.txt." + live + ".4.tmp", "a live writer's");
  Write(".other.txt." + d + ".0.tmp", "another target's");
  Write(".out.txt.x.0.tmp", "not ours");
  {
    AtomicFile f(Path("out.txt"));
    std::ofstream(f.temporary_path()) << "new";
    f.Commit();
  }
  EXPECT_EQ(Entries(),
            (std::vector<std::string>{".other.txt." + d + ".0.tmp", ".out.txt." + live + ".4.tmp",
                                      ".out.txt.x.0.tmp", "out.txt"}));
  EXPECT_EQ(RemoveStaleTemporaries(Path("out.txt")), 0);
}

TEST_F(AtomicFileTest, SignalsRemoveNamedTemporaries) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    if (child == 0) {
      RemoveTemporariesOnSignals();
      AtomicFile f(Path("out.txt"), false);
      AtomicFile g(Path("out.csv"), false);
      std::ofstream(f.temporary_path()) << "half";
      if (::write(ready[1], "r", 1) != 1) ::_exit(2);
      for (;;) ::pause();
    }
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    EXPECT_EQ(Entries().size(), 2u);
    ::kill(child, sig);
    int status = 0;
    ::waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_TRUE(Entries().empty()) << sig;
    ::close(ready[0]);
    ::close(ready[1]);
  }
}

TEST_F(AtomicFileTest, ReserveReportsTheFileSizeLimit) {
  const pid_t child = ::fork();
  if (child == 0) {
    const rlimit r{1 << 20, RLIM_INFINITY};
    ::setrlimit(RLIMIT_FSIZE, &r);
    AtomicFile f(Path("big.bin"));
    f.Reserve(1 << 19);
    try {
      f.Reserve(2 << 20);
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      ::_exit(m.rfind(Path("big.bin") + ": cannot write: File too large", 0) == 0 ? 0 : 3);
    }
    ::_exit(4);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_TRUE(Entries().empty());
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::io
