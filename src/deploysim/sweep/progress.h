#pragma once

/// Sweep progress on a stream (stderr): on a terminal a bar redrawn in place with the
/// rate and the time left; otherwise plain lines at a fixed interval (logs, CI).
/// Not thread-safe: one thread (the sweep's main thread) calls it.

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace deploysim::sweep {

class ProgressReporter {
 public:
  /// `total` cases of which `already_done` were finished before this run (resumed);
  /// the rate counts only cases computed by this run. `interval` [s]: plain lines.
  ProgressReporter(std::ostream& out,
                   bool tty,
                   std::size_t total,
                   std::size_t already_done,
                   double interval,
                   std::string label = "sweep");

  /// `done` cases are finished (including already_done). Prints when due.
  void Update(std::size_t done);
  /// Final line (clears the bar on a terminal).
  void Finish(std::size_t done, bool complete);

  /// "1:02:03", "2:03", "7 s" style durations.
  static std::string FormatDuration(double seconds);

 private:
  std::string Line(std::size_t done, double elapsed) const;

  std::ostream& out_;
  bool tty_;
  std::size_t total_;
  std::size_t already_done_;
  double interval_;
  std::string label_;
  std::chrono::steady_clock::time_point start_;
  double last_print_;
  std::size_t bar_width_ = 0;
};

}  // namespace deploysim::sweep
