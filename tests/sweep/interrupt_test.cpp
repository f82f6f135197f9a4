// sweep::InstallInterruptHandlers: the first SIGINT or SIGTERM only sets the flag that a
// sweep polls (it then stops after the cases at hand, its journal complete); the second
// stops the process at once, as the signal's default does.

#include "deploysim/sweep/interrupt.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <csignal>
#include <cstdlib>

namespace deploysim::sweep {
namespace {
namespace DEPLOYSIM_TEST_UNIT {

/// In a child process: installs the handlers, raises `sig` twice and reports by its exit
/// status how far it got (3: flag set before any signal, 4: flag not set by the first,
/// 0: survived the second).
[[noreturn]] void RaiseTwice(int sig) {
  const std::atomic<bool>& flag = InstallInterruptHandlers();
  if (flag.load()) std::_Exit(3);
  std::raise(sig);
  if (!flag.load()) std::_Exit(4);
  std::raise(sig);  // the default action again: the process ends here
  std::_Exit(0);
}

TEST(InterruptHandlersDeathTest, SigintSetsTheFlagThenTheSecondStopsTheProcess) {
  ::testing::GTEST_FLAG(death_test_style) = "threadsafe";
  EXPECT_EXIT(RaiseTwice(SIGINT), ::testing::KilledBySignal(SIGINT), "");
}

TEST(InterruptHandlersDeathTest, SigtermSetsTheFlagThenTheSecondStopsTheProcess) {
  ::testing::GTEST_FLAG(death_test_style) = "threadsafe";
  EXPECT_EXIT(RaiseTwice(SIGTERM), ::testing::KilledBySignal(SIGTERM), "");
}

TEST(InterruptHandlers, InstallingAgainKeepsTheOneFlag) {
  const std::atomic<bool>& a = InstallInterruptHandlers();
  const std::atomic<bool>& b = InstallInterruptHandlers();
  EXPECT_EQ(&a, &b);
  EXPECT_FALSE(a.load());
  // The handler is ours (not the default, not ignored) until the first signal.
  struct sigaction now {};
  ASSERT_EQ(::sigaction(SIGINT, nullptr, &now), 0);
  EXPECT_NE(now.sa_handler, SIG_DFL);
  EXPECT_NE(now.sa_handler, SIG_IGN);
}

}  // namespace DEPLOYSIM_TEST_UNIT
}  // namespace
}  // namespace deploysim::sweep
