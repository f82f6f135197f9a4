#pragma once

/// Runs the deploysim executable in a shell for the CLI tests: the command line is
/// `prefix` (e.g. ulimits) + `deploysim ARGS < stdin_from`, stdout discarded, stderr
/// captured through the file `err_path`.

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

namespace deploysim::testing {

struct CliRun {
  int exit_code = -1;  ///< -1 if killed by a signal
  std::string err;     ///< everything written to stderr
};

inline CliRun RunCliInShell(const std::string& prefix,
                            const std::string& args,
                            const std::string& err_path,
                            const std::string& stdin_from = "/dev/null") {
  const std::string cmd = prefix + "'" + std::string(DEPLOYSIM_CLI) + "' " + args + " <'" +
                          stdin_from + "' >/dev/null 2>'" + err_path + "'";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream f(err_path);
  r.err.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  return r;
}

}  // namespace deploysim::testing
