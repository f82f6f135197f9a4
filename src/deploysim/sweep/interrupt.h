#pragma once

/// Graceful interruption of a sweep from the command line: the first SIGINT (Ctrl-C) or
/// SIGTERM sets a flag that RunSweep polls (the workers finish the case at hand, the
/// journal is flushed, and `--resume` continues later); the handler then reverts to the
/// default, so a second Ctrl-C stops the process at once (the journal still loses no
/// finished case).

#include <atomic>

namespace deploysim::sweep {

/// Installs the handlers (idempotent) and returns the flag they set.
const std::atomic<bool>& InstallInterruptHandlers();

}  // namespace deploysim::sweep
