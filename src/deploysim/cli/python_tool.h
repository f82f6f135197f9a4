#pragma once

/// The subcommands that are Python programs (`deploysim report`, `deploysim view`): the
/// pages and figures are drawn with matplotlib and three.js, so they live in tools/ as
/// scripts; the CLI finds the script and replaces itself with the interpreter running it.

#include <string>
#include <vector>

namespace deploysim::cli {

/// The folder holding the Python tools, first that exists of: $DEPLOYSIM_TOOLS_DIR,
/// <folder of this executable>/../share/deploysim/tools (an installed package), and the
/// source tree's tools/ this binary was built from. Empty when none holds `script`.
std::string FindToolsDir(const std::string& script);

/// The interpreter: $DEPLOYSIM_PYTHON, else /usr/bin/python3 (Debian's, which has
/// matplotlib, numpy and h5py; the python3 first on PATH may not).
std::string PythonInterpreter();

/// Runs `<python> <tools>/<script> <args...> --deploysim <this executable>` in place of
/// this process (its exit code and signals are the script's), with $DEPLOYSIM_PROG set to
/// "deploysim <script stem>" for its usage lines. Returns only on failure,
/// with a one-line message in `error`.
void ExecPythonTool(const std::string& script,
                    const std::vector<std::string>& args,
                    std::string& error);

}  // namespace deploysim::cli
