#include "deploysim/sweep/interrupt.h"

#include <csignal>

namespace deploysim::sweep {

namespace {

// Set from a signal handler: must be lock-free (async-signal-safe).
std::atomic<bool> interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void OnSignal(int signal) {
  interrupted.store(true);
  std::signal(signal, SIG_DFL);  // the next one stops the process
}

}  // namespace

const std::atomic<bool>& InstallInterruptHandlers() {
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  return interrupted;
}

}  // namespace deploysim::sweep
