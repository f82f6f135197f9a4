#!/usr/bin/env bash
# Renders the main job's plots in a scratch folder and checks that every PNG exists, is
# a PNG and is not trivially small; and that the plot tool rejects a missing or
# non-trajectory file with one line and a non-zero exit. energy.png for every file,
# hinge_angles.png for files with hinge angles (geometry mode: the main job has them); a
# version 2 file from before the free-hinge outputs still plots; and, when the spring-driven
# deployment profile is there, the same plots of a free-hinge run (hinge events marked).
# Of each run, what was drawn is checked too (check_drawn: units, axis ranges, every hinge
# event numbered and in the key, a polhode panel per stage).
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

# What was drawn, from the JSON each PNG carries (tEXt chunk "deploysim-axes": every axes'
# labels, limits and curves' y range, the numbered hinge events), against the trajectory
# file read here with h5py: every axis names its unit (time s, angles deg, rates deg/s,
# never rad); no axes is stretched beyond its curves (the event labels stand in a strip
# above it): the top of each time plot's first axes at most 10 % of the curves' range above
# them, the spin-axis angle (0-180 deg) within [-10, 190] deg; every hinge event is in the
# key and every number 1..N in the strip; the polhode has a panel of its own per stage.
check_drawn() {  # folder, trajectory file
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, math, re, struct, sys
import h5py, numpy as np

folder, traj = sys.argv[1], sys.argv[2]


def drawn(name):
    data = open(f"{folder}/{name}.png", "rb").read()
    pos = 8
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"tEXt" and body.startswith(b"deploysim-axes\0"):
            return json.loads(body.split(b"\0", 1)[1].decode("latin-1"))
    sys.exit(f"FAIL: {name}.png carries no deploysim-axes metadata")


def fail(msg):
    sys.exit(f"FAIL: {traj}: {msg}")


UNIT = re.compile(r"\[[^\]]+\]\s*$")
with h5py.File(traj, "r") as f:
    t = f["time"][()]
    angle = np.degrees(f["spin_axis_angle"][()])
    stage_names = [x.decode() if isinstance(x, bytes) else x for x in f["stages/name"][()]]
    stage_laws = [x.decode() if isinstance(x, bytes) else x for x in f["stages/law"][()]]
    hinge = {}
    if "events" in f and "hinge" in f["events"]:
        ev = f["events/hinge"]
        hinge = {k: ev[k][()] for k in ("time", "kind", "panel_name")}
stretches = []  # consecutive stages of the same name and law are one stretch
for nm, law in zip(stage_names, stage_laws):
    if not stretches or stretches[-1] != (nm, law):
        stretches.append((nm, law))

time_plots = ["momentum", "angular_velocity", "spin_axis", "inertia", "energy", "hinge_angles"]
for name in time_plots + ["polhode"]:
    meta = drawn(name)
    for k, ax in enumerate(meta["axes"]):
        # (a twin axes shares the time axis of the one it is drawn over)
        labels = [ax["ylabel"]] + ([] if ax.get("twin") else [ax["xlabel"]]) + (
            [ax["zlabel"]] if "zlabel" in ax else [])
        for lab in labels:
            if not UNIT.search(lab):
                fail(f"{name}.png axes {k}: label {lab!r} states no unit")
            if re.search(r"\[rad", lab):
                fail(f"{name}.png axes {k}: {lab!r}: angles in deg, rates in deg/s")
        if name in time_plots and not ax.get("twin") and ax["xlabel"] != "time [s]":
            fail(f"{name}.png axes {k}: time axis labelled {ax['xlabel']!r}")
    top = meta["axes"][0]
    # (the spin-axis angle keeps its full 0-180 deg scale: checked below)
    if name in time_plots and name != "spin_axis" and top["ydata"]:
        lo, hi = top["ydata"]
        room = top["ylim"][1] - hi
        if room > 0.10 * (hi - lo) + 1e-12 * max(abs(hi), abs(lo), 1e-300):
            fail(f"{name}.png: y axis up to {top['ylim'][1]:.4g}, {room:.3g} above its "
                 f"curves ({lo:.4g} to {hi:.4g}): stretched")
    if name == "spin_axis":
        y0, y1 = top["ylim"]
        if not (-10.0 <= y0 and y1 <= 190.0 and y1 >= angle.max() and y0 <= angle.min()):
            fail(f"spin_axis.png: y limits {y0:.4g}..{y1:.4g} deg for angles "
                 f"{angle.min():.4g}..{angle.max():.4g} deg (want within -10..190)")
    if name in ("spin_axis", "hinge_angles"):
        items = meta["events"]
        if [it["n"] for it in items] != list(range(1, len(items) + 1)):
            fail(f"{name}.png: events not numbered 1..N")
        shown = sorted(int(x) for x in top["strip"]) if items else []
        if shown != [it["n"] for it in items]:
            fail(f"{name}.png: strip shows {shown}, the key has {len(items)} events")
        # every hinge event of the file is in the key: the stops by their bursts' counts,
        # the others by time, kind and panel (a release at the start is no event)
        stops = sum(1 for k in hinge.get("kind", []) if k in (b"stop", "stop"))
        if sum(it["count"] for it in items if it["kind"] == "stop") != stops:
            fail(f"{name}.png: {stops} stop impacts, the key counts others")
        for tt, kind, pn in zip(*(hinge.get(k, []) for k in ("time", "kind", "panel_name"))):
            kind, pn = (x.decode() if isinstance(x, bytes) else x for x in (kind, pn))
            if kind == "stop" or (kind == "release" and tt <= t[0]):
                continue
            if not any(it["t"] == tt and it["kind"] == kind and pn in it["names"]
                       for it in items):
                fail(f"{name}.png: {kind} {pn} at {tt} s not in the key")
    if name == "polhode":
        titles = [ax["title"] for ax in meta["axes"] if re.match(r"\d+\. ", ax["title"])]
        want = [f"{k + 1}. {nm}" for k, (nm, _) in enumerate(stretches)]
        if [x.split("\n")[0] for x in titles] != want:
            fail(f"polhode.png: panels {titles}, stages {want}")
print(f"drawn: {traj}: units, ranges, events and stage panels checked")
PY
}

