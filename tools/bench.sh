#!/usr/bin/env bash
# The benchmark, one command: builds (Release) and prints every table of ratios, each
# measured side by side in one run:
#   1. wing-nut work-precision table, ratios against the seed's thesis-euler (h = 2e-5 s)
#   2-3. deploysim against Simbody at matched accuracy (free body; satellite deployment)
#   4. sweep throughput with 1 and 2 threads and 2 MPI ranks, parallel efficiency
# Usage: tools/bench.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install_deps.sh >/dev/null
cmake --preset release >/dev/null
cmake --build --preset release --target wing_nut_bench simbody_bench sweep_bench deploysim >/dev/null
echo "== 1. wing nut work-precision =="
build/release/bench/wing_nut_bench "$@"
echo
echo "== 2-3. deploysim vs Simbody =="
build/release/bench/simbody_bench "$@"
echo
echo "== 4. sweep throughput =="
build/release/bench/sweep_bench "$@"
