#pragma once

/// The one thread pool of deploysim: runs body(k) for k = 0 .. count-1 on a few
/// std::threads, handing out the indices in increasing order from a shared counter.
///
/// Errors: an exception cannot cross a thread by itself. When body(k) throws, no index
/// above k is started any more, the indices already started finish, and ParallelFor
/// rethrows, after every thread has joined, the exception of the LOWEST failing index.
/// Since indices are handed out in order, every index below it has run: the error is
/// the one a serial loop would have reported.
///
/// An exception from monitor() (or from starting a thread: ThreadStartError) also stops
/// the work; it is rethrown after the join unless a body(k) failed.
///
/// Cancellation: `cancelled` (if set) is asked before each index; once it returns true
/// no further index is started and ParallelFor returns normally.

#include <cstddef>
#include <functional>
#include <stdexcept>

namespace deploysim::sweep {

struct ParallelOptions {
  /// Worker threads; 0: std::thread::hardware_concurrency(). Never more than the
  /// number of chunks.
  int threads = 0;
  /// Indices handed out at a time (larger chunks for cheap bodies).
  std::size_t chunk = 1;
  /// Asked before each index (any thread); true stops handing out indices.
  std::function<bool()> cancelled;
  /// If set, the calling thread does not run indices: it calls monitor() every
  /// monitor_interval seconds (and once more at the end) while the workers run, e.g. to
  /// show progress. Otherwise the calling thread is one of the workers.
  std::function<void()> monitor;
  double monitor_interval = 0.05;  ///< [s]
};

/// Most worker threads a caller may ask for (the sweep's --threads). Each thread
/// reserves its stack (8 MiB by default) of address space, so 256 of them take 2 GiB;
/// no node in use has more than a few hundred hardware threads, and a sweep gains
/// nothing from more threads than that. (threads = 0, the default, means all hardware
/// threads, whatever their number.)
inline constexpr int kMaxThreads = 256;

/// Thrown by ParallelFor when a worker thread cannot be started (std::thread's
/// std::system_error, e.g. under an address-space limit): "cannot start worker thread
/// 3 of 480: <reason>". The threads that did start have stopped after the index at hand.
class ThreadStartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Runs body(k) for every k in [0, count) (see the file comment for errors and
/// cancellation). `body` is called concurrently from several threads.
void ParallelFor(std::size_t count,
                 const std::function<void(std::size_t)>& body,
                 const ParallelOptions& options = {});

/// Worker threads by default: std::thread::hardware_concurrency(), at least 1.
int HardwareThreads();

}  // namespace deploysim::sweep
