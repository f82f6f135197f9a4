#!/usr/bin/python3
"""Writes a mission report of a deployment profile: one self-contained HTML file.

Usage:
  /usr/bin/python3 tools/report.py PROFILE.yaml -o REPORT.html [--deploysim BIN]
                                   [--method M] [--rtol R] [--atol A] [--step S] [--dt D]

What it runs (all with the same settings, the overrides passed to each):
  BIN analyze PROFILE --json        the numbers of the report (the JSON is the contract)
  BIN simulate PROFILE -o T.h5      the trajectory: model, inputs' text, plots, energy
  BIN analyze PROFILE --json --coupling OTHER   stage profiles in geometry mode: the
                                    flips under the other coupling (exact / quasi-rigid)
  tools/plot_trajectory.py T.h5     the time plots; tools/plot_geometry.py T.h5 (the
                                    inertia ellipsoid and the spacecraft), if present
and checks that simulate and analyze agree (flip times, stages, hinge events, latch
times, 45-degree crossings, danger windows, h_N drift, step counts identical); a
disagreement is an error (exit 4).

The report (no network, no scripts, images as data: URIs, A4 print style): a summary with
the verdict in one sentence, the configuration (model, principal moments and the spin
axis' role per stage end), the stability table with the danger windows and the
rigid-body caveats, the flips against the closed-form prediction, for free-hinge profiles
the deployment timeline (releases, latches, impulses, shocks, energy dissipated), the
coupling comparison, the plots, the integrator and its accuracy evidence, and the full
text of the inputs with the deploysim version.

Every number taken from `analyze --json` carries data-json="/json/pointer" and
data-value="<full precision>"; numbers computed from it carry data-derived="<expr>"
(`/a - /b`, `/a / /b`, `sum /x/*/y`, `len /x`, `norm /x`), numbers from the HDF5 file or
the model text carry data-src="<where>". data-value is in SI units (rad, rad/s) even
where the cell shows degrees; data-doc="other-coupling" marks pointers into the JSON of
the other-coupling run.

Exit codes: 0 written; 1 bad input (deploysim's one-line message passed through, or -o
naming an input, a missing deploysim); 2 bad command line; 3 the integration did not
reach its end time; 4 simulate and analyze disagree; 5 a plot tool or the output failed.
On any error nothing is written (the report goes to a temporary file in the target
folder, renamed at the end) and one line goes to stderr.

Examples:
  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_spring_deploy.yaml \\
      -o spring_report.html --deploysim build/release/bin/deploysim
  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_three_stage.yaml \\
      -o three_stage.html --method rkmk-rkf78 --rtol 1e-12 --dt 0.05
Needs Debian's python3-h5py, python3-numpy, python3-yaml, python3-matplotlib (run with
/usr/bin/python3).
"""

import argparse
import base64
import datetime
import html
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

TOOLS = os.path.dirname(os.path.abspath(__file__))
PROG = "report"

EXIT_BAD_INPUT = 1
EXIT_USAGE = 2
EXIT_INTEGRATION = 3
EXIT_DISAGREE = 4
EXIT_TOOL = 5

DEG = 180.0 / math.pi
RIGID_CAVEAT_MARK = "\u26a0"  # warning sign: the verdict holds only for a rigid body

# The figures of tools/plot_trajectory.py and tools/plot_geometry.py, in report order,
# with their captions.
TRAJECTORY_FIGURES = [
    ("spin_axis.png", "Angle between the initial body spin axis and the inertial angular "
     "momentum h_N. A flip is the axis turning over (through 90 deg); located flips and "
     "45-degree crossings are marked."),
    ("momentum.png", "Body-frame angular momentum H_B: its components exchange sign at "
     "each flip while |H_B| stays constant."),
    ("inertia.png", "Principal moments of J_B(t); stages shaded. The spin axis is in "
     "danger while its moment lies between the other two."),
    ("hinge_angles.png", "Hinge angles and rates per panel, with the hinge events "
     "(releases, latches, stops) marked."),
    ("angular_velocity.png", "Body angular velocity w_NB_B."),
    ("energy.png", "Kinetic energy (and, for free hinges, spring and total energy with the "
     "losses at hinge events)."),
    ("polhode.png", "Polhodes: H_B/|H_B| on the momentum sphere and its projections, with "
     "the separatrix of the final inertia."),
]
GEOMETRY_FIGURES = [
    ("geometry_ellipsoid.png", "The geometric picture of torque-free rotation for the "
     "principal moments of the last stage: the energy ellipsoid cut by the momentum sphere "
     "below, on and above the separatrix, and the family of polhodes, with this run's own "
     "polhode of that stage overlaid (docs/geometry.md)."),
    ("geometry_projections.png", "The same polhode family projected on the principal "
     "planes: ellipses about the stable axes, hyperbolas about the intermediate axis with "
     "the separatrix asymptotes; this run's polhode overlaid."),
]


class ReportError(Exception):
    """One line for stderr and an exit code."""

    def __init__(self, message, code, raw=False):
        super().__init__(message)
        self.code = code
        self.raw = raw  # a tool's own "deploysim: error: ..." line, passed through as is


def progress(args, msg):
    if not args.quiet:
        print(f"{PROG}: {msg}", file=sys.stderr, flush=True)


# --- running the tools ----------------------------------------------------------------

def find_deploysim(arg):
    if arg:
        if os.path.isfile(arg) and os.access(arg, os.X_OK):
            return os.path.abspath(arg)
        raise ReportError(f"--deploysim {arg}: not an executable file", EXIT_BAD_INPUT)
    for cand in (os.environ.get("DEPLOYSIM_BIN"), shutil.which("deploysim")):
        if cand and os.path.isfile(cand) and os.access(cand, os.X_OK):
            return os.path.abspath(cand)
    raise ReportError("no deploysim found: pass --deploysim BIN (or set DEPLOYSIM_BIN)",
                      EXIT_BAD_INPUT)


def overrides(args):
    out = []
    for name in ("method", "rtol", "atol", "step", "dt"):
        v = getattr(args, name)
        if v is not None:
            out += [f"--{name}", str(v)]
    return out


def run(cmd, what):
    """Runs cmd; returns (stdout, seconds). A failure raises with the tool's own last line."""
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    except OSError as e:
        raise ReportError(f"{what}: cannot run {cmd[0]}: {e.strerror}", EXIT_BAD_INPUT)
    if p.returncode != 0:
        lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
        line = lines[-1] if lines else f"{what} failed (exit {p.returncode}, no message)"
        # deploysim: 1 and CLI11's codes (>= 100) are bad input, 3 an integration that
        # stopped early; the plot tools' failures are tool failures.
        if what.startswith("plot"):  # their lines name the tool already
            raise ReportError(line if what.split(".")[0] in line else f"{what}: {line}",
                              EXIT_TOOL)
        code = EXIT_INTEGRATION if p.returncode == 3 else EXIT_BAD_INPUT
        raise ReportError(line, code, raw=line.startswith("deploysim"))
    return p.stdout, time.monotonic() - t0


def same_file(a, b):
    try:
        if os.path.exists(a) and os.path.exists(b):
            return os.path.samefile(a, b)
    except OSError:
        pass
    return os.path.realpath(a) == os.path.realpath(b)


def model_path_of(profile):
    """The model file the profile names (for the -o check), or None if unreadable."""
    try:
        import yaml
        with open(profile, encoding="utf-8") as f:
            doc = yaml.safe_load(f)
        m = doc.get("model") if isinstance(doc, dict) else None
        if isinstance(m, str):
            return os.path.join(os.path.dirname(profile), m)
    except Exception:  # deploysim reports a bad profile in its own words
        pass
    return None


# --- reading --------------------------------------------------------------------------

def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def read_h5(path):
    import h5py
    import numpy as np
    d = {}
    with h5py.File(path, "r") as f:
        d["attrs"] = {k: text(v) for k, v in f.attrs.items()}
        for k in ("time", "H_B", "w_NB_B", "J_B", "principal_moments", "energy", "h_N"):
            d[k] = f[k][()]
        d["energy_total"] = f["energy_total"][()] if "energy_total" in f else None

        def get(name, default=None):
            return f[name][()] if name in f else default
        d["flip_time"] = get("events/flip_time", np.array([]))
        d["predicted_flip_time"] = get("events/predicted_flip_time", np.array([]))
        d["cross45"] = get("events/spin_axis_45_time", np.array([]))
        d["danger_begin"] = get("danger_windows/t_begin", np.array([]))
        d["danger_end"] = get("danger_windows/t_end", np.array([]))
        d["latch_time"] = get("hinge_latch_time", np.array([]))
        d["panel_names"] = [text(s) for s in get("panel_names", [])]
        st = {}
        for k in ("t_begin", "t_end", "spin_axis_role", "moments_end", "name", "rigid"):
            st[k] = get("stages/" + k, [])
        d["stages"] = st
        ev = {}
        for k in ("time", "kind", "panel"):
            ev[k] = get("events/hinge/" + k, [])
        d["hinge"] = ev
    return d


