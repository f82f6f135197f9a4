#!/usr/bin/python3
"""Writes a self-contained 3D viewer (one HTML file) of a deploysim run.

Usage: /usr/bin/python3 tools/view.py RESULT.h5 -o RESULT.html [--model MODEL.yaml]
                                      [--title TEXT] [--three DIR]

RESULT.h5 is a trajectory (`deploysim simulate`) or a cross-check file (`deploysim
crosscheck`: the reduced model and Simbody side by side). The page works offline from a
local disk: three.js r111 and its OrbitControls from Debian's libjs-three are inlined, the
run's samples are decimated (tools/deploysim_scene.py) and embedded as JSON. docs/viewer.md
describes the scene, the controls, the event list and the page's test hooks
(window.deploysimReady, window.deploysimSetTime(t), window.deploysimEvents, ...).

Exit status: 0 written; 1 bad input or usage (one line on stderr, no output file
written), as for every deploysim command.
Needs Debian's python3-h5py, python3-numpy, python3-yaml and libjs-three.
"""
import argparse
import json
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deploysim_scene as scene  # noqa: E402

THREE_DIR = "/usr/share/javascript/three"
TEMPLATE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "view_template.html")
# Pose keyframes: a drawn box is re-posed only where a hinge angle (rad) or, for the
# equivalent box, J_B (relative) changes by more than this between kept samples.
POSE_CHANGE = 1e-9
# Stop impacts of one panel less than this apart [s] are one row of the event list (a
# panel rattling on its stop).
STOP_BURST_GAP = 1.0
# The deployment window (the hinge chart's second view): the span in which a hinge moves,
# widened by this fraction of its length on each side, at least DEPLOY_PAD_MIN [s].
DEPLOY_PAD = 0.15
DEPLOY_PAD_MIN = 1.0
# Default playback speed: the whole run in about this many seconds, rounded to one of the
# page's speeds, never slower than real time.
PLAY_SECONDS = 60.0
RAD_S_TO_RPM = 60.0 / (2.0 * math.pi)

WHAT = {"release": "released", "latch": "latched", "jam": "jammed",
        "rest": "comes to rest on its stop", "lift-off": "lifts off its stop",
        "stick": "sticks (friction holds it)", "slip": "slips (friction lets go)"}


def _r(a, digits):
    return [round(float(x), digits) for x in np.ravel(a)]


def _pose_keyframes(run, idx, scale):
    """Kept-sample positions where the drawn boxes move, with their neighbours."""
    if run["geometry"] is not None:
        v = run["hinge"][idx]
    else:
        v = run["J"][idx].reshape(len(idx), -1) / max(np.abs(run["J"]).max(), 1e-300)
    moved = np.abs(np.diff(v, axis=0)).max(axis=1) > POSE_CHANGE
    keep = np.zeros(len(idx), dtype=bool)
    keep[0] = keep[-1] = True
    keep[1:] |= moved
    keep[:-1] |= moved
    out_t, out = [], []
    for j in np.nonzero(keep)[0]:
        i = idx[j]
        out_t.append(float(run["time"][i]))
        for c, R, d in scene.poses_at(run, i, scale):
            out += _r(c, 5) + _r(scene.matrix_to_quat(R), 6) + _r(d, 5)
    return out_t, out


def _deg(x):
    return math.degrees(x)


def _f1(x):
    """x with one decimal, without a minus sign on a rounded zero."""
    t = f"{x:.1f}"
    return "0.0" if t == "-0.0" else t


