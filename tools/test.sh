#!/usr/bin/env bash
# Installs what is missing, builds deploysim and runs its test suite.
# Usage: tools/test.sh [release|asan|tsan]
#   release (default): optimised, warnings as errors; the whole suite, then
#            tools/check_install.sh (install, and build examples/ against the package)
#   asan:    AddressSanitizer + UndefinedBehaviorSanitizer, the whole suite but the tools'
#            checks of documents and pages (label tools: they re-run the same binary paths
#            the cli tests cover, 5-10x slower under the sanitizers) and the long runs of
#            tests/long_runs.txt (each beside the short tests that run its code paths)
#   tsan:    ThreadSanitizer, only what runs threads: the sweep tests (runner, thread
#            pool, MPI) and the libraries below them
set -euo pipefail
preset="${1:-release}"
case "$preset" in release|asan|tsan) ;; *) echo "usage: tools/test.sh [release|asan|tsan]" >&2; exit 2 ;; esac
cd "$(dirname "$0")/.."
tools/install_deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
skip=()
if [ "$preset" = asan ]; then
  skip=(-E "$(tools/long_runs.sh)")
fi
ctest --preset "$preset" -j2 "${skip[@]}"
if [ "$preset" = release ]; then
  tools/check_install.sh build/release
fi
