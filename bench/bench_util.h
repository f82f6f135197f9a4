#pragma once

// Helpers shared by the benchmark programs: the machine line printed under every table,
// the one timing rule of every table (cold repetitions, median), the command line
// (--quick, --markdown FILE) and the markdown text each program prints and writes.

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#ifndef DEPLOYSIM_BENCH_CXX_FLAGS
#define DEPLOYSIM_BENCH_CXX_FLAGS "?"
#endif

namespace deploysim::bench {

/// The CPU's model name from /proc/cpuinfo (Linux), for the tables' machine line.
inline std::string CpuModel() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

/// The 1, 5 and 15 minute load averages from /proc/loadavg ("?" elsewhere).
inline std::string LoadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  if (!(f >> a >> b >> c)) return "?";
  return a + " " + b + " " + c;
}

/// The compiler and its optimisation flags, as the benchmark was built.
inline std::string Compiler() {
#if defined(__clang__)
  std::string name = std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  std::string name = "GCC " + std::to_string(__GNUC__) + "." + std::to_string(__GNUC_MINOR__) +
                     "." + std::to_string(__GNUC_PATCHLEVEL__);
#else
  std::string name = "unknown compiler";
#endif
  std::string flags = DEPLOYSIM_BENCH_CXX_FLAGS;
  while (!flags.empty() && flags.front() == ' ') flags.erase(flags.begin());
  return flags.empty() ? name : name + " `" + flags + "`";
}

/// The current UTC date and time, "YYYY-MM-DD HH:MM UTC".
inline std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

/// One line naming the machine and the moment of the run, for under each table.
inline std::string MachineLine() {
  return "Machine: " + CpuModel() + ", " + std::to_string(std::thread::hardware_concurrency()) +
         " hardware threads, load average (1, 5, 15 min) " + LoadAverage() + "; " + Compiler() +
         "; " + UtcNow() + ".";
}

/// Wall times of cold repetitions of one run.
struct Timing {
  std::vector<double> seconds;  ///< Every repetition, in order.
  double median() const {
    if (seconds.empty()) throw std::logic_error("Timing::median of no repetitions");
    std::vector<double> s = seconds;
    std::sort(s.begin(), s.end());
    const std::size_t n = s.size();
    return n % 2 == 1 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
  }
  int n() const { return static_cast<int>(seconds.size()); }
};

/// The timing rule of every table: `n` repetitions of `run`, each a complete cold run
/// that builds everything it uses from the inputs (stepper, closed form, schedule,
/// Simbody system) inside the timed region; the median is reported.
template <class F>
Timing TimeCold(int n, F&& run) {
  if (n < 1) throw std::invalid_argument("TimeCold: n = " + std::to_string(n) + ": must be >= 1");
  Timing t;
  for (int i = 0; i < n; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    t.seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return t;
}

/// The sentence stating the timing rule, for under a table.
inline std::string TimingRule(int n, const std::string& what) {
  return "Timing: each side " + std::to_string(n) + (n == 1 ? " cold run" : " cold runs") +
         (n == 1 ? "" : ", median reported") + "; every run " + what + ".";
}

/// Markdown text built piece by piece: printed to stdout and, with --markdown, written to
/// a file (tools/bench.sh --update-readme puts the files into README.md).
class Markdown {
 public:
#if defined(__GNUC__)
  __attribute__((format(printf, 2, 3)))
#endif
  void
  Printf(const char* fmt, ...) {
    char buf[4096];
    va_list ap;
    va_start(ap, fmt);
    const int n = std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    if (n < 0) throw std::runtime_error("Markdown::Printf: bad format");
    if (static_cast<std::size_t>(n) >= sizeof buf) {
      std::vector<char> big(static_cast<std::size_t>(n) + 1);
      va_start(ap, fmt);
      std::vsnprintf(big.data(), big.size(), fmt, ap);
      va_end(ap);
      text_ += big.data();
    } else {
      text_ += buf;
    }
  }
  void Add(const std::string& s) { text_ += s; }
  const std::string& text() const { return text_; }

  /// Prints the text to stdout and writes it to `path` unless empty (throws on failure).
  void Emit(const std::string& path) const {
    std::fputs(text_.c_str(), stdout);
    std::fflush(stdout);
    if (path.empty()) return;
    std::ofstream f(path);
    f << text_;
    if (!f) throw std::runtime_error("cannot write " + path);
  }

 private:
  std::string text_;
};

/// The command line shared by the programs: --quick, --markdown FILE. Unknown arguments
/// are left in `rest` for the program.
struct Args {
  bool quick = false;
  std::string markdown;
  std::vector<std::string> rest;
};

inline Args ParseArgs(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--quick") {
      a.quick = true;
    } else if (s == "--markdown") {
      if (i + 1 >= argc) throw std::invalid_argument("--markdown: needs a FILE");
      a.markdown = argv[++i];
    } else {
      a.rest.push_back(s);
    }
  }
  return a;
}

}  // namespace deploysim::bench