def event_list(run):
    """The page's event list, in time order: every row of the hinge event table (a burst
    of stop impacts of one panel as one row), the flips, and the outcome's transition.
    Each: t [s], t_last [s] (the burst's last impact, else t), kind, panel, side and text
    (units stated). A cross-check file has no hinge event table: its rows are when each
    hinge starts and stops moving (kinds "moves" and "halts")."""
    rows, burst = [], {}
    for e in run["events"]:
        p, k = e["panel"], e["kind"]
        a, rb, ra = _deg(e["angle"]), _deg(e["rate_before"]), _deg(e["rate_after"])
        if k == "stop":
            r = burst.get(p)
            if r is not None and e["t"] - r["t_last"] < STOP_BURST_GAP:
                r["count"] += 1
                r["t_last"] = e["t"]
                r["text"] = (f"{p}: {r['count']} stop impacts at {_f1(a)} deg, "
                             f"{r['t']:.2f}–{e['t']:.2f} s, the first at "
                             f"{_f1(r['first_rate'])} deg/s")
                continue
            r = dict(t=e["t"], t_last=e["t"], kind="stop", panel=p, side=None, count=1,
                     first_rate=abs(rb),
                     text=f"{p} hits its stop at {_f1(a)} deg, {_f1(abs(rb))} deg/s "
                          f"(rebounds at {_f1(abs(ra))} deg/s)")
            burst[p] = r
            rows.append(r)
            continue
        burst.pop(p, None)
        # An appendage's grouped releases come with their text (deploysim_scene).
        text = e.get("text") or f"{p} {WHAT.get(k, k)} at {_f1(a)} deg"
        if k in ("latch", "jam", "stick"):
            text += f", {_f1(abs(rb))} deg/s"
            if e["impulse"]:
                text += f" (impulse {abs(e['impulse']):.3g} N m s)"
        rows.append(dict(t=e["t"], t_last=e["t"], kind=k, panel=p, side=None, count=1,
                         text=text))
    if run["kind"] == "crosscheck" and run["geometry"] is not None:
        # A cross-check file has no hinge event table: when each hinge starts and stops
        # moving, from Simbody's hinge angles.
        t, h = run["time"], run["hinge"]
        for p, name in enumerate(run["geometry"].names):
            moving = np.nonzero(np.abs(np.diff(h[:, p])) > scene.HINGE_MOTION)[0]
            if len(moving) == 0:
                continue
            a, b = moving[0], moving[-1] + 1
            rows.append(dict(t=float(t[a]), t_last=float(t[a]), kind="moves", panel=name,
                             side=None, count=1,
                             text=f"{name} starts to move from {_f1(_deg(h[a, p]))} deg "
                                  "(Simbody's hinge angle)"))
            rows.append(dict(t=float(t[b]), t_last=float(t[b]), kind="halts", panel=name,
                             side=None, count=1,
                             text=f"{name} stops moving at {_f1(_deg(h[b, p]))} deg "
                                  "(Simbody's hinge angle)"))
    two = len(run["sides"]) > 1
    for si, s in enumerate(run["sides"]):
        n = len(s["flips"])
        for i, tf in enumerate(s["flips"]):
            rows.append(dict(t=float(tf), t_last=float(tf), kind="flip", panel=None, side=si,
                             count=1, text=f"flip {i + 1} of {n}"
                             + (f" ({s['label']})" if two else "")
                             + ": the spin axis passes 90 deg from h_N"))
    o = run.get("outcome")
    if o and o.get("transition_time") is not None:
        tt = float(o["transition_time"])
        rows.append(dict(t=tt, t_last=tt, kind="transition", panel=None, side=None, count=1,
                         text=f"{o['name']}: the spin axis passes 45 deg from its start "
                              "for the last time"))
    rows.sort(key=lambda r: (r["t"], r["kind"], r["side"] or 0))
    for r in rows:
        r.pop("first_rate", None)
        r["t"], r["t_last"] = round(r["t"], 6), round(r["t_last"], 6)
    return rows


def hinge_channels(geometry):
    """The hinge chart's and readout's lines: (names, hinge columns summed per line)
    (deploysim_scene.hinge_channels)."""
    return scene.hinge_channels(geometry.names, geometry.appendages)


def deployment_window(run):
    """[t0, t1] around the span in which a hinge moves (the hinge chart's second view), or
    None."""
    span = scene.moving_span(run)
    if span is None:
        return None
    pad = max(DEPLOY_PAD * (span[1] - span[0]), DEPLOY_PAD_MIN)
    t = run["time"]
    return [max(float(t[0]), span[0] - pad), min(float(t[-1]), span[1] + pad)]


def footer(run):
    """The cross-check file's maxima as text with units and three significant digits."""
    out = []
    for k, (label, _, unit, factor) in scene.CROSSCHECK_MAXIMA.items():
        if k in run["attrs"]:
            v = run["attrs"][k] * factor
            out.append(f"{label}: {v:.3g}" + (f" {unit}" if unit else ""))
    return out


def build_data(run, title=None):
    """The page's JSON: decimated samples, pose keyframes and the run's annotations."""
    idx = scene.decimate(run)
    scale = scene.tensor_scale(run)
    t = run["time"][idx]
    names, kinds = scene.part_names(run)
    pose_t, pose = _pose_keyframes(run, idx, scale)
    L = scene.extent(run, idx, scale)
    sides = []
    for k, s in enumerate(run["sides"]):
        q = s["q"][idx] / np.linalg.norm(s["q"][idx], axis=1)[:, None]
        h = s["h_N"][0] / np.linalg.norm(s["h_N"][0])
        # The hub's rate |w_NB_B| in rpm, where the file has it.
        rpm = (None if s.get("w") is None
               else _r(np.linalg.norm(s["w"][idx], axis=1) * RAD_S_TO_RPM, 4))
        sides.append(dict(label=s["label"], q=_r(q, 6), H=_r(s["H"][idx], 8),
                          Hnorm=float(np.linalg.norm(s["H"][0])),
                          angle=_r(np.degrees(s["angle"][idx]), 3), hN=_r(h, 6),
                          flips=_r(s["flips"], 6), rpm=rpm))
    n_sides = len(sides)
    hinge = None
    if run["geometry"] is not None:
        lines_names, columns = hinge_channels(run["geometry"])
        rates = run.get("hinge_rates")

        def lines(x):  # (kept samples, lines): each line the sum of its hinges' columns
            return np.stack([x[idx][:, c].sum(axis=1) for c in columns], axis=1)
        hinge = dict(names=lines_names, deg=_r(np.degrees(lines(run["hinge"])), 3),
                     rate=None if rates is None else _r(np.degrees(lines(rates)), 3),
                     window=deployment_window(run))
    if run["geometry"] is not None and run["geometry"].appendages:
        body = ("hub, panels and appendages (%s) at their hinge angles (model %s)"
                % (", ".join(a["name"] for a in run["geometry"].appendages), run["model_name"]))
    elif run["geometry"] is not None:
        body = "hub and panels at their hinge angles (model %s)" % run["model_name"]
    else:
        body = ("uniform box with the principal moments of J_B (model %s, tensor mode)"
                % run["model_name"])
    what = ("cross-check: reduced model and Simbody" if run["kind"] == "crosscheck"
            else "trajectory")
    return dict(
        title=title or "%s (%s)" % (run["profile_name"], what),
        source=os.path.basename(run["path"]), kind=run["kind"], body=body,
        t=_r(t, 6), t0=float(t[0]), t1=float(t[-1]), samples=len(run["time"]),
        kept=len(idx), sides=sides, hinge=hinge, parts=dict(names=names, kinds=kinds),
        poses=dict(t=pose_t, data=pose, stride=10 * len(names)),
        spinAxisB=_r(run["spin_axis_B"], 6), extent=L, stages=run["stages"],
        danger=run["danger"], events=event_list(run), foot=footer(run),
        outcome=run.get("outcome"), playSeconds=PLAY_SECONDS,
        trailSeconds=scene.trail_seconds(run),
        spacing=2.6 * L if n_sides > 1 else 0.0)