"$cli" simulate "$src/deployment_profiles/smallsat_three_stage.yaml" -q -o "$tmp/smallsat.h5"
/usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/smallsat.h5" -o "$tmp/plots" >/dev/null
# shellcheck disable=SC2086
check_pngs "$tmp/plots" $plots
check_drawn "$tmp/plots" "$tmp/smallsat.h5"
count=7

# A file written before the free-hinge outputs (no spring energy, hinge rates or event
# tables) still plots.
/usr/bin/python3 "$src/tools/plot_trajectory.py" "$src/tests/io/data/trajectory_v2_before_issue9.h5" \
  -o "$tmp/v2_plots" >/dev/null
# shellcheck disable=SC2086
check_pngs "$tmp/v2_plots" $plots
check_drawn "$tmp/v2_plots" "$src/tests/io/data/trajectory_v2_before_issue9.h5"
count=$((count + 7))

spring="$src/deployment_profiles/smallsat_spring_deploy.yaml"
if [ -f "$spring" ]; then
  "$cli" simulate "$spring" -q -o "$tmp/spring.h5"
  /usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/spring.h5" -o "$tmp/spring_plots" >/dev/null
  # shellcheck disable=SC2086
  check_pngs "$tmp/spring_plots" $plots
  check_drawn "$tmp/spring_plots" "$tmp/spring.h5"
  count=$((count + 7))
fi

if /usr/bin/python3 "$src/tools/plot_trajectory.py" "$tmp/nope.h5" 2>"$tmp/err"; then
  echo "FAIL: missing file accepted"; exit 1
fi
grep -q "nope.h5" "$tmp/err" || { echo "FAIL: error does not name the file"; exit 1; }
echo "plots: $count PNGs rendered and checked"
