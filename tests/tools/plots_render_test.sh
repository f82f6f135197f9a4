#!/usr/bin/env bash
# Renders the main job's plots in a scratch folder and checks that every PNG exists, is
# a PNG and is not trivially small; and that the plot tool rejects a missing or
# non-trajectory file with one line and a non-zero exit. energy.png for every file,
# hinge_angles.png for files with hinge angles (geometry mode: the main job has them); a
# version 2 file from before the free-hinge outputs still plots; and, when the spring-driven deployment profile is there, the same plots of a
# free-hinge run (hinge events marked).
# Usage: plots_render_test.sh DEPLOYSIM_BINARY SOURCE_DIR
set -euo pipefail
cli="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
plots="momentum angular_velocity spin_axis inertia energy polhode hinge_angles"

check_pngs() {  # folder, names...
  local dir="$1"
  shift
  for f in "$@"; do
    png="$dir/$f.png"
    [ -f "$png" ] || { echo "FAIL: $png missing"; exit 1; }
    head -c 8 "$png" | od -An -tx1 | grep -q "89 50 4e 47" || { echo "FAIL: $png is not a PNG"; exit 1; }
    size=$(stat -c %s "$png")
    [ "$size" -gt 20000 ] || { echo "FAIL: $png is only $size bytes"; exit 1; }
  done
}

"$cli" simulate "$src/deployment_profiles/smallsat_three_stage.yaml" -q -o "$tmp/smallsat.h5"
/usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/smallsat.h5" -o "$tmp/plots" >/dev/null
# shellcheck disable=SC2086
check_pngs "$tmp/plots" $plots
count=7

# A file written before the free-hinge outputs (no spring energy, hinge rates or event
# tables) still plots.
/usr/bin/python3 "$src/tools/plot_trajectory.py" "$src/tests/io/data/trajectory_v2_before_issue9.h5" \
  -o "$tmp/v2_plots" >/dev/null
# shellcheck disable=SC2086
check_pngs "$tmp/v2_plots" $plots
count=$((count + 7))

spring="$src/deployment_profiles/smallsat_spring_deploy.yaml"
if [ -f "$spring" ]; then
  "$cli" simulate "$spring" -q -o "$tmp/spring.h5"
  /usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/spring.h5" -o "$tmp/spring_plots" >/dev/null
  # shellcheck disable=SC2086
  check_pngs "$tmp/spring_plots" $plots
  count=$((count + 7))
fi

if /usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/nope.h5" 2>"$tmp/err"; then
  echo "FAIL: missing file accepted"; exit 1
fi
grep -q "nope.h5" "$tmp/err" || { echo "FAIL: error does not name the file"; exit 1; }
echo "plots: $count PNGs rendered and checked"
