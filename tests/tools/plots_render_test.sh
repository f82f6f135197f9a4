#!/usr/bin/env bash
# Renders the main job's plots in a scratch folder (issue 3, acceptance 5) and checks
# that every PNG exists, is a PNG and is not trivially small; and that the plot tool
# rejects a missing or non-trajectory file with one line and a non-zero exit.
# Usage: plots_render_test.sh DEPLOYSIM_BINARY SOURCE_DIR
set -euo pipefail
cli="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$cli" simulate "$src/deployment_profiles/smallsat_three_stage.yaml" -q -o "$tmp/smallsat.h5"
/usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/smallsat.h5" -o "$tmp/plots" >/dev/null
for f in momentum angular_velocity spin_axis inertia polhode; do
  png="$tmp/plots/$f.png"
  [ -f "$png" ] || { echo "FAIL: $f.png missing"; exit 1; }
  head -c 8 "$png" | od -An -tx1 | grep -q "89 50 4e 47" || { echo "FAIL: $f.png is not a PNG"; exit 1; }
  size=$(stat -c %s "$png")
  [ "$size" -gt 20000 ] || { echo "FAIL: $f.png is only $size bytes"; exit 1; }
done
if /usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/nope.h5" 2>"$tmp/err"; then
  echo "FAIL: missing file accepted"; exit 1
fi
grep -q "nope.h5" "$tmp/err" || { echo "FAIL: error does not name the file"; exit 1; }
echo "plots: 5 PNGs rendered and checked"
