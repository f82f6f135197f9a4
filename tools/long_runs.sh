#!/usr/bin/env bash
# Prints the ctest regular expression (for ctest -E) of the long runs listed in
# tests/long_runs.txt: the tests that the sanitizer step (tools/test.sh asan) and the qemu
# step (tools/cross_aarch64.sh) leave out because a short test, named beside each there,
# runs the same code paths in those steps. Every one of them still runs in the Release step.
# Usage: tools/long_runs.sh
set -euo pipefail
list="$(dirname "$0")/../tests/long_runs.txt"
names=$(grep -vE '^\s*(#|$)' "$list" | awk '{print $1}' | paste -sd'|')
[ -n "$names" ] || { echo "long_runs.sh: $list lists no test" >&2; exit 1; }
printf '^(%s)$\n' "$names"
