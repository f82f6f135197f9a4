#pragma once

// Helpers shared by the benchmark programs.

#include <fstream>
#include <string>

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

}  // namespace deploysim::bench
