#!/usr/bin/env bash
# The main job: installs what is missing, builds deploysim (Release) and runs the
# default simulation. Extra arguments go to `deploysim` (default: the wing-nut demo).
# Usage: tools/run.sh [deploysim arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh >/dev/null
cmake --preset release >/dev/null
cmake --build --preset release --target deploysim >/dev/null
if [ $# -eq 0 ]; then set -- wingnut; fi
exec build/release/src/cli/deploysim "$@"
