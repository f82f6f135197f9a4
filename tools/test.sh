#!/usr/bin/env bash
# Installs what is missing, builds deploysim and runs its whole test suite.
# Usage: tools/test.sh [release|asan]   (default release: optimised, warnings as errors;
#        asan: AddressSanitizer + UndefinedBehaviorSanitizer)
set -euo pipefail
preset="${1:-release}"
case "$preset" in release|asan) ;; *) echo "usage: tools/test.sh [release|asan]" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."
tools/install_deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
ctest --preset "$preset" -j2
