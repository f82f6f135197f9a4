#include "deploysim/sweep/parallel.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace deploysim::sweep {

int HardwareThreads() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void ParallelFor(std::size_t count,
                 const std::function<void(std::size_t)>& body,
                 const ParallelOptions& options) {
  if (count == 0) {
    if (options.monitor) options.monitor();
    return;
  }
  const std::size_t chunk = std::max<std::size_t>(options.chunk, 1);
  const std::size_t chunks = (count + chunk - 1) / chunk;
  const std::size_t threads = std::min<std::size_t>(
      static_cast<std::size_t>(options.threads > 0 ? options.threads : HardwareThreads()), chunks);

  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> first_bad{count};  // lowest failing index so far
  std::atomic<bool> cancelled{false};
  std::exception_ptr error;  // of first_bad; guarded by `mutex`
  std::mutex mutex;
  std::condition_variable finished;
  std::size_t running = 0;  // guarded by `mutex`

  auto work = [&] {
    for (;;) {
      const std::size_t begin = next.fetch_add(chunk);
      if (begin >= count) return;
      for (std::size_t k = begin; k < std::min(count, begin + chunk); ++k) {
        if (k >= first_bad.load() || cancelled.load()) return;
        if (options.cancelled && options.cancelled()) {
          cancelled.store(true);
          return;
        }
        try {
          body(k);
        } catch (...) {
          const std::lock_guard<std::mutex> lock(mutex);
          if (k < first_bad.load()) {
            first_bad.store(k);
            error = std::current_exception();
          }
          return;
        }
      }
    }
  };

  const bool monitored = static_cast<bool>(options.monitor);
  const std::size_t spawned = monitored ? threads : threads - 1;
  std::vector<std::thread> pool;
  pool.reserve(spawned);
  std::exception_ptr own_error;  // from the calling thread: monitor() or starting a thread
  try {
    for (std::size_t t = 0; t < spawned; ++t) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        ++running;
      }
      try {
        pool.emplace_back([&] {
          work();
          {
            const std::lock_guard<std::mutex> lock(mutex);
            --running;
          }
          finished.notify_all();
        });
      } catch (const std::system_error& e) {
        {
          const std::lock_guard<std::mutex> lock(mutex);
          --running;
        }
        throw ThreadStartError("cannot start worker thread " + std::to_string(t + 1) + " of " +
                               std::to_string(spawned) + ": " + e.what());
      }
    }
    if (monitored) {
      const auto interval = std::chrono::duration<double>(std::max(options.monitor_interval, 1e-3));
      for (;;) {
        {
          std::unique_lock<std::mutex> lock(mutex);
          if (finished.wait_for(lock, interval, [&] { return running == 0; })) break;
        }
        options.monitor();
      }
    } else {
      work();
    }
  } catch (...) {
    own_error = std::current_exception();
    cancelled.store(true);  // the workers stop after the index at hand
  }
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (own_error) std::rethrow_exception(own_error);
  if (monitored) options.monitor();
}

}  // namespace deploysim::sweep
