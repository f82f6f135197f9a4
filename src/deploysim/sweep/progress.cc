#include "deploysim/sweep/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace deploysim::sweep {

namespace {
constexpr int kBarWidth = 30;
constexpr double kTtyRefresh = 0.2;  // [s] between redraws of the bar
}  // namespace

ProgressReporter::ProgressReporter(std::ostream& out,
                                   bool tty,
                                   std::size_t total,
                                   std::size_t already_done,
                                   double interval,
                                   std::string label)
    : out_(out),
      tty_(tty),
      total_(total),
      already_done_(already_done),
      interval_(interval),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      last_print_(tty ? -1e300 : 0.0) {}  // plain lines: the first after one interval

std::string ProgressReporter::FormatDuration(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  const long s = std::lround(std::max(seconds, 0.0));
  char buf[48];
  if (s < 60) {
    std::snprintf(buf, sizeof(buf), "%ld s", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof(buf), "%ld:%02ld", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof(buf), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  }
  return buf;
}

std::string ProgressReporter::Line(std::size_t done, double elapsed) const {
  const std::size_t computed = done - std::min(done, already_done_);
  const double rate = elapsed > 0.0 ? static_cast<double>(computed) / elapsed : 0.0;
  const double left = rate > 0.0 ? static_cast<double>(total_ - done) / rate : NAN;
  const double fraction =
      total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  char buf[256];
  if (tty_) {
    const int filled = static_cast<int>(fraction * kBarWidth);
    std::snprintf(buf, sizeof(buf), "%s [%s%s] %3d%% %zu/%zu  %.0f cases/s  ETA %s", label_.c_str(),
                  std::string(static_cast<std::size_t>(filled), '#').c_str(),
                  std::string(static_cast<std::size_t>(kBarWidth - filled), '.').c_str(),
                  static_cast<int>(fraction * 100), done, total_, rate,
                  FormatDuration(left).c_str());
  } else {
    std::snprintf(buf, sizeof(buf), "%s: %zu/%zu cases (%.0f%%), %.0f cases/s, %s elapsed, ETA %s",
                  label_.c_str(), done, total_, fraction * 100, rate,
                  FormatDuration(elapsed).c_str(), FormatDuration(left).c_str());
  }
  return buf;
}

void ProgressReporter::Update(std::size_t done) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed - last_print_ < (tty_ ? kTtyRefresh : interval_)) return;
  last_print_ = elapsed;
  const std::string line = Line(done, elapsed);
  if (tty_) {
    out_ << '\r' << line
         << std::string(bar_width_ > line.size() ? bar_width_ - line.size() : 0, ' ');
    bar_width_ = line.size();
  } else {
    out_ << line << '\n';
  }
  out_.flush();
}

void ProgressReporter::Finish(std::size_t done, bool complete) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::size_t computed = done - std::min(done, already_done_);
  const double rate = elapsed > 0.0 ? static_cast<double>(computed) / elapsed : 0.0;
  if (tty_ && bar_width_ > 0) out_ << '\r' << std::string(bar_width_, ' ') << '\r';
  char buf[256];
  std::snprintf(
      buf, sizeof(buf), "%s: %zu/%zu cases %s (%zu computed in %s, %.0f cases/s%s)", label_.c_str(),
      done, total_, complete ? "done" : "finished, interrupted", computed,
      FormatDuration(elapsed).c_str(), rate,
      already_done_ > 0 ? (", " + std::to_string(already_done_) + " resumed").c_str() : "");
  out_ << buf << '\n';
  out_.flush();
}

}  // namespace deploysim::sweep
