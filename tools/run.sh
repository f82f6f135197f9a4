#!/usr/bin/env bash
# The main job: installs what is missing, builds deploysim (Release), simulates the
# small satellite's three-stage wing deployment (deployment_profiles/smallsat_three_stage.yaml),
# writes out/smallsat.h5 and its PNG plots in out/smallsat_plots/, and prints the
# stability summary with the exact vs quasi-rigid coupling comparison.
# Usage: tools/run.sh [PROFILE.yaml]     (default: the small satellite)
set -euo pipefail
cd "$(dirname "$0")/.."
profile="${1:-deployment_profiles/smallsat_three_stage.yaml}"
name="$(basename "$profile" .yaml)"
name="${name%_three_stage}"
tools/install_deps.sh >/dev/null
echo "building deploysim (Release)..." >&2
cmake --preset release >/dev/null
cmake --build --preset release --target deploysim >/dev/null
mkdir -p out
build/release/bin/deploysim simulate "$profile" -o "out/$name.h5" --compare-coupling
/usr/bin/python3 tools/plot_trajectory.py "out/$name.h5" -o "out/${name}_plots"