def inline_js(three_dir):
    parts = []
    for rel in ("three.min.js", "examples/js/controls/OrbitControls.js"):
        p = os.path.join(three_dir, rel)
        if not os.path.isfile(p):
            raise scene.SceneError(f"{p}: not found (Debian package libjs-three)")
        with open(p, encoding="utf-8") as fh:
            js = fh.read()
        if "</script" in js.lower():
            raise scene.SceneError(f"{p}: contains </script>; cannot inline")
        parts.append(js)
    return "\n".join(parts)


def write_html(data, out, three_dir=THREE_DIR):
    with open(TEMPLATE, encoding="utf-8") as fh:
        page = fh.read()
    js = inline_js(three_dir)
    blob = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    page = page.replace("/*@THREE@*/", js, 1).replace("@DATA@", blob, 1)
    page = page.replace("@TITLE@", data["title"].replace("&", "&amp;").replace("<", "&lt;"))
    # Atomic: a temporary file in the same folder, renamed into place with the usual mode.
    d = os.path.dirname(os.path.abspath(out))
    fd, tmp = tempfile.mkstemp(prefix=".view-", suffix=".html", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(page)
        scene.publish(tmp, out)
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv):
    ap = argparse.ArgumentParser(
        prog=os.environ.get("DEPLOYSIM_PROG") or None,
        description=__doc__.split("\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="examples:\n"
               "  deploysim simulate deployment_profiles/smallsat_spring_deploy.yaml -o spring.h5\n"
               "  deploysim view spring.h5 -o spring.html         (open spring.html in a browser)\n"
               "  deploysim crosscheck deployment_profiles/smallsat_spring_deploy.yaml --until 300 "
               "-o cc.h5\n"
               "  deploysim view cc.h5 -o cc.html                 (reduced model and Simbody side by side)\n"
               "  /usr/bin/python3 tools/view.py spring.h5 -o spring.html   (the same, without the CLI)\n"
               "The page and its controls: docs/viewer.md.")
    # Set by `deploysim view` (the executable that ran this script); not needed here.
    ap.add_argument("--deploysim", help=argparse.SUPPRESS)
    ap.add_argument("result", help="trajectory or cross-check file (HDF5) written by deploysim")
    ap.add_argument("-o", "--output", required=True, help="HTML file to write")
    ap.add_argument("--model", help="model YAML to draw (default: the file's model_text; for a "
                                    "cross-check file, the model its profile names)")
    ap.add_argument("--title", help="page title")
    ap.add_argument("--three", default=THREE_DIR, help="libjs-three folder (default %(default)s)")
    try:
        a = ap.parse_args(argv)
    except SystemExit as e:
        # argparse exits 2 on bad usage; deploysim's commands exit 1 for any bad input.
        raise SystemExit(1 if e.code == 2 else e.code)
    try:
        for src in (a.result, a.model):
            if src and os.path.exists(a.output) and os.path.samefile(src, a.output):
                raise scene.SceneError(f"{a.output}: output is the input file {src} (rule: an "
                                       "output never replaces an input)")
        run = scene.read_run(a.result, a.model)
        data = build_data(run, a.title)
        if not all(math.isfinite(x) for s in data["sides"] for x in s["q"]):
            raise scene.SceneError(f"{a.result}: non-finite attitude")
        write_html(data, a.output, a.three)
    except scene.SceneError as e:
        print(f"view: {e}", file=sys.stderr)
        return 1
    except (OSError, KeyError, ValueError, TypeError) as e:
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        print(f"view: {a.result}: cannot read ({msg})", file=sys.stderr)
        return 1
    size = os.path.getsize(a.output)
    print(f"wrote {a.output} ({size / 1e6:.2f} MB; {data['kept']} of {data['samples']} "
          f"samples, {len(data['poses']['t'])} pose keyframes)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
