#include "deploysim/cli/python_tool.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace deploysim::cli {
namespace {

namespace fs = std::filesystem;

fs::path SelfExecutable() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : p;
}

bool HasScript(const fs::path& dir, const std::string& script) {
  std::error_code ec;
  return !dir.empty() && fs::is_regular_file(dir / script, ec);
}

}  // namespace

std::string FindToolsDir(const std::string& script) {
  if (const char* env = std::getenv("DEPLOYSIM_TOOLS_DIR"); env != nullptr && *env != '\0') {
    return HasScript(env, script) ? std::string(env) : std::string();
  }
  const fs::path self = SelfExecutable();
  if (!self.empty()) {
    const fs::path installed = self.parent_path().parent_path() / "share" / "deploysim" / "tools";
    if (HasScript(installed, script)) return installed.string();
  }
#ifdef DEPLOYSIM_SOURCE_TOOLS_DIR
  if (HasScript(DEPLOYSIM_SOURCE_TOOLS_DIR, script)) return DEPLOYSIM_SOURCE_TOOLS_DIR;
#endif
  return {};
}

std::string PythonInterpreter() {
  if (const char* env = std::getenv("DEPLOYSIM_PYTHON"); env != nullptr && *env != '\0') {
    return env;
  }
  return "/usr/bin/python3";
}

void ExecPythonTool(const std::string& script,
                    const std::vector<std::string>& args,
                    std::string& error) {
  const std::string dir = FindToolsDir(script);
  if (dir.empty()) {
    error = script +
            ": not found (looked in $DEPLOYSIM_TOOLS_DIR, <prefix>/share/deploysim/tools and "
            "the source tree's tools/; rule: the report and view subcommands run deploysim's "
            "Python tools)";
    return;
  }
  const std::string python = PythonInterpreter();
  const fs::path self = SelfExecutable();
  std::vector<std::string> argv_s{python, (fs::path(dir) / script).string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  if (!self.empty()) {
    argv_s.push_back("--deploysim");
    argv_s.push_back(self.string());
  }
  std::vector<char*> argv_c;
  argv_c.reserve(argv_s.size() + 1);
  for (std::string& s : argv_s) argv_c.push_back(s.data());
  argv_c.push_back(nullptr);
  // The script names itself as the user called it (argparse's prog), e.g. "deploysim report".
  const std::string prog = "deploysim " + fs::path(script).stem().string();
  ::setenv("DEPLOYSIM_PROG", prog.c_str(), 1);
  ::execv(python.c_str(), argv_c.data());
  error = python + ": cannot run (" + std::strerror(errno) +
          "; rule: the report and view subcommands need Debian's python3 with matplotlib, "
          "numpy and h5py — tools/install_deps.sh installs them, or set DEPLOYSIM_PYTHON)";
}

}  // namespace deploysim::cli