def parse_kv(s):
    """'steps=278, rejected=28' -> {'steps': '278', ...}"""
    out = {}
    for part in s.split(","):
        if "=" in part:
            k, v = part.split("=", 1)
            out[k.strip()] = v.strip()
    return out


def check_agreement(j, h):
    """simulate (HDF5) and analyze (JSON) must be the same run: raise on the first
    difference."""
    def same_list(name, a, b):
        a, b = [float(x) for x in a], [float(x) for x in b]
        if len(a) != len(b):
            raise ReportError(f"simulate and analyze disagree: {name}: {len(b)} in the HDF5 "
                              f"file, {len(a)} in analyze --json", EXIT_DISAGREE)
        for i, (x, y) in enumerate(zip(a, b)):
            if not (x == y or (math.isnan(x) and math.isnan(y))):
                raise ReportError(f"simulate and analyze disagree: {name}[{i}]: {y!r} (HDF5) "
                                  f"vs {x!r} (analyze --json)", EXIT_DISAGREE)

    same_list("flip times", j["flip_times"], h["flip_time"])
    same_list("predicted flip times",
              [t for s in j["stages"] for t in s["predicted_flips"]], h["predicted_flip_time"])
    same_list("stage starts", [s["t_begin"] for s in j["stages"]], h["stages"]["t_begin"])
    same_list("stage ends", [s["t_end"] for s in j["stages"]], h["stages"]["t_end"])
    same_list("stage end moments", [m for s in j["stages"] for m in s["principal_moments_end"]],
              [m for row in h["stages"]["moments_end"] for m in row])
    roles_h = [text(r) for r in h["stages"]["spin_axis_role"]]
    roles_j = [s["spin_axis_end"] for s in j["stages"]]
    if roles_h != roles_j:
        raise ReportError(f"simulate and analyze disagree: spin-axis roles {roles_h} (HDF5) vs "
                          f"{roles_j} (analyze --json)", EXIT_DISAGREE)
    same_list("45-degree crossings", j["spin_axis_45_crossings"], h["cross45"])
    same_list("danger window starts", [w[0] for w in j["danger_windows"]], h["danger_begin"])
    same_list("danger window ends", [w[1] for w in j["danger_windows"]], h["danger_end"])
    same_list("hinge event times", [e["t"] for e in j["hinge_events"]], h["hinge"]["time"])
    kinds_h = [text(k) for k in h["hinge"]["kind"]]
    if kinds_h != [e["kind"] for e in j["hinge_events"]]:
        raise ReportError("simulate and analyze disagree: hinge event kinds", EXIT_DISAGREE)
    latch_j = [j["latch_times"].get(n) for n in h["panel_names"]] if j["latch_times"] else []
    same_list("latch times", [float("nan") if v is None else v for v in latch_j],
              h["latch_time"] if j["latch_times"] else [])
    drift_h = float(h["attrs"].get("max_h_N_drift", "nan"))
    if drift_h != j["max_h_N_drift"]:
        raise ReportError(f"simulate and analyze disagree: max_h_N_drift {drift_h!r} (HDF5) vs "
                          f"{j['max_h_N_drift']!r} (analyze --json)", EXIT_DISAGREE)
    stats = parse_kv(h["attrs"].get("statistics", ""))
    for key, jkey in (("steps", "steps"), ("evaluations", "rhs_evaluations")):
        if key in stats and int(stats[key]) != j[jkey]:
            raise ReportError(f"simulate and analyze disagree: {jkey} {stats[key]} (HDF5) vs "
                              f"{j[jkey]} (analyze --json)", EXIT_DISAGREE)
    if h["attrs"].get("integrator") != j["integrator"]:
        raise ReportError("simulate and analyze disagree: integrator "
                          f"{h['attrs'].get('integrator')} vs {j['integrator']}", EXIT_DISAGREE)


# --- analysis of the HDF5 file ---------------------------------------------------------

AXIS_NAMES = ("x", "y", "z")


def initial_spin_axis(h):
    """The principal axis of J_B(t0) most nearly parallel to H_B(t0), signed along it
    (docs/file_formats.md, Flips, rule 1); its name and role among the principal axes."""
    import numpy as np
    vals, vecs = np.linalg.eigh(h["J_B"][0])
    H = h["H_B"][0]
    cos = [abs(vecs[:, k] @ H) / np.linalg.norm(H) for k in range(3)]
    k = int(np.argmax(cos))
    s = vecs[:, k] * (1.0 if vecs[:, k] @ H >= 0 else -1.0)
    big = int(np.argmax(np.abs(s)))
    if abs(s[big]) > 0.9999:
        name = ("+" if s[big] > 0 else "\u2212") + AXIS_NAMES[big]
    else:
        name = "[" + ", ".join(f"{c:.3f}" for c in s) + "]"
    lo, hi = vals[0], vals[2]
    tol = 1e-9 * hi
    if vals[1] - lo <= tol or hi - vals[1] <= tol:
        role = "degenerate"
    else:
        role = ("minor", "intermediate", "major")[k]
    return name, role, vals


def rigid_energy_drift(j, h):
    """Per rigid stage: max |E(t) - E(t1)| / E(t1) over the output samples strictly inside
    the stage (t1 the first of them); None with fewer than two samples."""
    import numpy as np
    t, E = h["time"], h["energy"]
    out = []
    for s in j["stages"]:
        if not s["rigid"]:
            out.append(None)
            continue
        m = (t > s["t_begin"]) & (t < s["t_end"])
        if np.count_nonzero(m) < 2:
            out.append(None)
            continue
        e = E[m]
        out.append((float(np.max(np.abs(e - e[0])) / abs(e[0])), int(np.count_nonzero(m))))
    return out


# --- HTML helpers -----------------------------------------------------------------------

def esc(s):
    return html.escape(str(s), quote=True)


def ptr(*parts):
    """A JSON pointer (RFC 6901) from its reference tokens."""
    return "".join("/" + str(p).replace("~", "~0").replace("/", "~1") for p in parts)


def get_ptr(doc, pointer):
    cur = doc
    for tok in pointer.split("/")[1:]:
        tok = tok.replace("~1", "/").replace("~0", "~")
        cur = cur[int(tok)] if isinstance(cur, list) else cur[tok]
    return cur


def value_attr(v):
    if v is None:
        return "null"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def fmt_num(v, digits=4):
    """Shortest readable form with `digits` significant digits."""
    if v is None:
        return "\u2014"
    if isinstance(v, int):
        return str(v)
    if v == 0:
        return "0"
    if not math.isfinite(v):
        return "\u221e" if v > 0 else "\u2212\u221e"
    a = abs(v)
    if a >= 1e-3 and a < 1e6:
        dec = max(0, digits - 1 - int(math.floor(math.log10(a))))
        s = f"{v:.{dec}f}"
    else:
        s = f"{v:.{digits - 1}e}"
        mant, ex = s.split("e")
        s = f"{mant}\u00d710<sup>{int(ex)}</sup>"
    return s.replace("-", "\u2212")


def fmt_fixed(v, dec):
    if v is None:
        return "\u2014"
    return f"{v:.{dec}f}".replace("-", "\u2212")


class Cells:
    """Makes the machine-readable number cells; keeps the JSON documents to read from."""

    def __init__(self, j, other=None):
        self.j = j
        self.other = other

    def _attrs(self, pointer, doc, unit):
        d = self.j if doc is None else self.other
        v = get_ptr(d, pointer)
        a = f' data-json="{esc(pointer)}" data-value="{esc(value_attr(v))}"'
        if doc:
            a += f' data-doc="{esc(doc)}"'
        if unit:
            a += f' data-unit="{esc(unit)}"'
        return a, v

    def js(self, pointer, shown=None, unit=None, tag="td", scale=1.0, digits=4, dec=None,
           doc=None, suffix="", cls="n"):
        """An element showing the JSON value at pointer (times scale), unit for data-unit."""
        a, v = self._attrs(pointer, doc, unit)
        if shown is None:
            if isinstance(v, str):
                shown = esc(v)
            elif isinstance(v, bool):
                shown = "yes" if v else "no"
            elif v is None:
                shown = "\u2014"
            elif dec is not None:
                shown = fmt_fixed(v * scale, dec)
            else:
                shown = fmt_num(v * scale if isinstance(v, float) or scale != 1.0 else v, digits)
        c = f' class="{cls}"' if cls and tag == "td" else ""
        return f"<{tag}{c}{a}>{shown}{suffix}</{tag}>"

    def derived(self, expr, value, shown, tag="td", unit=None, cls="n"):
        u = f' data-unit="{esc(unit)}"' if unit else ""
        c = f' class="{cls}"' if cls and tag == "td" else ""
        return (f'<{tag}{c} data-derived="{esc(expr)}" data-value="{esc(value_attr(value))}"'
                f"{u}>{shown}</{tag}>")

    @staticmethod
    def src(where, value, shown, tag="td", unit=None, cls="n"):
        u = f' data-unit="{esc(unit)}"' if unit else ""
        c = f' class="{cls}"' if cls and tag == "td" else ""
        return (f'<{tag}{c} data-src="{esc(where)}" data-value="{esc(value_attr(value))}"'
                f"{u}>{shown}</{tag}>")


