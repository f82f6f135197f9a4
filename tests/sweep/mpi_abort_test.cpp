// An error on one MPI rank ends the whole job (MPI_Abort in the CLI) instead of leaving
// the other ranks waiting forever in the next collective.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "deploysim/sweep/mpi_session.h"
#include "deploysim/sweep/runner.h"
#include "sweep_test_support.h"

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

namespace fs = std::filesystem;
using testing::SmallsatProfile;
using testing::SweepDirTest;

TEST_F(SweepDirTest, MpiErrorOnOneRankAbortsTheJob) {
  if (!MpiBuilt()) GTEST_SKIP() << "built without MPI (cmake -DDEPLOYSIM_WITH_MPI=ON)";
  const std::string sweep = Write("s.yaml", "name: abort test\nbase: " + SmallsatProfile() + R"(
integrator: {method: exact, rtol: 1.0e-9, atol: 1.0e-11}
grid:
  - {parameter: spin_rate_rpm, linspace: [2, 9, 8]}
)");
  const std::string out = Path("abort.h5");
  // Rank 0 alone fails: after the cases are gathered it cannot write the results (a
  // directory is in the way), while rank 1 waits for it in the final barrier. Without
  // MPI_Abort the job hangs until the timeout (exit status 124).
  fs::create_directory(out);
  const std::string log = Path("abort.log");
  const std::string cmd = "timeout 120 '" + MpiExecutable() +
                          "' --allow-run-as-root --oversubscribe -np 2 --mca btl self,tcp "
                          "--mca btl_tcp_if_include lo --mca oob_tcp_if_include lo '" +
                          std::string(DEPLOYSIM_CLI) + "' sweep '" + sweep + "' -o '" + out +
                          "' --threads 1 -q > '" + log + "' 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_NE(WEXITSTATUS(status), 124) << "the job hung (killed by the timeout):\n" << text;
  EXPECT_NE(WEXITSTATUS(status), 0) << text;
  EXPECT_NE(text.find("deploysim: error: " + out), std::string::npos) << text;
  EXPECT_TRUE(fs::is_directory(out));
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
