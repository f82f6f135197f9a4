#!/usr/bin/python3
"""Writes a self-contained 3D viewer (one HTML file) of a deploysim run.

Usage: /usr/bin/python3 tools/view.py RESULT.h5 -o RESULT.html [--model MODEL.yaml]
                                      [--title TEXT] [--three DIR]

RESULT.h5 is a trajectory (`deploysim simulate`) or a cross-check file (`deploysim
crosscheck`: the reduced model and Simbody side by side). The page works offline from a
local disk: three.js r111 and its OrbitControls from Debian's libjs-three are inlined, the
run's samples are decimated (tools/deploysim_scene.py) and embedded as JSON. docs/viewer.md
describes the scene, the controls and the page's test hooks (window.deploysimReady,
window.deploysimSetTime(t)).

Exit status: 0 written; 1 bad input (one line on stderr, no output file written);
2 bad usage.
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
        sides.append(dict(label=s["label"], q=_r(q, 6), H=_r(s["H"][idx], 8),
                          Hnorm=float(np.linalg.norm(s["H"][0])),
                          angle=_r(np.degrees(s["angle"][idx]), 3), hN=_r(h, 6),
                          flips=_r(s["flips"], 6)))
    n_sides = len(sides)
    hinge = None
    if run["geometry"] is not None:
        hinge = dict(names=run["geometry"].names, deg=_r(np.degrees(run["hinge"][idx]), 3))
    if run["geometry"] is not None:
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
        danger=run["danger"], events=run["events"], attrs=run["attrs"],
        outcome=run.get("outcome"),
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
    # Atomic: a temporary file in the same folder, renamed into place.
    d = os.path.dirname(os.path.abspath(out))
    fd, tmp = tempfile.mkstemp(prefix=".view-", suffix=".html", dir=d)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(page)
        os.replace(tmp, out)
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
    a = ap.parse_args(argv)
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