def png_uri(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode("ascii")


CSS = """
@page { size: A4; margin: 14mm 13mm 16mm 13mm; }
*, *::before, *::after { box-sizing: border-box; }
html { font-family: "DejaVu Sans", "Liberation Sans", Arial, sans-serif; font-size: 10pt;
       color: #111; background: #fff; }
body { max-width: 196mm; margin: 0 auto; padding: 8mm 6mm 16mm; line-height: 1.38; }
h1 { font-size: 17pt; margin: 0 0 2pt; }
h2 { font-size: 13pt; margin: 18pt 0 6pt; padding-bottom: 2pt; border-bottom: 1.5px solid #333;
     break-after: avoid; page-break-after: avoid; }
h3 { font-size: 10.5pt; margin: 12pt 0 4pt; break-after: avoid; page-break-after: avoid; }
p { margin: 4pt 0 6pt; }
sup, sub { line-height: 0; }
.subtitle { color: #444; margin-bottom: 8pt; }
.meta { color: #444; font-size: 8.5pt; }
.summary { border: 1.5px solid #333; background: #f4f4f0; padding: 7pt 10pt; margin: 10pt 0;
           break-inside: avoid; page-break-inside: avoid; }
.summary .verdict { font-size: 11.5pt; font-weight: bold; margin: 2pt 0 6pt; }
.summary ul { margin: 2pt 0; padding-left: 14pt; }
.summary li { margin: 1pt 0; }
table { border-collapse: collapse; margin: 4pt 0 8pt; font-size: 8.6pt; width: 100%; }
caption { caption-side: top; text-align: left; font-weight: bold; padding: 2pt 0; font-size: 9pt; }
th, td { border: 1px solid #999; padding: 2pt 4pt; vertical-align: top; }
thead th { background: #e6e6e6; text-align: center; font-weight: bold; }
tbody th { text-align: left; font-weight: normal; background: #f6f6f6; }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.t { text-align: left; }
tr { break-inside: avoid; page-break-inside: avoid; }
table.kv { width: auto; }
table.kv caption { white-space: nowrap; }
table.stab { font-size: 7.8pt; }
table.stab th, table.stab td { padding: 2pt 3pt; }
table.kv th { text-align: left; background: #f6f6f6; font-weight: normal; }
.note { font-size: 8.6pt; color: #333; }
.warn { color: #8a1c1c; font-weight: bold; }
.na { border: 1px dashed #999; padding: 6pt; color: #555; background: #fafafa; }
figure { margin: 8pt 0 12pt; break-inside: avoid; page-break-inside: avoid; }
figure img { max-width: 100%; border: 1px solid #ccc; display: block; margin: 0 auto; }
figcaption { font-size: 8.6pt; color: #222; margin-top: 3pt; }
pre { font-family: "DejaVu Sans Mono", "Liberation Mono", monospace; font-size: 7.4pt;
      background: #f7f7f7; border: 1px solid #ccc; padding: 5pt; white-space: pre-wrap;
      word-break: break-word; }
code { font-family: "DejaVu Sans Mono", "Liberation Mono", monospace; font-size: 8.6pt; }
.toc { font-size: 9pt; columns: 2; margin: 4pt 0; padding-left: 16pt; }
.ok { color: #1b5e20; }
@media print {
  body { max-width: none; padding: 0; }
  .summary { background: none; }
  thead { display: table-header-group; }
  h2 { break-before: auto; }
  section.inputs { break-before: page; page-break-before: always; }
  a { color: inherit; text-decoration: none; }
}
"""


# --- the sections -----------------------------------------------------------------------

def role_text(role):
    return {"minor": "minor", "intermediate": "intermediate (unstable)",
            "major": "major", "degenerate": "degenerate (two moments equal)"}.get(role, role)


def section_summary(c, j, h, ctx):
    stages = j["stages"]
    last = len(stages) - 1
    parts = []
    axis = ctx["axis_name"]
    span_end = c.js(ptr("stages", last, "t_end"), tag="span", cls=None, digits=4, unit="s",
                    suffix="\u00a0s")
    dws = j["danger_windows"]
    if dws:
        first = c.js(ptr("danger_windows", 0, 0), tag="span", cls=None, dec=1, unit="s",
                     suffix="\u00a0s")
        if dws[0][0] <= stages[0]["t_begin"]:
            s = f"spin about {axis}, the intermediate axis from the start"
        else:
            s = f"spin about {axis} becomes the intermediate axis at {first}"
        # the final configuration: the last stage if rigid, intermediate, starting later
        ls = stages[last]
        if ls["rigid"] and ls["spin_axis_end"] == "intermediate" and ls["t_begin"] > dws[0][0]:
            s += (" (final configuration from "
                  + c.js(ptr("stages", last, "t_begin"), tag="span", cls=None, dec=1, unit="s",
                         suffix="\u00a0s") + ")")
        if len(dws) > 1:
            n = c.derived("len /danger_windows", len(dws), str(len(dws)), tag="span", cls=None)
            s += f" ({n} danger windows)"
        parts.append(s)
    else:
        role = stages[last]["spin_axis_end"]
        shown = {"degenerate": "an axis of two equal moments"}.get(role, f"the {role} axis")
        parts.append(f"spin about {axis} never becomes the intermediate axis (it ends as "
                     + c.js(ptr("stages", last, "spin_axis_end"), tag="span", cls=None,
                            shown=esc(shown)) + ")")
    nf = len(j["flip_times"])
    if nf:
        parts.append("first flip at " + c.js("/flip_times/0", tag="span", cls=None, dec=1,
                                              unit="s", suffix="\u00a0s"))
        parts.append(c.derived("len /flip_times", nf, str(nf), tag="span", cls=None)
                     + (" flip" if nf == 1 else " flips") + " in " + span_end)
    else:
        s = "no flips in " + span_end
        if j["spin_axis_45_crossings"]:
            # no flip, but the spin is not kept either (an energy sink, a flat spin)
            s += (", but the spin axis is 45\u00b0 away from the angular momentum at "
                  + c.js("/spin_axis_45_crossings/0", tag="span", cls=None, dec=1, unit="s",
                         suffix="\u00a0s"))
        parts.append(s)
    verdict = "; ".join(parts) + "."
    verdict = verdict[0].upper() + verdict[1:]
    items = []
    # agreement with the closed form
    pred = sum(len(s["predicted_flips"]) for s in stages)
    worst_i = max(range(len(stages)), key=lambda i: stages[i]["max_flip_time_difference"])
    if pred:
        items.append(
            "Located flips on the constant-inertia stages agree with the closed-form "
            "prediction to "
            + c.js(ptr("stages", worst_i, "max_flip_time_difference"), tag="span", cls=None,
                   unit="s", digits=2, suffix="\u00a0s") + " (section 3).")
    fs = stages[last]
    items.append(f"Final stage \u201c{esc(fs['name'])}\u201d: spin axis "
                 + c.js(ptr("stages", last, "spin_axis_end"), tag="span", cls=None)
                 + "; " + esc(fs["caveat"] or "no caveat") + "."
                 + (f' <span class="warn">{RIGID_CAVEAT_MARK} Only a perfectly rigid body would '
                    'keep this spin.</span>' if fs["rigid_body_only"] else ""))
    if j["hinge_events"]:
        ne = len(j["hinge_events"])
        total = sum(e["energy_dissipated"] for e in j["hinge_events"])
        latched = {k: v for k, v in j["latch_times"].items() if v is not None}
        if not latched:
            locked = "no panel locks"
        else:
            last = max(latched, key=lambda k: latched[k])
            locked = (("all panels" if len(latched) == len(j["latch_times"]) else
                       f"{len(latched)} of {len(j['latch_times'])} panels")
                      + " locked, the last at "
                      + c.js(ptr("latch_times", last), tag="span", cls=None, dec=2, unit="s",
                             suffix="\u00a0s"))
        items.append(
            "Deployment: "
            + c.derived("len /hinge_events", ne, str(ne), tag="span", cls=None)
            + (" hinge event, " if ne == 1 else " hinge events, ")
            + c.derived("sum /hinge_events/*/energy_dissipated", total,
                        fmt_num(total, 3) + "\u00a0J", tag="span", cls=None, unit="J")
            + (" dissipated in it; " if ne == 1 else " dissipated in them; ")
            + locked + " (section 4).")
    if "coupling_comparison" in j:
        items.append(
            "Quasi-rigid vs exact coupling: attitude offset at the end of deployment "
            + c.js("/coupling_comparison/attitude_offset_at_deployment_end", tag="span",
                   cls=None, scale=DEG, digits=3, unit="rad", suffix="\u00a0deg")
            + " (section 5).")
    items.append(
        f"Integrator <code>{esc(j['integrator'])}</code>: inertial momentum kept to "
        + c.js("/max_h_N_drift", tag="span", cls=None, digits=2)
        + " (relative); simulate and analyze agree (section 7).")
    lis = "".join(f"<li>{i}</li>" for i in items)
    return (f'<div class="summary"><div class="verdict">{verdict}</div><ul>{lis}</ul></div>')


def section_configuration(c, j, h, ctx):
    out = ['<section id="configuration"><h2>1. Configuration</h2>']
    a = h["attrs"]
    model = ctx["model"] or {}
    kind = model.get("kind", "?")
    desc = model.get("description") or ""
    out.append(f"<p>Model <b>{esc(a.get('model_name', '?'))}</b> "
               f"(<code>{esc(a.get('model_source', '?'))}</code>, kind <code>{esc(kind)}</code>)"
               f"{': ' + esc(' '.join(str(desc).split()).rstrip('.')) if desc else ''}. Mode "
               + c.js("/mode", tag="code", cls=None) + ", coupling "
               + c.js("/coupling", tag="code", cls=None) + ".</p>")
    if kind == "hinged":
        hub = model.get("hub", {})
        panels = model.get("panels", [])
        rows = []
        total = 0.0

        def vec(v):
            return ", ".join(fmt_num(float(x), 4) for x in v) if isinstance(v, list) else "\u2014"
        hm = float(hub.get("mass", float("nan")))
        total += hm
        rows.append("<tr><th>hub</th><td class='t'>\u2014</td>"
                    + Cells.src("model_text: hub.mass", hm, fmt_num(hm, 4), unit="kg")
                    + Cells.src("model_text: hub.box", hub.get("box"), vec(hub.get("box")),
                                unit="m")
                    + "<td class='t'>\u2014</td><td class='t'>\u2014</td></tr>")
        for k, p in enumerate(panels):
            m = float(p.get("mass", float("nan")))
            total += m
            rows.append(
                f"<tr><th>{esc(p.get('name', k))}</th>"
                f"<td class='t'>{esc(p.get('parent', 'hub'))}</td>"
                + Cells.src(f"model_text: panels[{k}].mass", m, fmt_num(m, 4), unit="kg")
                + Cells.src(f"model_text: panels[{k}].box", p.get("box"), vec(p.get("box")),
                            unit="m")
                + Cells.src(f"model_text: panels[{k}].hinge_point", p.get("hinge_point"),
                            vec(p.get("hinge_point")), unit="m")
                + Cells.src(f"model_text: panels[{k}].hinge_axis", p.get("hinge_axis"),
                            vec(p.get("hinge_axis")), unit="1")
                + "</tr>")
        rows.append("<tr><th>total</th><td class='t'></td>"
                    + Cells.src("model_text: hub.mass + panels[*].mass", total,
                                "<b>" + fmt_num(total, 4) + "</b>", unit="kg")
                    + "<td></td><td></td><td></td></tr>")
        out.append("<table><caption>Bodies (from the model file; B-frame components)</caption>"
                   "<thead><tr><th>body</th><th>parent</th><th>mass [kg]</th>"
                   "<th>box (deployed) [m]</th><th>hinge point [m]</th><th>hinge axis</th>"
                   "</tr></thead><tbody>" + "".join(rows) + "</tbody></table>")
        confs = model.get("configurations", {}) or {}
        if confs:
            names = [p.get("name", str(k)) for k, p in enumerate(panels)]
            crow = []
            for cn, cv in confs.items():
                angles = (cv or {}).get("hinge_angles_deg", [])
                crow.append(f"<tr><th>{esc(cn)}</th>" + "".join(
                    Cells.src(f"model_text: configurations.{cn}.hinge_angles_deg[{i}]",
                              float(x), fmt_num(float(x), 8), unit="deg")
                    for i, x in enumerate(angles)) + "</tr>")
            out.append("<table class='kv'><caption>Named configurations: hinge angles [deg] "
                       "(0 = deployed)</caption><thead><tr><th>configuration</th>"
                       + "".join(f"<th>{esc(n)}</th>" for n in names) + "</tr></thead><tbody>"
                       + "".join(crow) + "</tbody></table>")
    elif kind == "tensors":
        confs = model.get("configurations", {}) or {}
        crow = []
        for cn, cv in confs.items():
            pm = (cv or {}).get("principal_moments")
            shown = ", ".join(fmt_num(float(x), 4) for x in pm) if pm else "(full tensor)"
            crow.append(f"<tr><th>{esc(cn)}</th>"
                        + Cells.src(f"model_text: configurations.{cn}", pm, shown,
                                    unit="kg m^2", cls="t") + "</tr>")
        out.append("<table class='kv'><caption>Named configurations (inertia, kg m\u00b2, "
                   "body x, y, z)</caption><tbody>" + "".join(crow) + "</tbody></table>")
    # initial state
    import numpy as np
    w0 = h["w_NB_B"][0]
    rate = float(np.linalg.norm(w0))
    H0 = float(np.linalg.norm(h["H_B"][0]))
    out.append("<table class='kv'><caption>Initial state (t = "
               + fmt_num(float(h["time"][0])) + " s, from the trajectory file)</caption><tbody>"
               f"<tr><th>spin axis (principal axis nearest H_B)</th><td class='t'>"
               f"{esc(ctx['axis_name'])}, the {esc(role_text(ctx['axis_role0']))} axis</td></tr>"
               "<tr><th>spin rate |w|</th>"
               + Cells.src("h5: |/w_NB_B[0]|", rate,
                           f"{fmt_num(rate, 4)} rad/s = "
                           f"{fmt_num(rate * 60 / (2 * math.pi), 4)} rpm",
                           unit="rad/s")
               + "</tr><tr><th>w_NB_B(0) [rad/s]</th>"
               + Cells.src("h5: /w_NB_B[0]", [float(x) for x in w0],
                           ", ".join(fmt_num(float(x), 5) for x in w0), unit="rad/s")
               + "</tr><tr><th>|H_B(0)| [kg m\u00b2/s]</th>"
               + Cells.src("h5: |/H_B[0]|", H0, fmt_num(H0, 5), unit="kg m^2/s")
               + "</tr></tbody></table>")
    # principal moments per stage end
    rows = []
    pm0 = [float(x) for x in ctx["moments0"]]
    rows.append("<tr><th>start</th><td class='t'>initial state</td>"
                + Cells.src("h5: /time[0]", float(h["time"][0]), fmt_fixed(float(h["time"][0]), 3),
                            unit="s")
                + "".join(Cells.src(f"h5: /principal_moments[0][{k}]", pm0[k], fmt_num(pm0[k], 6),
                                    unit="kg m^2") for k in range(3))
                + f"<td class='t'>{esc(role_text(ctx['axis_role0']))}</td></tr>")
    for i, s in enumerate(j["stages"]):
        rows.append(
            "<tr>" + c.js(ptr("stages", i, "index"), tag="th", cls=None)
            + c.js(ptr("stages", i, "name"), cls="t")
            + c.js(ptr("stages", i, "t_end"), unit="s", dec=3)
            + "".join(c.js(ptr("stages", i, "principal_moments_end", k), unit="kg m^2", digits=6)
                      for k in range(3))
            + c.js(ptr("stages", i, "spin_axis_end"), cls="t",
                   shown=esc(role_text(s["spin_axis_end"])))
            + "</tr>")
    out.append("<table><caption>Principal moments at each stage end (ascending) and the role "
               "of the spin axis among the principal axes</caption><thead><tr><th>#</th>"
               "<th>stage</th><th>at t [s]</th><th>I<sub>1</sub> [kg m\u00b2]</th>"
               "<th>I<sub>2</sub> [kg m\u00b2]</th><th>I<sub>3</sub> [kg m\u00b2]</th>"
               "<th>spin axis</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table>")
    out.append("<p class='note'>A spin about the intermediate axis (the middle moment) is "
               "unstable: the body flips over periodically (Dzhanibekov effect). About the "
               "minor or major axis the momentum only wobbles.</p></section>")
    return "".join(out)


def section_stability(c, j, h, ctx):
    out = ['<section id="stability"><h2>2. Stability per stage</h2>']
    rows = []
    for i, s in enumerate(j["stages"]):
        p = lambda *k: ptr("stages", i, *k)  # noqa: E731
        rigid = s["rigid"]
        regime = (c.js(p("regime"), cls="t") if rigid else
                  f"<td class='t'>{'(free hinges)' if s['law'] == 'free' else '(deploying)'}</td>")
        seen = c.derived(f"len {p('observed_flips')}", len(s["observed_flips"]),
                         str(len(s["observed_flips"])), tag="span", cls=None)
        if rigid:
            pred = c.derived(f"len {p('predicted_flips')}", len(s["predicted_flips"]),
                             str(len(s["predicted_flips"])), tag="span", cls=None)
            flips = f"<td class='n'>{seen} / {pred}</td>"
        else:
            flips = f"<td class='n'>{seen}</td>"
        hp = s["flip_half_period"]
        rows.append(
            "<tr>" + c.js(p("index"), tag="th", cls=None) + c.js(p("name"), cls="t")
            + c.js(p("law"), cls="t")
            + "<td class='n'>" + c.js(p("t_begin"), tag="span", cls=None, unit="s", dec=3)
            + "\u2013<br>" + c.js(p("t_end"), tag="span", cls=None, unit="s", dec=3) + "</td>"
            + c.js(p("rigid"), cls="t")
            + c.js(p("spin_axis_end"), cls="t") + regime
            + (c.js(p("one_minus_k2"), digits=3) if rigid else "<td class='t'>\u2014</td>")
            + c.js(p("separatrix_distance"), digits=3)
            + (c.js(p("flip_half_period"), unit="s", dec=3) if hp is not None else
               c.js(p("flip_half_period"), shown="\u221e" if rigid else "\u2014"))
            + flips
            + c.js(p("rigid_body_only"), cls="t",
                   shown=(f'<span class="warn">{RIGID_CAVEAT_MARK}</span>'
                          if s["rigid_body_only"] else ""))
            + "</tr>")
    out.append(
        "<table class='stab'><caption>Stability table (one row per stage; a free-hinge profile: "
        "per phase between hinge events)</caption><thead><tr><th>#</th><th>stage</th>"
        "<th>law</th><th>t<sub>0</sub>\u2013t<sub>1</sub> [s]</th><th>const. J</th>"
        "<th>spin axis at t<sub>1</sub></th><th>regime</th><th>1\u2212k\u00b2</th>"
        "<th>sep. dist.</th><th>flip every [s]</th><th>flips seen / pred.</th>"
        f"<th title='verdict holds only for a perfectly rigid body'>{RIGID_CAVEAT_MARK}</th>"
        "</tr></thead><tbody>"
        + "".join(rows) + "</tbody></table>")
    out.append(
        "<p class='note'><b>const. J</b>: J_B constant and no relative momentum over the "
        "stage (a hold), where the closed form applies. <b>regime</b>: the closed-form regime "
        "on constant stages. <b>1\u2212k\u00b2</b>: complementary elliptic parameter (0 on the "
        "separatrix). <b>sep. dist.</b>: (D \u2212 I<sub>2</sub>)/(I<sub>3</sub> \u2212 "
        "I<sub>1</sub>) at the stage end, 0 on the separatrix, &lt; 0 circulating about the "
        "minor axis. <b>flip every</b>: closed-form time between flips (\u221e: no flips). "
        f"<b>flips</b>: located / closed-form (constant stages only). {RIGID_CAVEAT_MARK}: the "
        "verdict holds only for a perfectly rigid body (see the caveats).</p>")
    # caveats
    crow = []
    for i, s in enumerate(j["stages"]):
        crow.append("<tr>" + c.js(ptr("stages", i, "index"), tag="th", cls=None)
                    + c.js(ptr("stages", i, "caveat"), cls="t",
                           shown=(f'<span class="warn">{RIGID_CAVEAT_MARK}</span> '
                                  if s["rigid_body_only"] else "") + esc(s["caveat"] or "\u2014"))
                    + "</tr>")
    out.append("<h3>Caveats: what each verdict assumes</h3>"
               f"<p class='note'>{RIGID_CAVEAT_MARK} marks verdicts that hold only for a "
               "perfectly rigid body: with any energy dissipation (flexible panels, dampers, "
               "fuel slosh) a spin settles about the major axis (the major-axis rule).</p>"
               "<table><thead><tr><th>#</th><th>caveat</th></tr></thead><tbody>"
               + "".join(crow) + "</tbody></table>")
    # danger windows
    if j["danger_windows"]:
        drow = []
        for w in range(len(j["danger_windows"])):
            a, b = j["danger_windows"][w]
            drow.append(f"<tr><th>{w + 1}</th>"
                        + c.js(ptr("danger_windows", w, 0), unit="s", dec=3)
                        + c.js(ptr("danger_windows", w, 1), unit="s", dec=3)
                        + c.derived(f"{ptr('danger_windows', w, 1)} - "
                                    f"{ptr('danger_windows', w, 0)}",
                                    b - a, fmt_fixed(b - a, 3), unit="s") + "</tr>")
        out.append("<h3>Danger windows</h3><p class='note'>Intervals in which the spin axis is "
                   "the intermediate principal axis of J_B(t) (flips possible); first and last "
                   "output time.</p><table class='kv'><thead><tr><th>#</th><th>from [s]</th>"
                   "<th>to [s]</th><th>length [s]</th></tr></thead><tbody>" + "".join(drow)
                   + "</tbody></table>")
    else:
        out.append("<h3>Danger windows</h3><p>None: the spin axis is never the intermediate "
                   "axis.</p>")
    out.append("</section>")
    return "".join(out)


def section_flips(c, j, h, ctx):
    out = ['<section id="flips"><h2>3. Flips: located vs predicted</h2>']
    out.append("<p class='note'>A flip is a sign change of the angular momentum along the "
               "tracked spin axis while that axis is intermediate, located on the dense "
               "output (docs/file_formats.md, Flips). On constant-inertia stages the closed "
               "form predicts a flip every half period; on deploying stages there is no "
               "closed-form prediction.</p>")
    stage_of = {}
    for i, s in enumerate(j["stages"]):
        for k, t in enumerate(s["observed_flips"]):
            stage_of.setdefault(t, (i, k))
    rows = []
    for f, t in enumerate(j["flip_times"]):
        i, k = stage_of.get(t, (None, None))
        cells = f"<tr><th>{f + 1}</th>" + c.js(ptr("flip_times", f), unit="s", dec=6)
        if i is None:
            cells += "<td class='t'>?</td><td></td><td></td>"
        else:
            s = j["stages"][i]
            cells += c.js(ptr("stages", i, "name"), cls="t")
            preds = s["predicted_flips"]
            if preds:
                # the nearest predicted flip
                n = min(range(len(preds)), key=lambda m: abs(preds[m] - t))
                cells += c.js(ptr("stages", i, "predicted_flips", n), unit="s", dec=6)
                d = t - preds[n]
                cells += c.derived(f"{ptr('flip_times', f)} - "
                                   f"{ptr('stages', i, 'predicted_flips', n)}", d,
                                   fmt_num(d, 3), unit="s")
            else:
                cells += ("<td class='t'>(no closed form: deploying)</td>"
                          "<td class='t'>\u2014</td>")
        rows.append(cells + "</tr>")
    # predicted flips that no located flip matched
    seen = set()
    for i, s in enumerate(j["stages"]):
        for f, t in enumerate(j["flip_times"]):
            if s["predicted_flips"] and stage_of.get(t, (None,))[0] == i:
                n = min(range(len(s["predicted_flips"])),
                        key=lambda m: abs(s["predicted_flips"][m] - t))
                seen.add((i, n))
    for i, s in enumerate(j["stages"]):
        for n, t in enumerate(s["predicted_flips"]):
            if (i, n) not in seen:
                rows.append("<tr><th>\u2014</th><td class='t warn'>not located</td>"
                            + c.js(ptr("stages", i, "name"), cls="t")
                            + c.js(ptr("stages", i, "predicted_flips", n), unit="s", dec=6)
                            + "<td class='t'>\u2014</td></tr>")
    if rows:
        out.append("<table><thead><tr><th>#</th><th>located t [s]</th><th>stage</th>"
                   "<th>predicted t [s]</th><th>located \u2212 predicted [s]</th></tr></thead>"
                   "<tbody>" + "".join(rows) + "</tbody></table>")
    else:
        out.append("<p>No flips located, none predicted.</p>")
    srow = []
    for i, s in enumerate(j["stages"]):
        if not s["predicted_flips"] and not s["observed_flips"]:
            continue
        srow.append("<tr>" + c.js(ptr("stages", i, "index"), tag="th", cls=None)
                    + c.js(ptr("stages", i, "name"), cls="t")
                    + c.derived(f"len {ptr('stages', i, 'observed_flips')}",
                                len(s["observed_flips"]), str(len(s["observed_flips"])))
                    + c.derived(f"len {ptr('stages', i, 'predicted_flips')}",
                                len(s["predicted_flips"]), str(len(s["predicted_flips"])))
                    + c.js(ptr("stages", i, "max_flip_time_difference"), unit="s", digits=3)
                    + "</tr>")
    if srow:
        out.append("<table class='kv'><caption>Per stage</caption><thead><tr><th>#</th>"
                   "<th>stage</th><th>located</th><th>predicted</th>"
                   "<th>max |located \u2212 predicted| [s]</th></tr></thead><tbody>"
                   + "".join(srow) + "</tbody></table>")
    out.append("</section>")
    return "".join(out)


def section_timeline(c, j, h, ctx):
    out = ['<section id="timeline"><h2>4. Deployment timeline</h2>']
    if not ctx["is_hinge"]:
        out.append("<p>A stage profile: the panels follow prescribed laws (section 2); there "
                   "are no hinge events (releases, latches, impacts).</p>")
    else:
        ev = j["hinge_events"]
        rows = []
        for e in range(len(ev)):
            p = lambda *k: ptr("hinge_events", e, *k)  # noqa: E731
            rel = ev[e]["kind"] == "release"
            dash = "<td class='t'>\u2014</td>"
            wj = math.sqrt(sum(x * x for x in ev[e]["w_jump_B"]))
            rows.append(
                "<tr>" + c.js(p("t"), unit="s", dec=4) + c.js(p("panel_name"), cls="t")
                + c.js(p("kind"), cls="t")
                + c.js(p("angle"), unit="rad", scale=DEG, dec=3)
                + (dash * 2 if rel else c.js(p("rate_before"), unit="rad/s", scale=DEG, dec=3)
                   + c.js(p("rate_after"), unit="rad/s", scale=DEG, dec=3))
                + (dash * 3 if rel else c.js(p("impulse"), unit="N m s", digits=4)
                   + c.derived(f"norm {p('w_jump_B')}", wj, fmt_num(wj * DEG, 4),
                               unit="rad/s")
                   + c.js(p("energy_dissipated"), unit="J", digits=4))
                + "</tr>")
        total = sum(e["energy_dissipated"] for e in ev)
        rows.append("<tr><th colspan='8' style='text-align:right'>energy dissipated in all "
                    "events [J]</th>"
                    + c.derived("sum /hinge_events/*/energy_dissipated", total,
                                "<b>" + fmt_num(total, 4) + "</b>", unit="J") + "</tr>")
        out.append("<table><caption>Hinge events in time order</caption><thead><tr>"
                   "<th>t [s]</th><th>panel</th><th>event</th><th>angle [deg]</th>"
                   "<th>rate before [deg/s]</th><th>rate after [deg/s]</th>"
                   "<th>impulse [N m s]</th><th>|hub w jump| [deg/s]</th>"
                   "<th>dissipated [J]</th></tr></thead><tbody>" + "".join(rows)
                   + "</tbody></table>")
        out.append("<p class='note'><b>release</b>: a held hinge starts to move. "
                   "<b>latch</b>: the hinge reaches its latch angle and is locked by a plastic "
                   "impulse. <b>jam</b>: locked part-way (failure mode). <b>stop</b>: impact on "
                   "a hard stop, the panel rebounds. <b>rest</b>: the panel comes to rest on a "
                   "stop. <b>|hub w jump|</b>: the shock a latch gives the spacecraft (jump of "
                   "the hub's angular velocity); angles 0 = deployed.</p>")
        lrow = []
        for name, t in j["latch_times"].items():
            how = ""
            for e in ev:
                if e["panel_name"] == name and e["t"] == t and e["kind"] not in ("release", "stop"):
                    how = e["kind"]
            lrow.append(f"<tr><th>{esc(name)}</th>"
                        + (c.js(ptr("latch_times", name), unit="s", dec=4) if t is not None
                           else c.js(ptr("latch_times", name), shown="never", cls="t warn"))
                        + f"<td class='t'>{esc(how)}</td></tr>")
        out.append("<table class='kv'><caption>Panels locked (latch, jam or rest on a stop)"
                   "</caption><thead><tr><th>panel</th><th>t [s]</th><th>how</th></tr></thead>"
                   "<tbody>" + "".join(lrow) + "</tbody></table>")
    cr = j["spin_axis_45_crossings"]
    if cr:
        per_row = 6  # a grid, not one tall column
        rows = []
        for r0 in range(0, len(cr), per_row):
            r1 = min(len(cr), r0 + per_row)
            rows.append(f"<tr><th>{r0 + 1}\u2013{r1}</th>" if r1 > r0 + 1 else
                        f"<tr><th>{r0 + 1}</th>")
            rows[-1] += "".join(c.js(ptr("spin_axis_45_crossings", k), unit="s", dec=3)
                                for k in range(r0, r1)) + "</tr>"
        out.append("<h3>45-degree crossings</h3><p class='note'>Times [s] at which the angle "
                   "between the initial spin axis (fixed in the body) and the inertial "
                   "momentum h_N crosses 45 deg, either way, numbered in time order.</p>"
                   "<table class='kv'><tbody>" + "".join(rows) + "</tbody></table>")
    else:
        out.append("<h3>45-degree crossings</h3><p>The spin axis never comes 45 deg from "
                   "h_N.</p>")
    out.append("</section>")
    return "".join(out)


def section_coupling(c, j, h, ctx):
    out = ['<section id="coupling"><h2>5. Coupling: exact vs quasi-rigid</h2>']
    if ctx["is_hinge"]:
        out.append("<p>Not applicable: this is a free-hinge profile (<code>hinges:</code>). "
                   "Free hinges are always coupled exactly: the hinge rates come out of the "
                   "dynamics and their relative momentum enters the equations; there is no "
                   "quasi-rigid alternative to compare.</p></section>")
        return "".join(out)
    if "coupling_comparison" not in j:
        out.append(f"<p>Not applicable: mode <code>{esc(j['mode'])}</code> has no hinge "
                   "geometry, so the panels carry no relative momentum to neglect (the "
                   "comparison needs a geometry-mode stage profile).</p></section>")
        return "".join(out)
    cc = "/coupling_comparison/"
    cmp = j["coupling_comparison"]
    frac = cmp["max_w_difference_deploying"] / cmp["w_scale"]
    other = ctx["other_coupling"]
    rows = [
        "<tr><th>max |w<sub>exact</sub> \u2212 w<sub>quasi</sub>| while deploying</th>"
        + c.js(cc + "max_w_difference_deploying", unit="rad/s", digits=4, suffix=" rad/s")
        + c.derived(f"{cc}max_w_difference_deploying / {cc}w_scale", frac,
                    fmt_num(frac, 3) + " of max |w|") + "</tr>",
        "<tr><th>attitude offset at the end of deployment (t = "
        + c.js(cc + "deployment_end", tag="span", cls=None, unit="s", digits=4) + " s)</th>"
        + c.js(cc + "attitude_offset_at_deployment_end", unit="rad", digits=4, suffix=" rad")
        + c.js(cc + "attitude_offset_at_deployment_end", unit="rad", scale=DEG, digits=4,
               suffix=" deg") + "</tr>",
        "<tr><th>after deployment: max attitude difference</th>"
        + c.js(cc + "max_attitude_difference_after", unit="rad", digits=4, suffix=" rad")
        + c.js(cc + "max_attitude_difference_after", unit="rad", scale=DEG, digits=4,
               suffix=" deg") + "</tr>",
        "<tr><th>after deployment: max |\u0394H_B| / |H|</th>"
        + c.js(cc + "max_H_B_difference_after", digits=4) + "<td></td></tr>",
    ]
    out.append("<p>With <b>exact</b> coupling the panels' relative momentum h_rel (from the "
               "hinge rates) enters the equations; <b>quasi-rigid</b> coupling takes the body "
               "as instantaneously rigid (h_rel = 0). This run uses "
               + c.js("/coupling", tag="code", cls=None) + " coupling; the comparison runs "
               "both.</p>")
    out.append("<table class='kv'><tbody>" + "".join(rows) + "</tbody></table>")
    if ctx["other"] is not None:
        o = ctx["other"]
        ex_j, qr_j = (j, o) if j["coupling"] == "exact" else (o, j)
        ex_doc, qr_doc = ((None, "other-coupling") if j["coupling"] == "exact"
                          else ("other-coupling", None))
        n = max(len(ex_j["flip_times"]), len(qr_j["flip_times"]))
        frow = []
        for k in range(n):
            r = f"<tr><th>{k + 1}</th>"
            for doc, d in ((ex_doc, ex_j), (qr_doc, qr_j)):
                r += (c.js(ptr("flip_times", k), unit="s", dec=3, doc=doc)
                      if k < len(d["flip_times"]) else "<td class='t'>\u2014</td>")
            if k < len(ex_j["flip_times"]) and k < len(qr_j["flip_times"]):
                dd = qr_j["flip_times"][k] - ex_j["flip_times"][k]
                r += Cells.src("quasi-rigid minus exact flip time", dd, fmt_num(dd, 3),
                               unit="s")
            else:
                r += "<td></td>"
            frow.append(r + "</tr>")
        out.append(f"<h3>Flips under each coupling</h3><p class='note'>The {esc(other)} run is "
                   f"<code>deploysim analyze --json --coupling {esc(other)}</code> with the same "
                   "settings (its cells carry data-doc=\"other-coupling\").</p>"
                   "<table class='kv'><thead><tr><th>#</th><th>exact t [s]</th>"
                   "<th>quasi-rigid t [s]</th><th>difference [s]</th></tr></thead><tbody>"
                   + "".join(frow) + "</tbody></table>")
    out.append("</section>")
    return "".join(out)


def section_plots(c, j, h, ctx):
    out = ['<section id="plots"><h2>6. Plots</h2>']
    n = 0
    for name, caption in TRAJECTORY_FIGURES:
        path = os.path.join(ctx["plot_dir"], name)
        if not os.path.isfile(path):
            continue
        n += 1
        out.append(f'<figure><img src="{png_uri(path)}" alt="{esc(name)}">'
                   f"<figcaption><b>Figure {n}.</b> {esc(caption)} "
                   f"<span class='meta'>({esc(name)}, tools/plot_trajectory.py)</span>"
                   "</figcaption></figure>")
    out.append("<h3>Geometry</h3>")
    if ctx["geometry_note"]:
        out.append(f"<p class='na'>Geometry figures not available: {esc(ctx['geometry_note'])}"
                   "</p>")
    else:
        for name, caption in GEOMETRY_FIGURES:
            path = os.path.join(ctx["geometry_dir"], name)
            if not os.path.isfile(path):
                out.append(f"<p class='na'>{esc(name)} not available: tools/plot_geometry.py "
                           "did not write it.</p>")
                continue
            n += 1
            out.append(f'<figure><img src="{png_uri(path)}" alt="{esc(name)}">'
                       f"<figcaption><b>Figure {n}.</b> {esc(caption)} "
                       f"<span class='meta'>({esc(name)}, tools/plot_geometry.py)</span>"
                       "</figcaption></figure>")
    out.append("</section>")
    return "".join(out)


def section_integrator(c, j, h, ctx):
    a = h["attrs"]
    st = parse_kv(a.get("statistics", ""))
    settings = parse_kv(a.get("integrator_settings", ""))
    out = ['<section id="integrator"><h2>7. Integrator and accuracy</h2>']
    rows = ["<tr><th>method</th>" + c.js("/integrator", cls="t") + "</tr>"]
    for k in ("rtol", "atol", "step", "max_step", "output_dt"):
        if k in settings:
            v = float(settings[k])
            unit = {"step": "s", "max_step": "s", "output_dt": "s"}.get(k, "1")
            rows.append(f"<tr><th>{esc(k)}{' [s]' if unit == 's' else ''}</th>"
                        + Cells.src("h5: @integrator_settings " + k, v,
                                    esc(settings[k]), unit=unit) + "</tr>")
    rows.append("<tr><th>termination</th>" + c.js("/termination", cls="t") + "</tr>")
    rows.append("<tr><th>accepted steps</th>" + c.js("/steps") + "</tr>")
    if "rejected" in st:
        rows.append("<tr><th>rejected steps</th>"
                    + Cells.src("h5: @statistics rejected", int(st["rejected"]), st["rejected"])
                    + "</tr>")
    rows.append("<tr><th>right-hand-side evaluations</th>" + c.js("/rhs_evaluations") + "</tr>")
    rows.append("<tr><th>wall time of the analyze run [s]</th>"
                + c.js("/wall_seconds", unit="s", digits=3) + "</tr>")
    rows.append("<tr><th>wall time of the simulate run (incl. writing HDF5) [s]</th>"
                + Cells.src("measured by tools/report.py", ctx["sim_seconds"],
                            fmt_num(ctx["sim_seconds"], 3), unit="s") + "</tr>")
    out.append("<table class='kv'><caption>Settings and work</caption><tbody>"
               + "".join(rows) + "</tbody></table>")
    # accuracy
    arow = ["<tr><th>max |h_N(t) \u2212 h_N(0)| / |h_N(0)| over the run (inertial momentum, "
            "conserved exactly)</th>" + c.js("/max_h_N_drift", digits=3) + "</tr>"]
    drifts = ctx["energy_drift"]
    for i, s in enumerate(j["stages"]):
        if drifts[i] is None:
            continue
        d, n = drifts[i]
        arow.append("<tr><th>energy drift on stage "
                    + c.js(ptr("stages", i, "index"), tag="span", cls=None) + " \u201c"
                    + esc(s["name"]) + "\u201d ("
                    + c.js(ptr("stages", i, "t_begin"), tag="span", cls=None, dec=2) + "\u2013"
                    + c.js(ptr("stages", i, "t_end"), tag="span", cls=None, dec=2)
                    + f" s, {n} samples): max |E \u2212 E<sub>first</sub>| / E</th>"
                    + Cells.src(f"h5: /energy over /time in (t_begin, t_end) of stage {i}", d,
                                fmt_num(d, 3)) + "</tr>")
    wi = max(range(len(j["stages"])), key=lambda i: j["stages"][i]["max_flip_time_difference"])
    arow.append("<tr><th>max |located \u2212 closed-form flip time| [s]</th>"
                + c.js(ptr("stages", wi, "max_flip_time_difference"), unit="s", digits=3) + "</tr>")
    out.append("<table class='kv'><caption>Accuracy evidence</caption><tbody>" + "".join(arow)
               + "</tbody></table>")
    out.append("<p class='note'>Rigid (constant-inertia) stages conserve the kinetic energy "
               "exactly; its drift there, like the drift of the inertial momentum h_N over the "
               "whole run, measures the integration error. The closed-form flip times are an "
               "independent analytic oracle for the located ones.</p>")
    out.append("<h3>Consistency of the two runs</h3><p class='ok'>\u2714 "
               "<code>deploysim simulate</code> (the HDF5 file) and <code>deploysim analyze "
               "--json</code> agree exactly: flip times, predicted flip times, stage bounds, "
               "moments and spin-axis roles, danger windows, hinge events, latch times, "
               "45-degree crossings, h_N drift, steps and right-hand-side evaluations.</p>")
    out.append("</section>")
    return "".join(out)


def section_inputs(c, j, h, ctx):
    a = h["attrs"]
    out = ['<section id="inputs" class="inputs"><h2>8. Inputs and provenance</h2>']
    # (label, where it comes from, its value, how it is shown)
    rows = [
        ("deploysim version", "h5: @deploysim_version", a.get("deploysim_version", "?"),
         esc(a.get("deploysim_version", "?"))
         + (f" <span class='meta'>({esc(ctx['build_id'])})</span>" if ctx["build_id"] else "")),
        ("HDF5 schema version", "h5: @schema_version", a.get("schema_version", "?"),
         esc(a.get("schema_version", "?"))),
        ("report generated", "clock of tools/report.py (UTC)", ctx["generated"],
         esc(ctx["generated"])),
        ("profile", "h5: @profile_source", a.get("profile_source", "?"),
         f"<code>{esc(a.get('profile_source', '?'))}</code> "
         f"(name {esc(a.get('profile_name', '?'))})"),
        ("model", "h5: @model_source", a.get("model_source", "?"),
         f"<code>{esc(a.get('model_source', '?'))}</code> "
         f"(name {esc(a.get('model_name', '?'))})"),
        ("mode, coupling", "h5: @mode, @coupling",
         a.get("mode", "?") + ", " + a.get("coupling", "?"),
         esc(a.get("mode", "?")) + ", " + esc(a.get("coupling", "?"))),
        ("integrator", "h5: @integrator, @integrator_settings",
         a.get("integrator", "?") + ": " + a.get("integrator_settings", "?"),
         f"{esc(a.get('integrator', '?'))}: "
         f"<code>{esc(a.get('integrator_settings', '?'))}</code>"),
    ]
    cmds = "".join(f"<li><code>{esc(cmd)}</code></li>" for cmd in ctx["commands"])
    out.append("<table class='kv'><tbody>" + "".join(
        f"<tr><th>{k}</th>" + Cells.src(where, value, shown, cls="t") + "</tr>"
        for k, where, value, shown in rows) + "</tbody></table>")
    out.append(f"<p>Commands run for this report:</p><ul class='note'>{cmds}</ul>")
    out.append("<p class='note'>To reproduce the run from the texts below: save the profile, "
               "save the model at the path its <code>model:</code> key names, and run "
               "<code>deploysim simulate</code> with the settings above (the trajectory is the "
               "same bit for bit; docs/file_formats.md).</p>")
    out.append(f"<h3>Profile ({esc(a.get('profile_source', ''))})</h3>"
               f"<pre>{esc(a.get('profile_text', ''))}</pre>")
    out.append(f"<h3>Model ({esc(a.get('model_source', ''))})</h3>"
               f"<pre>{esc(a.get('model_text', ''))}</pre>")
    out.append("<h3>Reading the numbers by machine</h3><p class='note'>Every number of the "
               "analysis carries <code>data-json</code> (a JSON pointer into the output of "
               "<code>deploysim analyze --json</code> with the settings above) and "
               "<code>data-value</code> (its full-precision value, SI units even where the "
               "cell shows degrees); numbers computed from it carry <code>data-derived</code>, "
               "numbers from the trajectory file or the model carry <code>data-src</code>.</p>")
    out.append("</section>")
    return "".join(out)


def build_html(j, h, ctx):
    c = Cells(j, ctx["other"])
    a = h["attrs"]
    profile = ctx["profile_doc"] or {}
    desc = profile.get("description") or ""
    title = f"Mission report: {a.get('profile_name', j['profile'])}"
    toc = ("<ol class='toc'><li><a href='#configuration'>Configuration</a></li>"
           "<li><a href='#stability'>Stability per stage</a></li>"
           "<li><a href='#flips'>Flips: located vs predicted</a></li>"
           "<li><a href='#timeline'>Deployment timeline</a></li>"
           "<li><a href='#coupling'>Coupling</a></li><li><a href='#plots'>Plots</a></li>"
           "<li><a href='#integrator'>Integrator and accuracy</a></li>"
           "<li><a href='#inputs'>Inputs and provenance</a></li></ol>")
    body = [
        f"<h1>{esc(title)}</h1>",
        f"<div class='subtitle'>{esc(' '.join(str(desc).split()))}</div>" if desc else "",
        f"<div class='meta'>deploysim {esc(a.get('deploysim_version', '?'))} \u00b7 profile "
        f"<code>{esc(a.get('profile_source', ''))}</code> \u00b7 model "
        f"<code>{esc(a.get('model_source', ''))}</code> \u00b7 integrator "
        f"{esc(j['integrator'])} \u00b7 generated {esc(ctx['generated'])}</div>",
        section_summary(c, j, h, ctx),
        toc,
        section_configuration(c, j, h, ctx),
        section_stability(c, j, h, ctx),
        section_flips(c, j, h, ctx),
        section_timeline(c, j, h, ctx),
        section_coupling(c, j, h, ctx),
        section_plots(c, j, h, ctx),
        section_integrator(c, j, h, ctx),
        section_inputs(c, j, h, ctx),
    ]
    return ("<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
            "<meta name='viewport' content='width=device-width, initial-scale=1'>"
            f"<meta name='generator' content='deploysim tools/report.py'>"
            f"<title>{esc(title)}</title><style>{CSS}</style></head>\n<body>\n"
            + "\n".join(body) + "\n</body></html>\n")


# --- main ------------------------------------------------------------------------------

class OneLineParser(argparse.ArgumentParser):
    """Command-line errors on one line, as deploysim's."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"{PROG}: error: {message} (see report.py --help)\n")


def number(s):
    float(s)  # argparse turns the ValueError into a one-line usage error
    return s


def parse_args(argv):
    ap = OneLineParser(
        prog=os.environ.get("DEPLOYSIM_PROG") or "report.py",
        description="Write a self-contained HTML mission report of a deployment profile "
                    "(verdict, stability table, flips vs prediction, deployment timeline, "
                    "coupling comparison, plots, integrator accuracy, inputs).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n"
               "  deploysim report deployment_profiles/smallsat_spring_deploy.yaml -o spring.html\n"
               "  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_spring_deploy.yaml"
               " \\\n      -o spring_report.html --deploysim build/release/bin/deploysim\n"
               "  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_three_stage.yaml"
               " \\\n      -o three_stage.html --method rkmk-rkf78 --rtol 1e-12 --dt 0.05\n\n"
               "Exit codes: 0 written; 1 bad input (deploysim's message passed through); 2 bad "
               "command line;\n3 integration stopped early; 4 simulate and analyze disagree; "
               "5 a plot tool or the output failed.\nOn an error no file is written.")
    ap.add_argument("profile", help="deployment profile (YAML)")
    ap.add_argument("-o", "--output", required=True, help="the report to write (HTML)")
    ap.add_argument("--deploysim", help="the deploysim executable (default: $DEPLOYSIM_BIN, then "
                    "deploysim on PATH)")
    ap.add_argument("--method", help="integrator (deploysim methods)")
    # Numbers are passed to deploysim as written (it checks their ranges).
    ap.add_argument("--rtol", type=number, help="relative tolerance")
    ap.add_argument("--atol", type=number, help="absolute tolerance, relative to |H_B(0)|")
    ap.add_argument("--step", type=number, help="fixed step [s] (initial step if adaptive)")
    ap.add_argument("--dt", type=number, help="output sampling interval [s]")
    ap.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    return ap.parse_args(argv)


def generated_stamp():
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch and epoch.isdigit():
        t = datetime.datetime.fromtimestamp(int(epoch), datetime.timezone.utc)
    else:
        t = datetime.datetime.now(datetime.timezone.utc)
    return t.strftime("%Y-%m-%d %H:%M UTC")


def make_report(args):
    t_start = time.monotonic()
    exe = find_deploysim(args.deploysim)
    profile = args.profile
    out = args.output
    if not os.path.isfile(profile):
        # deploysim names the file in its own words
        pass
    inputs = [profile, exe]
    mp = model_path_of(profile)
    if mp:
        inputs.append(mp)
    for inp in inputs:
        if same_file(out, inp):
            raise ReportError(f"-o {out}: is an input ({inp}); refusing to overwrite it",
                              EXIT_BAD_INPUT)
    if os.path.isdir(out):
        raise ReportError(f"-o {out}: is a folder", EXIT_BAD_INPUT)
    out_dir = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(out_dir):
        raise ReportError(f"-o {out}: folder {out_dir} does not exist", EXIT_BAD_INPUT)
    ov = overrides(args)
    commands = []

    # The first run also validates the input: its progress line comes after it, so that
    # bad input gives deploysim's one line and nothing else.
    cmd = [exe, "analyze", profile, "--json", *ov]
    commands.append(" ".join(["deploysim"] + cmd[1:]))
    js_text, secs = run(cmd, "analyze")
    try:
        j = json.loads(js_text)
    except ValueError as e:
        raise ReportError(f"deploysim analyze --json: not JSON ({e})", EXIT_TOOL)
    progress(args, f"analyzed {profile} (deploysim analyze --json, {secs:.1f} s): "
                   f"{len(j['stages'])} stage(s), {len(j['flip_times'])} flip(s)")

    with tempfile.TemporaryDirectory(prefix="deploysim-report-") as work:
        h5 = os.path.join(work, "trajectory.h5")
        progress(args, "simulating (deploysim simulate)")
        cmd = [exe, "simulate", profile, "-o", h5, *ov]
        compare = "coupling_comparison" in j
        if compare:
            cmd.append("--compare-coupling")
        else:
            cmd.append("-q")
        commands.append(" ".join(["deploysim"] + cmd[1:]).replace(h5, "TRAJECTORY.h5"))
        sim_out, sim_seconds = run(cmd, "simulate")
        h = read_h5(h5)
        check_agreement(j, h)
        ctx = {"commands": commands, "sim_seconds": sim_seconds, "other": None,
               "other_coupling": None, "generated": generated_stamp(), "build_id": ""}
        try:
            v = subprocess.run([exe, "--version"], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True, timeout=30)
            ctx["build_id"] = v.stdout.strip()
        except (OSError, subprocess.SubprocessError):
            pass
        if compare:
            other = "quasi-rigid" if j["coupling"] == "exact" else "exact"
            ctx["other_coupling"] = other
            progress(args, f"analyzing with {other} coupling")
            cmd = [exe, "analyze", profile, "--json", *ov, "--coupling", other]
            commands.append(" ".join(["deploysim"] + cmd[1:]))
            o_text, _ = run(cmd, "analyze")
            ctx["other"] = json.loads(o_text)
            # simulate --compare-coupling prints "flips: exact N, quasi-rigid M"
            m = re.search(r"flips: exact (\d+), quasi-rigid (\d+)", sim_out)
            if m:
                n_other = int(m.group(2) if other == "quasi-rigid" else m.group(1))
                if n_other != len(ctx["other"]["flip_times"]):
                    raise ReportError(
                        f"simulate --compare-coupling counts {n_other} {other} flips, "
                        f"analyze --coupling {other} {len(ctx['other']['flip_times'])}",
                        EXIT_DISAGREE)
        import yaml
        try:
            ctx["model"] = yaml.safe_load(h["attrs"].get("model_text", "")) or {}
        except yaml.YAMLError:
            ctx["model"] = {}
        try:
            ctx["profile_doc"] = yaml.safe_load(h["attrs"].get("profile_text", "")) or {}
        except yaml.YAMLError:
            ctx["profile_doc"] = {}
        ctx["is_hinge"] = isinstance(ctx["profile_doc"], dict) and "hinges" in ctx["profile_doc"]
        ctx["axis_name"], ctx["axis_role0"], ctx["moments0"] = initial_spin_axis(h)
        ctx["energy_drift"] = rigid_energy_drift(j, h)

        progress(args, "plotting (tools/plot_trajectory.py)")
        ctx["plot_dir"] = os.path.join(work, "plots")
        run([sys.executable, os.path.join(TOOLS, "plot_trajectory.py"), h5, "-o",
             ctx["plot_dir"]], "plot_trajectory.py")
        geo = os.path.join(TOOLS, "plot_geometry.py")
        ctx["geometry_dir"] = os.path.join(work, "geometry")
        ctx["geometry_note"] = ""
        if os.path.isfile(geo):
            progress(args, "plotting (tools/plot_geometry.py)")
            try:
                run([sys.executable, geo, h5, "-o", ctx["geometry_dir"]], "plot_geometry.py")
            except ReportError as e:
                # e.g. two equal principal moments in the last stage: no separatrix to draw.
                # The rest of the report stands; the note says why the figures are missing.
                why = str(e).replace(h5, "the trajectory")
                ctx["geometry_note"] = f"tools/plot_geometry.py could not draw them ({why})"
                progress(args, f"no geometry figures: {e}")
        else:
            ctx["geometry_note"] = ("tools/plot_geometry.py is not installed next to "
                                    "tools/report.py.")
        page = build_html(j, h, ctx)

    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=".tmp",
                               dir=out_dir)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(page)
        os.chmod(tmp, 0o644)
        os.replace(tmp, out)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise ReportError(f"{out}: cannot write: {e.strerror}", EXIT_TOOL)
    progress(args, f"wrote {out} ({len(page.encode()) / 1024:.0f} kB) in "
                   f"{time.monotonic() - t_start:.1f} s")


def main(argv):
    args = parse_args(argv)
    try:
        make_report(args)
    except ReportError as e:
        print(str(e) if e.raw else f"{PROG}: error: {e}", file=sys.stderr)
        return e.code
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
