#!/usr/bin/env bash
# The main job: installs what is missing, builds deploysim (Release), simulates the small
# satellite's spring-driven wing deployment (deployment_profiles/smallsat_spring_deploy.yaml:
# free hinges with torsion springs, dampers and latches), writes out/<profile>.h5 and its
# PNG plots in out/<profile>_plots/, the 3D viewer out/<profile>.html and the mission report
# out/<profile>_report.html, and prints the stability summary with the deployment timeline
# (releases, latches and their shocks).
# Usage: tools/run.sh [PROFILE.yaml]
#   e.g. tools/run.sh deployment_profiles/smallsat_three_stage.yaml   (the same wings moved
#        along a prescribed three-stage law; stage profiles also print the exact vs
#        quasi-rigid coupling comparison)
set -euo pipefail
cd "$(dirname "$0")/.."
profile="${1:-deployment_profiles/smallsat_spring_deploy.yaml}"
name="$(basename "$profile" .yaml)"
tools/install_deps.sh >/dev/null
echo "building deploysim (Release)..." >&2
cmake --preset release >/dev/null
cmake --build --preset release --target deploysim >/dev/null
mkdir -p out
compare=()
# Free hinges are coupled exactly; the coupling comparison is for stage profiles.
grep -q '^hinges:' "$profile" || compare=(--compare-coupling)
build/release/bin/deploysim simulate "$profile" -o "out/$name.h5" "${compare[@]}"
/usr/bin/python3 tools/plot_trajectory.py "out/$name.h5" -o "out/${name}_plots"
build/release/bin/deploysim view "out/$name.h5" -o "out/$name.html"
build/release/bin/deploysim report "$profile" -q -o "out/${name}_report.html"
echo "open out/$name.html (3D viewer) and out/${name}_report.html (mission report) in a browser"
