#!/usr/bin/python3
"""Writes a mission report of a deployment profile: one self-contained HTML file.

Usage:
  /usr/bin/python3 tools/report.py PROFILE.yaml -o REPORT.html [--deploysim BIN]
                                   [--method M] [--rtol R] [--atol A] [--step S] [--dt D]

What it runs (all with the same settings, the overrides passed to each):
  BIN simulate PROFILE -o T.h5      the run: every number of the report is read from its
                                    trajectory file (tools/deploysim_results.py), the
                                    plots are drawn from it
  BIN analyze PROFILE --json --coupling OTHER   stage profiles in geometry mode only: the
                                    comparison with the other coupling (exact /
                                    quasi-rigid; deploysim runs both and compares them)
                                    and the other coupling's flips
  tools/plot_trajectory.py T.h5     the time plots; tools/plot_geometry.py T.h5 (the
                                    inertia ellipsoid and the spacecraft), if present

The report (no network, no scripts, images as data: URIs, A4 print style): a summary with
the verdict in one sentence, the configuration (model, principal moments and the spin
axis' role per stage end), the stability table with the danger windows and the
rigid-body caveats, the flips against the closed-form prediction, for free-hinge profiles
the deployment timeline (releases, latches, impulses, shocks, energy dissipated), the
coupling comparison, the plots, the integrator and its accuracy evidence, and the full
text of the inputs with the deploysim version.

Provenance: every number read from the trajectory file carries data-h5="<pointer>" and
data-value="<full precision>". A pointer is a dataset and a row, `/stages/t_end#2`
(row 2), `/stages/moments_end#2,0` (row 2, column 0), `/w_NB_B#0` (a whole row), or a
root attribute, `@max_h_N_drift` (a number where the attribute holds one), `@statistics#steps`
(the field steps= of a "k=v, k=v" attribute). Numbers computed from the file carry
data-derived="<expr>" (`/a#i - /b#j`, `len /a`, `sum /a`, `norm /a#i`); the comparison with
the other coupling carries data-json="/json/pointer" into that run's `analyze --json` with
data-doc="other-coupling" (data-derived too, with `/a / /b` on JSON pointers); numbers from
the model text, the report's own clock and the wall time it measures around `deploysim
simulate` (the file holds no wall time) carry data-src="<where>". data-value is in SI
units (rad, rad/s) even where the cell shows degrees.

Exit codes: 0 written; 1 bad input or command line (deploysim's one-line message passed
through, or -o naming an input, a missing deploysim); 3 the integration did not
reach its end time; 5 a plot tool, the trajectory file or the output failed (4 is not
used: it was two runs of one mission disagreeing, when the report ran it twice). On any
error nothing is written (the report goes to a temporary file in the target folder,
renamed at the end) and one line goes to stderr.

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
import shutil
import subprocess
import sys
import tempfile
import time

from deploysim_results import TrajectoryError, read_trajectory
from deploysim_scene import bending_owners, phase_label

TOOLS = os.path.dirname(os.path.abspath(__file__))
PROG = "report"

EXIT_BAD_INPUT = 1
EXIT_USAGE = 1  # bad usage is bad input, as for every deploysim command
EXIT_INTEGRATION = 3
EXIT_TOOL = 5

# data-doc of the cells that point into the other coupling's analyze --json.
OTHER = "other-coupling"

DEG = 180.0 / math.pi
RIGID_CAVEAT_MARK = "\u26a0"  # warning sign: the verdict holds only for a rigid body

# The figures of tools/plot_trajectory.py and tools/plot_geometry.py, in report order,
# with their captions.
TRAJECTORY_FIGURES = [
    ("spin_axis.png", "Angle between the initial body spin axis and the inertial angular "
     "momentum h_N. A flip is the axis turning over (through 90 deg); located flips and "
     "45-degree crossings are marked. Hinge events are numbered above the plot, the same "
     "numbers on every time plot, and listed in the key under it."),
    ("momentum.png", "Body-frame angular momentum H_B: its components exchange sign at "
     "each flip while |H_B| stays constant."),
    ("inertia.png", "Principal moments of J_B(t); stages shaded. The spin axis is in "
     "danger while its moment lies between the other two."),
    ("hinge_angles.png", "Hinge angles and rates per panel, with the hinge events "
     "(releases, latches, stops) marked."),
    ("angular_velocity.png", "Body angular velocity w_NB_B [deg/s]."),
    ("energy.png", "Kinetic energy (and, for free hinges, spring and total energy with the "
     "losses at hinge events)."),
    ("polhode.png", "Polhode: H_B/|H_B| on the momentum sphere and its projections, a "
     "colour per stage (a dot at each stage's start), with the separatrix of the final "
     "inertia; below, each stage on its own, zoomed and seen along the body axis nearest "
     "its mean momentum, against the separatrix of its own inertia."),
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


# --- analysis of the trajectory ----------------------------------------------------------

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
    return name, role


def rigid_energy_drift(h, stages):
    """Per rigid stage: max |E(t) - E(t1)| / E(t1) over the output samples strictly inside
    the stage (t1 the first of them); None with fewer than two samples."""
    import numpy as np
    t, E = h["time"], h["energy"]
    out = []
    for s in stages:
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


def hp(path, *index):
    """A pointer into the trajectory file: /path#i or /path#i,k (module docstring)."""
    return "/" + path + ("#" + ",".join(str(i) for i in index) if index else "")


def h5_value(h, pointer):
    """The value at a data-h5 pointer: a Python number, str or list of numbers."""
    if pointer.startswith("@"):
        name, _, key = pointer[1:].partition("#")
        if key and h.attr(name).startswith("{"):  # a JSON record: @outcome#linear.verdict
            v = json.loads(h.attr(name))
            for k in key.split("."):
                v = v[int(k)] if isinstance(v, list) else v[k]
            return v
        v = h.attr_fields(name)[key] if key else h.attr(name)
        for kind in (int, float):
            try:
                return kind(v)
            except ValueError:
                pass
        return v
    path, _, index = pointer.partition("#")
    v = h[path]
    for i in index.split(",") if index else []:
        v = v[int(i)]
    if hasattr(v, "tolist"):
        return v.tolist()
    return v


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


def shown_value(v, scale=1.0, digits=4, dec=None):
    """How a cell shows the value v (times scale)."""
    if isinstance(v, str):
        return esc(v)
    if isinstance(v, bool):
        return "yes" if v else "no"
    if v is None:
        return "\u2014"
    if dec is not None:
        return fmt_fixed(v * scale, dec)
    return fmt_num(v * scale if isinstance(v, float) or scale != 1.0 else v, digits)


class Cells:
    """Makes the machine-readable number cells: from the trajectory file (h5), from the
    other coupling's analyze --json (js), computed (derived) or from elsewhere (src)."""

    def __init__(self, h, other=None):
        self.h = h
        self.other = other

    @staticmethod
    def _element(tag, cls, attrs, shown, suffix=""):
        c = f' class="{cls}"' if cls and tag == "td" else ""
        return f"<{tag}{c}{attrs}>{shown}{suffix}</{tag}>"

    @staticmethod
    def _attrs(source, where, value, unit=None, doc=None):
        a = f' {source}="{esc(where)}" data-value="{esc(value_attr(value))}"'
        if doc:
            a += f' data-doc="{esc(doc)}"'
        if unit:
            a += f' data-unit="{esc(unit)}"'
        return a

    def h5(self, pointer, shown=None, unit=None, tag="td", scale=1.0, digits=4, dec=None,
           suffix="", cls="n"):
        """An element showing the trajectory file's value at pointer (times scale), unit
        for data-unit."""
        v = h5_value(self.h, pointer)
        shown = shown_value(v, scale, digits, dec) if shown is None else shown
        return self._element(tag, cls, self._attrs("data-h5", pointer, v, unit), shown, suffix)

    def js(self, pointer, shown=None, unit=None, tag="td", scale=1.0, digits=4, dec=None,
           suffix="", cls="n"):
        """An element showing the other coupling's analyze --json value at pointer."""
        v = get_ptr(self.other, pointer)
        shown = shown_value(v, scale, digits, dec) if shown is None else shown
        return self._element(tag, cls, self._attrs("data-json", pointer, v, unit, OTHER),
                             shown, suffix)

    def derived(self, expr, value, shown, tag="td", unit=None, cls="n", doc=None):
        return self._element(tag, cls, self._attrs("data-derived", expr, value, unit, doc),
                             shown)

    @staticmethod
    def src(where, value, shown, tag="td", unit=None, cls="n"):
        return Cells._element(tag, cls, Cells._attrs("data-src", where, value, unit), shown)


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
@media print {
  /* Compact on paper: no section starts a page of its own (a heading stays with what
     follows it), tables break between rows (the header row repeats), a figure stays with
     its caption and is at most about 40 % of a page high, so that the next one fits
     beside it instead of leaving the rest of the page blank; the input texts in two
     columns. */
  body { max-width: none; padding: 0; }
  .summary { background: none; }
  thead { display: table-header-group; }
  h2, h3, section { break-before: auto; page-break-before: auto; }
  table { break-inside: auto; page-break-inside: auto; }
  figure { margin: 4pt 0 8pt; }
  figure img { max-height: 100mm; width: auto; }
  pre { columns: 2; column-gap: 5mm; column-rule: 1px solid #ddd; font-size: 6.6pt; }
  a { color: inherit; text-decoration: none; }
}
"""


# --- the sections -----------------------------------------------------------------------

def regime_text(regime):
    """The closed-form regime (/stages/regime) as the stability table shows it: the axis
    the polhode circulates about ('minor-axis': 'minor'), 'separatrix' as it is."""
    return regime[:-len("-axis")] if regime.endswith("-axis") else regime


def role_text(role):
    return {"minor": "minor", "intermediate": "intermediate (unstable)",
            "major": "major", "degenerate": "degenerate (two moments equal)"}.get(role, role)


def verdict(c, h, ctx):
    """The summary's one sentence: the run's outcome record (its headline: faults first,
    then what the motion did); for a file written before it, when the spin axis becomes
    intermediate and the flips."""
    if h.outcome:
        return c.h5("@outcome#headline", tag="span", cls=None, shown=esc(h.outcome["headline"]))
    stages = ctx["stages"]
    last = len(stages) - 1
    parts = []
    axis = ctx["axis_name"]
    t_end = float(stages[last]["t_end"])
    span_end = c.h5(hp("stages/t_end", last), tag="span", cls=None, digits=4, unit="s",
                    shown=fmt_num(int(t_end)) if t_end.is_integer() else None,
                    suffix="\u00a0s")
    dws = h.danger_windows
    if dws:
        first = c.h5(hp("danger_windows/t_begin", 0), tag="span", cls=None, dec=1, unit="s",
                     suffix="\u00a0s")
        if dws[0][0] <= stages[0]["t_begin"]:
            s = f"spin about {axis}, the intermediate axis from the start"
        else:
            s = f"spin about {axis} becomes the intermediate axis at {first}"
        # the final configuration: the last stage if rigid, intermediate, starting later
        ls = stages[last]
        if ls["rigid"] and ls["spin_axis_role"] == "intermediate" and ls["t_begin"] > dws[0][0]:
            s += (" (final configuration from "
                  + c.h5(hp("stages/t_begin", last), tag="span", cls=None, dec=1, unit="s",
                         suffix="\u00a0s") + ")")
        if len(dws) > 1:
            n = c.derived("len /danger_windows/t_begin", len(dws), str(len(dws)), tag="span",
                          cls=None)
            s += f" ({n} danger windows)"
        parts.append(s)
    else:
        role = stages[last]["spin_axis_role"]
        shown = {"degenerate": "an axis of two equal moments"}.get(role, f"the {role} axis")
        parts.append(f"spin about {axis} never becomes the intermediate axis (it ends as "
                     + c.h5(hp("stages/spin_axis_role", last), tag="span", cls=None,
                            shown=esc(shown)) + ")")
    nf = len(h.flip_time)
    if nf:
        parts.append("first flip at " + c.h5(hp("events/flip_time", 0), tag="span", cls=None,
                                              dec=1, unit="s", suffix="\u00a0s"))
        parts.append(c.derived("len /events/flip_time", nf, str(nf), tag="span", cls=None)
                     + (" flip" if nf == 1 else " flips") + " in " + span_end)
    else:
        s = "no flips in " + span_end
        if len(h.spin_axis_45_time):
            # no flip, but the spin is not kept either (an energy sink, a flat spin)
            s += (", but the spin axis is 45\u00b0 away from the angular momentum at "
                  + c.h5(hp("events/spin_axis_45_time", 0), tag="span", cls=None, dec=1,
                         unit="s", suffix="\u00a0s"))
        parts.append(s)
    v = "; ".join(parts) + "."
    return v[0].upper() + v[1:]


def outcome_item(c, o):
    """The summary's line on the prediction for the final phase's steady spin: its linear
    stability from the run's own equations."""
    lin = o["linear"]
    if not lin["found"]:
        return ("Linear stability of the final spin: none ("
                + c.h5("@outcome#linear.reason", tag="span", cls=None) + ").")
    s = ("Linear stability of the final spin (from the run's own equations): "
         + c.h5("@outcome#linear.verdict", tag="span", cls=None))
    if lin["growth_rate"]:
        s += (", nutation " + ("growing" if lin["growth_rate"] > 0 else "decaying")
              + " with time constant "
              + c.h5("@outcome#linear.time_constant", tag="span", cls=None, unit="s",
                     suffix="\u00a0s"))
    s += "."  # (where the rigid-body rule disagrees, the headline above says why)
    return s


def deployment_item(c, h, ctx):
    """The summary's line on the hinge events: their count, the energy, the locks."""
    ev = ctx["events"]
    ne = len(ev)
    total = sum(e["energy_dissipated"] for e in ev)
    bending = bending_hinges(h)  # free springs: they never lock
    latch = {k: v for k, v in h.latch_times.items() if k not in bending}
    latched = {k: v for k, v in latch.items() if math.isfinite(v)}
    if not latched:
        locked = "no panel locks"
    else:
        last = max(latched, key=lambda k: latched[k])
        locked = (("all panels" if len(latched) == len(latch) else
                   f"{len(latched)} of {len(latch)} panels")
                  + " locked, the last at "
                  + c.h5(hp("hinge_latch_time", h.panel_names.index(last)), tag="span",
                         cls=None, dec=2, unit="s", suffix="\u00a0s"))
    hidden = ne - len(listed_events(h, ev))
    return ("Deployment: "
            + c.derived("len /events/hinge/time", ne, str(ne), tag="span", cls=None)
            + (" hinge event" if ne == 1 else " hinge events")
            + (f" ({hidden} of them the appendages' generated hinges, free from the start), "
               if hidden else ", ")
            + c.derived("sum /events/hinge/energy_dissipated", total,
                        fmt_num(total, 3) + "\u00a0J", tag="span", cls=None, unit="J")
            + (" dissipated in it; " if ne == 1 else " dissipated in them; ")
            + locked + " (section 4).")


def section_summary(c, h, ctx):
    stages = ctx["stages"]
    last = len(stages) - 1
    items = []
    # agreement with the closed form
    worst_i = max(range(len(stages)), key=lambda i: stages[i]["max_flip_time_difference"])
    if len(h.predicted_flip_time):
        items.append(
            "Located flips on the constant-inertia stages agree with the closed-form "
            "prediction to "
            + c.h5(hp("stages/max_flip_time_difference", worst_i), tag="span", cls=None,
                   unit="s", digits=2, suffix="\u00a0s") + " (section 3).")
    fs = stages[last]
    # Legal inputs that are almost certainly not meant: first, so that no reader misses them.
    for w in h.warnings:
        items.append("Input warning: " + c.h5("@warnings", shown=esc(w), tag="span", cls="warn"))
    if h.outcome:
        items.append(outcome_item(c, h.outcome))
    items.append(f"Final stage \u201c{stage_label(h, last)}\u201d: spin axis "
                 + c.h5(hp("stages/spin_axis_role", last), tag="span", cls=None)
                 + ("; the rigid-body rule (a prediction; the verdict above is the motion's): "
                    if h.outcome else "; ")
                 + esc(fs["caveat"] or "no caveat") + "."
                 + (f' <span class="warn">{RIGID_CAVEAT_MARK} Only a perfectly rigid body would '
                    'keep this spin.</span>' if fs["rigid_body_only"] and not h.outcome else ""))
    if ctx["events"]:
        items.append(deployment_item(c, h, ctx))
    if ctx["comparison"]:
        items.append(
            "Quasi-rigid vs exact coupling: attitude offset at the end of deployment "
            + c.js("/coupling_comparison/attitude_offset_at_deployment_end", tag="span",
                   cls=None, scale=DEG, digits=3, unit="rad", suffix="\u00a0deg")
            + " (section 5).")
    items.append(
        f"Integrator <code>{esc(h.attr('integrator'))}</code>: inertial momentum kept to "
        + c.h5("@max_h_N_drift", tag="span", cls=None, digits=2)
        + " (relative; section 7).")
    lis = "".join(f"<li>{i}</li>" for i in items)
    return (f'<div class="summary"><div class="verdict">{verdict(c, h, ctx)}</div>'
            f"<ul>{lis}</ul></div>")


def model_tables(model):
    """The model's bodies (hinged) or named configurations (tensors), from its text."""
    out = []
    kind = model.get("kind", "?")
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
            names = [p.get("name", str(k)) for k, p in enumerate(panels)] + [
                str(a.get("name", "?")) for a in model.get("appendages", []) or []]
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
    return out


DASH = "\u2014"


def stage_label(h, i):
    """Stage i's name as the text shows it: an appendage's bending hinges named once, by
    the appendage and their count (deploysim_scene.phase_label, as the CLI's text)."""
    return esc(phase_label(h["stages/name"][i], h.panel_names, h.appendages))


def bending_hinges(h):
    """The panel names of the appendages' generated bending hinges (the file's @body)."""
    return {h.panel_names[k] for k in bending_owners(h.appendages)}


def listed_events(h, ev):
    """(index, event) of the hinge events the timeline lists: all but the releases of the
    appendages' bending hinges at the run's start (free from the start by construction;
    the note above the table counts them, the file keeps them)."""
    bending, t0 = bending_hinges(h), float(h.time[0])
    return [(e, x) for e, x in enumerate(ev)
            if not (x["panel_name"] in bending and x["kind"] == "release" and x["time"] <= t0)]


def appendage_row(c, i, a, p):
    """Appendage i's row for bending plane p (a slosh pendulum: its hinges, p = 0)."""
    at = f"@body#appendages.{i}."
    cells = (f"<th>{esc(a['name'])}</th>" + c.h5(at + "kind", cls="t")
             + c.h5(at + "segments")
             + (c.src(f"{at}planes: plane {p + 1} of them", p + 1, str(p + 1))
                if a["planes"] else f"<td class='t'>{DASH}</td>"))
    if a["planes"]:
        for n in (0, 1):
            chain, beam = a["chain_frequencies"][p][n], a["beam_frequencies"][p][n]
            cells += (c.h5(f"{at}chain_frequencies.{p}.{n}", unit="rad/s", digits=4)
                      + c.h5(f"{at}beam_frequencies.{p}.{n}", unit="rad/s", digits=4)
                      + c.derived(f"{at}chain_frequencies.{p}.{n} / "
                                  f"{at}beam_frequencies.{p}.{n}", chain / beam,
                                  fmt_num(100 * (chain / beam - 1), 2) + "\u00a0%", unit="1"))
        cells += c.h5(f"{at}damping_ratio.{p}", unit="1", digits=3)
    else:
        cells += f"<td class='t'>{DASH}</td>" * 7
    return "<tr>" + cells + c.h5(f"{at}damping.{p}", unit="N m s/rad", digits=4) + "</tr>"


def appendage_table(c, h):
    """The flexible appendages the run simulated (the file's @body): per appendage and
    bending plane the clamped chain's first two frequencies against Euler-Bernoulli's and
    the damping; then what the flexing did: the dampers' work in the energy ledger and
    the linear nutation rate against the quasi-rigid energy-sink estimate (@outcome)."""
    apps = h.appendages
    if not apps:
        return ""
    rows = [appendage_row(c, i, a, p) for i, a in enumerate(apps)
            for p in range(max(1, a["planes"]))]
    out = ["<h3>Appendages</h3><table><caption>Flexible appendages (the run's body, "
           "<code>@body</code>): clamped chain of rigid segments vs the Euler-Bernoulli "
           "beam</caption><thead><tr><th>appendage</th><th>kind</th><th>segments</th>"
           "<th>plane</th><th>\u03c9<sub>1</sub> chain [rad/s]</th>"
           "<th>\u03c9<sub>1</sub> beam [rad/s]</th><th>chain/beam \u2212 1</th>"
           "<th>\u03c9<sub>2</sub> chain [rad/s]</th><th>\u03c9<sub>2</sub> beam [rad/s]</th>"
           "<th>chain/beam \u2212 1</th><th>\u03b6<sub>1</sub></th>"
           "<th>damper per hinge [N m s/rad]</th></tr></thead><tbody>" + "".join(rows)
           + "</tbody></table>"]
    items = []
    if "work_damper" in h:
        n = len(h.time) - 1
        w, e0 = float(h["work_damper"][n]), float(h["energy_total"][0])
        items.append("Work of the dampers on the system over the run (energy ledger; "
                     "&lt; 0: dissipated): "
                     + c.h5(hp("work_damper", n), tag="span", cls=None, unit="J", digits=3,
                            suffix="\u00a0J")
                     + ", " + c.derived(f"{hp('work_damper', n)} / /energy_total#0", w / e0,
                                        fmt_num(100 * w / e0, 3) + "\u00a0%", tag="span",
                                        cls=None, unit="1")
                     + " of the initial energy.")
    o = h.outcome
    if o is not None and o["linear"]["found"]:
        quasi = o["linear"]["quasi_rigid_rate"]
        items.append("Nutation rate of the final spin from the linearized equations (flexing "
                     "included): "
                     + c.h5("@outcome#linear.growth_rate", tag="span", cls=None, unit="1/s",
                            digits=4, suffix="\u00a01/s")
                     + "; quasi-rigid energy-sink estimate: "
                     + (c.h5("@outcome#linear.quasi_rigid_rate", tag="span", cls=None,
                             unit="1/s", digits=4, suffix="\u00a01/s")
                        if quasi is not None else "none")
                     + " (&lt; 0: the nutation decays).")
    if items:
        out.append("<ul>" + "".join(f"<li>{i}</li>" for i in items) + "</ul>")
    out.append("<p class='note'><b>\u03c9<sub>n</sub> chain</b>: the n-th bending frequency "
               "of the appendage's chain of segments with the hub held still; <b>beam</b>: "
               "the uniform Euler-Bernoulli cantilever's (the chain converges to it as "
               "1/N\u00b2). <b>\u03b6<sub>1</sub></b>: the first mode's damping ratio "
               "(stiffness-proportional dampers, the same on every bending hinge of a "
               "plane).</p>")
    return "".join(out)


def section_configuration(c, h, ctx):
    out = ['<section id="configuration"><h2>1. Configuration</h2>']
    model = ctx["model"] or {}
    desc = model.get("description") or ""
    out.append("<p>Model <b>" + c.h5("@model_name", tag="span", cls=None) + "</b> (<code>"
               + c.h5("@model_source", tag="span", cls=None) + "</code>, kind "
               f"<code>{esc(model.get('kind', '?'))}</code>)"
               f"{': ' + esc(' '.join(str(desc).split()).rstrip('.')) if desc else ''}. Mode "
               + c.h5("@mode", tag="code", cls=None) + ", coupling "
               + c.h5("@coupling", tag="code", cls=None) + ".</p>")
    out += model_tables(model)
    out.append(appendage_table(c, h))
    out.append(initial_state(c, h, ctx))
    rows = ["<tr><th>start</th><td class='t'>initial state</td>"
            + c.h5("/time#0", unit="s", dec=3)
            + "".join(c.h5(hp("principal_moments", 0, k), unit="kg m^2", digits=6)
                      for k in range(3))
            + f"<td class='t'>{esc(role_text(ctx['axis_role0']))}</td></tr>"]
    for i, s in enumerate(ctx["stages"]):
        rows.append(
            "<tr>" + c.h5(hp("stages/index", i), tag="th", cls=None)
            + c.h5(hp("stages/name", i), cls="t", shown=stage_label(h, i))
            + c.h5(hp("stages/t_end", i), unit="s", dec=3)
            + "".join(c.h5(hp("stages/moments_end", i, k), unit="kg m^2", digits=6)
                      for k in range(3))
            + c.h5(hp("stages/spin_axis_role", i), cls="t",
                   shown=esc(role_text(s["spin_axis_role"])))
            + "</tr>")
    out.append("<table><caption>Principal moments at each stage end (ascending) and the role "
               "of the spin axis among the principal axes</caption><thead><tr><th>#</th>"
               "<th>stage</th><th>at t [s]</th><th>I<sub>1</sub> [kg m\u00b2]</th>"
               "<th>I<sub>2</sub> [kg m\u00b2]</th><th>I<sub>3</sub> [kg m\u00b2]</th>"
               "<th>spin axis is the \u2026 axis</th></tr></thead><tbody>" + "".join(rows)
               + "</tbody></table>")
    out.append("<p class='note'>A spin about the intermediate axis (the middle moment) is "
               "unstable: the body flips over periodically (Dzhanibekov effect). About the "
               "minor or major axis the momentum only wobbles.</p></section>")
    return "".join(out)


def initial_state(c, h, ctx):
    """The table of the initial spin: axis, rate, w and |H_B| at the first sample."""
    w0 = [float(x) for x in h["w_NB_B"][0]]
    rate = math.sqrt(sum(x * x for x in w0))
    H0 = math.sqrt(sum(float(x) ** 2 for x in h["H_B"][0]))
    return ("<table class='kv'><caption>Initial state (t = "
            + c.h5("/time#0", tag="span", cls=None) + " s, from the trajectory file)"
            "</caption><tbody>"
            f"<tr><th>spin axis (principal axis nearest H_B)</th><td class='t'>"
            f"{esc(ctx['axis_name'])}, the {esc(role_text(ctx['axis_role0']))} axis</td></tr>"
            "<tr><th>spin rate |w|</th>"
            + c.derived("norm /w_NB_B#0", rate,
                        f"{fmt_num(rate, 4)} rad/s = {fmt_num(rate * 60 / (2 * math.pi), 4)} rpm",
                        unit="rad/s")
            + "</tr><tr><th>w_NB_B(0) [rad/s]</th>"
            + c.h5("/w_NB_B#0", shown=", ".join(fmt_num(x, 5) for x in w0), unit="rad/s")
            + "</tr><tr><th>|H_B(0)| [kg m\u00b2/s]</th>"
            + c.derived("norm /H_B#0", H0, fmt_num(H0, 5), unit="kg m^2/s")
            + "</tr></tbody></table>")


def stability_row(c, i, s):
    """One row of the stability table: stage i of the file's stage table."""
    def p(col):
        return hp("stages/" + col, i)
    rigid = s["rigid"]
    regime = (c.h5(p("regime"), cls="t", shown=esc(regime_text(s["regime"]))) if rigid else
              f"<td class='t'>{'(free hinges)' if s['law'] == 'free' else '(deploying)'}</td>")
    flips = c.h5(p("observed_flip_count"), tag="span", cls=None)
    if rigid:
        flips += " / " + c.h5(p("predicted_flip_count"), tag="span", cls=None)
    half = p("predicted_flip_half_period")
    return (
        "<tr>" + c.h5(p("index"), tag="th", cls=None)
        + c.h5(p("name"), cls="t", shown=stage_label(c.h, i))
        + c.h5(p("law"), cls="t")
        + "<td class='n'>" + c.h5(p("t_begin"), tag="span", cls=None, unit="s", dec=3)
        + "\u2013<br>" + c.h5(p("t_end"), tag="span", cls=None, unit="s", dec=3) + "</td>"
        + c.h5(p("rigid"), cls="t", shown="yes" if rigid else "no")
        + c.h5(p("spin_axis_role"), cls="t") + regime
        + (c.h5(p("one_minus_k2"), digits=3) if rigid else "<td class='t'>\u2014</td>")
        + c.h5(p("separatrix_distance"), digits=3)
        + (c.h5(half, unit="s", dec=3) if math.isfinite(s["predicted_flip_half_period"]) else
           c.h5(half, unit="s", shown="\u221e" if rigid else "\u2014"))
        + f"<td class='n'>{flips}</td>"
        + c.h5(p("rigid_body_only"), cls="t",
               shown=(f'<span class="warn">{RIGID_CAVEAT_MARK}</span>'
                      if s["rigid_body_only"] else ""))
        + "</tr>")


def section_stability(c, h, ctx):
    out = ['<section id="stability"><h2>2. Stability per stage</h2>']
    rows = [stability_row(c, i, s) for i, s in enumerate(ctx["stages"])]
    out.append(
        "<table class='stab'><caption>Stability table (one row per stage; a free-hinge profile: "
        "per phase between hinge events)</caption><thead><tr><th>#</th><th>stage</th>"
        "<th>law</th><th>t<sub>0</sub>\u2013t<sub>1</sub> [s]</th><th>const. J</th>"
        "<th>spin axis at t<sub>1</sub> is the \u2026 axis</th>"
        "<th>polhode circulates about the \u2026 axis</th><th>1\u2212k\u00b2</th>"
        "<th>sep. dist.</th><th>flip every [s]</th><th>flips seen / pred.</th>"
        f"<th title='verdict holds only for a perfectly rigid body'>{RIGID_CAVEAT_MARK}</th>"
        "</tr></thead><tbody>"
        + "".join(rows) + "</tbody></table>")
    out.append(
        "<p class='note'><b>Two different axes.</b> <b>spin axis</b>: the role of the body's "
        "spin axis among the principal axes of J_B at the stage end (minor, intermediate or "
        "major moment). <b>polhode circulates about</b> (constant stages): the principal "
        "axis that the angular momentum's path in the body (the polhode) goes round, set "
        "by the energy: about the minor axis when D &lt; I<sub>2</sub>, about the major "
        "axis when D &gt; I<sub>2</sub> (D = |H|\u00b2/2T). A polhode never circulates "
        "about the intermediate axis, so an intermediate spin axis always goes with "
        "\u201cminor\u201d or \u201cmajor\u201d here: the momentum goes round that other "
        "axis and so turns over relative to the spin axis, which is the flip.</p>"
        "<p class='note'><b>const. J</b>: J_B constant and no relative momentum over the "
        "stage (a hold), where the closed form applies. <b>1\u2212k\u00b2</b>: complementary elliptic parameter (0 on the "
        "separatrix). <b>sep. dist.</b>: (D \u2212 I<sub>2</sub>)/(I<sub>3</sub> \u2212 "
        "I<sub>1</sub>) at the stage end, 0 on the separatrix, &lt; 0 circulating about the "
        "minor axis. <b>flip every</b>: closed-form time between flips (\u221e: no flips). "
        f"<b>flips</b>: located / closed-form (constant stages only). {RIGID_CAVEAT_MARK}: the "
        "verdict holds only for a perfectly rigid body (see the caveats).</p>")
    # caveats
    crow = []
    for i, s in enumerate(ctx["stages"]):
        crow.append("<tr>" + c.h5(hp("stages/index", i), tag="th", cls=None)
                    + c.h5(hp("stages/caveat", i), cls="t",
                           shown=(f'<span class="warn">{RIGID_CAVEAT_MARK}</span> '
                                  if s["rigid_body_only"] else "") + esc(s["caveat"] or "\u2014"))
                    + "</tr>")
    out.append("<h3>Caveats: what each verdict assumes</h3>"
               f"<p class='note'>{RIGID_CAVEAT_MARK} marks verdicts that hold only for a "
               "perfectly rigid body: with any energy dissipation (flexible panels, dampers, "
               "fuel slosh) a spin settles about the major axis (the major-axis rule).</p>"
               "<table><thead><tr><th>#</th><th>caveat</th></tr></thead><tbody>"
               + "".join(crow) + "</tbody></table>")
    out.append(danger_windows(c, h))
    out.append("</section>")
    return "".join(out)


def danger_windows(c, h):
    if not h.danger_windows:
        return ("<h3>Danger windows</h3><p>None: the spin axis is never the intermediate "
                "axis.</p>")
    drow = []
    for w, (a, b) in enumerate(h.danger_windows):
        begin, end = hp("danger_windows/t_begin", w), hp("danger_windows/t_end", w)
        drow.append(f"<tr><th>{w + 1}</th>" + c.h5(begin, unit="s", dec=3)
                    + c.h5(end, unit="s", dec=3)
                    + c.derived(f"{end} - {begin}", b - a, fmt_fixed(b - a, 3), unit="s")
                    + "</tr>")
    return ("<h3>Danger windows</h3><p class='note'>Intervals in which the spin axis is "
            "the intermediate principal axis of J_B(t) (flips possible); first and last "
            "output time.</p><table class='kv'><thead><tr><th>#</th><th>from [s]</th>"
            "<th>to [s]</th><th>length [s]</th></tr></thead><tbody>" + "".join(drow)
            + "</tbody></table>")


def flip_rows(c, h, ctx):
    """The located flips, each with its stage and the nearest predicted flip; then the
    predicted flips that no located flip matched."""
    stages, tp = ctx["stages"], h.predicted_flip_time
    stage_of = {}
    for i, s in enumerate(stages):
        for f in s["flip_rows"]:
            stage_of.setdefault(f, i)
    rows, matched = [], set()
    for f, t in enumerate(h.flip_time):
        i = stage_of.get(f)
        cells = f"<tr><th>{f + 1}</th>" + c.h5(hp("events/flip_time", f), unit="s", dec=6)
        preds = stages[i]["predicted_flip_rows"] if i is not None else []
        if i is None:
            cells += "<td class='t'>?</td><td></td><td></td>"
        elif preds:
            n = min(preds, key=lambda k: abs(tp[k] - t))
            matched.add(n)
            d = float(t - tp[n])
            cells += (c.h5(hp("stages/name", i), cls="t", shown=stage_label(h, i))
                      + c.h5(hp("events/predicted_flip_time", n), unit="s", dec=6)
                      + c.derived(f"{hp('events/flip_time', f)} - "
                                  f"{hp('events/predicted_flip_time', n)}", d, fmt_num(d, 3),
                                  unit="s"))
        else:
            cells += (c.h5(hp("stages/name", i), cls="t", shown=stage_label(h, i))
                      + "<td class='t'>(no closed form: deploying)</td><td class='t'>\u2014</td>")
        rows.append(cells + "</tr>")
    for i, s in enumerate(stages):
        for n in s["predicted_flip_rows"]:
            if n not in matched:
                rows.append("<tr><th>\u2014</th><td class='t warn'>not located</td>"
                            + c.h5(hp("stages/name", i), cls="t", shown=stage_label(h, i))
                            + c.h5(hp("events/predicted_flip_time", n), unit="s", dec=6)
                            + "<td class='t'>\u2014</td></tr>")
    return rows


def section_flips(c, h, ctx):
    out = ['<section id="flips"><h2>3. Flips: located vs predicted</h2>']
    out.append("<p class='note'>A flip is a sign change of the angular momentum along the "
               "tracked spin axis while that axis is intermediate, located on the dense "
               "output (docs/file_formats.md, Flips). On constant-inertia stages the closed "
               "form predicts a flip every half period; on deploying stages there is no "
               "closed-form prediction.</p>")
    rows = flip_rows(c, h, ctx)
    if rows:
        out.append("<table><thead><tr><th>#</th><th>located t [s]</th><th>stage</th>"
                   "<th>predicted t [s]</th><th>located \u2212 predicted [s]</th></tr></thead>"
                   "<tbody>" + "".join(rows) + "</tbody></table>")
    else:
        out.append("<p>No flips located, none predicted.</p>")
    srow = []
    for i, s in enumerate(ctx["stages"]):
        if not s["predicted_flip_count"] and not s["observed_flip_count"]:
            continue
        srow.append("<tr>" + c.h5(hp("stages/index", i), tag="th", cls=None)
                    + c.h5(hp("stages/name", i), cls="t", shown=stage_label(h, i))
                    + c.h5(hp("stages/observed_flip_count", i))
                    + c.h5(hp("stages/predicted_flip_count", i))
                    + c.h5(hp("stages/max_flip_time_difference", i), unit="s", digits=3)
                    + "</tr>")
    if srow:
        out.append("<table class='kv'><caption>Per stage</caption><thead><tr><th>#</th>"
                   "<th>stage</th><th>located</th><th>predicted</th>"
                   "<th>max |located \u2212 predicted| [s]</th></tr></thead><tbody>"
                   + "".join(srow) + "</tbody></table>")
    out.append("</section>")
    return "".join(out)


def hinge_event_row(c, e, ev):
    """One row of the deployment timeline: event e of the hinge event table."""
    def p(col):
        return hp("events/hinge/" + col, e)
    dash = "<td class='t'>\u2014</td>"
    rel = ev["kind"] == "release"
    wj = math.sqrt(sum(float(x) ** 2 for x in ev["w_jump_B"]))
    return (
        "<tr>" + c.h5(p("time"), unit="s", dec=4) + c.h5(p("panel_name"), cls="t")
        + c.h5(p("kind"), cls="t")
        + c.h5(p("angle"), unit="rad", scale=DEG, dec=3)
        + (dash * 2 if rel else c.h5(p("rate_before"), unit="rad/s", scale=DEG, dec=3)
           + c.h5(p("rate_after"), unit="rad/s", scale=DEG, dec=3))
        + (dash * 3 if rel else c.h5(p("impulse"), unit="N m s", digits=4)
           + c.derived(f"norm {p('w_jump_B')}", wj, fmt_num(wj * DEG, 4), unit="rad/s")
           + c.h5(p("energy_dissipated"), unit="J", digits=4))
        + "</tr>")


def hinge_timeline(c, h, ctx):
    """The hinge event table and the panels' lock times of a free-hinge profile."""
    ev = ctx["events"]
    listed = listed_events(h, ev)
    rows = [hinge_event_row(c, e, x) for e, x in listed]
    total = sum(e["energy_dissipated"] for e in ev)
    rows.append("<tr><th colspan='8' style='text-align:right'>energy dissipated in all "
                "events [J]</th>"
                + c.derived("sum /events/hinge/energy_dissipated", total,
                            "<b>" + fmt_num(total, 4) + "</b>", unit="J") + "</tr>")
    hidden = len(ev) - len(listed)
    out = [] if not hidden else [
        f"<p class='note'>The {hidden} hinges the appendages generated are free from the start: "
        "their releases at t = " + c.h5("/time#0", tag="span", cls=None, unit="s")
        + " s are in the file's <code>/events/hinge</code>, not listed here.</p>"]
    out += ["<table><caption>Hinge events in time order</caption><thead><tr>"
           "<th>t [s]</th><th>panel</th><th>event</th><th>angle [deg]</th>"
           "<th>rate before [deg/s]</th><th>rate after [deg/s]</th>"
           "<th>impulse [N m s]</th><th>|hub w jump| [deg/s]</th>"
           "<th>dissipated [J]</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table>",
           "<p class='note'><b>release</b>: a held hinge starts to move. "
           "<b>latch</b>: the hinge reaches its latch angle and is locked by a plastic "
           "impulse. <b>jam</b>: locked part-way (failure mode). <b>stop</b>: impact on "
           "a hard stop, the panel rebounds. <b>rest</b>: the panel comes to rest on a "
           "stop and is held there; <b>lift-off</b>: the torque holding it pulls it away. "
           "<b>stick</b> / <b>slip</b>: Coulomb friction holds the hinge at rest / lets it "
           "go. <b>|hub w jump|</b>: the shock a latch gives the spacecraft (jump of "
           "the hub's angular velocity); angles 0 = deployed.</p>"]
    lrow = []
    bending = bending_hinges(h)
    for k, (name, t) in enumerate(h.latch_times.items()):
        if name in bending:  # free springs: they never lock
            continue
        how = ""
        for e in ev:
            if e["panel_name"] == name and e["time"] == t and e["kind"] not in ("release", "stop"):
                how = e["kind"]
        lrow.append(f"<tr><th>{esc(name)}</th>"
                    + (c.h5(hp("hinge_latch_time", k), unit="s", dec=4) if math.isfinite(t)
                       else c.h5(hp("hinge_latch_time", k), shown="never", cls="t warn"))
                    + f"<td class='t'>{esc(how)}</td></tr>")
    out.append("<table class='kv'><caption>Panels locked (latch, jam or rest on a stop)"
               "</caption><thead><tr><th>panel</th><th>t [s]</th><th>how</th></tr></thead>"
               "<tbody>" + "".join(lrow) + "</tbody></table>")
    return "".join(out)


def section_timeline(c, h, ctx):
    out = ['<section id="timeline"><h2>4. Deployment timeline</h2>']
    if not ctx["is_hinge"]:
        out.append("<p>A stage profile: the panels follow prescribed laws (section 2); there "
                   "are no hinge events (releases, latches, impacts).</p>")
    else:
        out.append(hinge_timeline(c, h, ctx))
    cr = h.spin_axis_45_time
    if len(cr):
        per_row = 6  # a grid, not one tall column
        rows = []
        for r0 in range(0, len(cr), per_row):
            r1 = min(len(cr), r0 + per_row)
            rows.append(f"<tr><th>{r0 + 1}\u2013{r1}</th>" if r1 > r0 + 1 else
                        f"<tr><th>{r0 + 1}</th>")
            rows[-1] += "".join(c.h5(hp("events/spin_axis_45_time", k), unit="s", dec=3)
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


def section_coupling(c, h, ctx):
    out = ['<section id="coupling"><h2>5. Coupling: exact vs quasi-rigid</h2>']
    if ctx["is_hinge"]:
        out.append("<p>Not applicable: this is a free-hinge profile (<code>hinges:</code>). "
                   "Free hinges are always coupled exactly: the hinge rates come out of the "
                   "dynamics and their relative momentum enters the equations; there is no "
                   "quasi-rigid alternative to compare.</p></section>")
        return "".join(out)
    if not ctx["comparison"]:
        out.append(f"<p>Not applicable: mode <code>{esc(h.attr('mode'))}</code> has no hinge "
                   "geometry, so the panels carry no relative momentum to neglect (the "
                   "comparison needs a geometry-mode stage profile).</p></section>")
        return "".join(out)
    cc = "/coupling_comparison/"
    cmp = ctx["other"]["coupling_comparison"]
    frac = cmp["max_w_difference_deploying"] / cmp["w_scale"]
    other = ctx["other_coupling"]
    rows = [
        "<tr><th>max |w<sub>exact</sub> \u2212 w<sub>quasi</sub>| while deploying</th>"
        + c.js(cc + "max_w_difference_deploying", unit="rad/s", digits=4, suffix=" rad/s")
        + c.derived(f"{cc}max_w_difference_deploying / {cc}w_scale", frac,
                    fmt_num(frac, 3) + " of max |w|", doc=OTHER) + "</tr>",
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
               + c.h5("@coupling", tag="code", cls=None) + " coupling. The comparison runs "
               f"both: <code>deploysim analyze --json --coupling {esc(other)}</code> with the "
               "same settings, whose cells carry data-doc=\"other-coupling\".</p>")
    out.append("<table class='kv'><tbody>" + "".join(rows) + "</tbody></table>")
    out.append(coupling_flips(c, h, ctx))
    out.append("</section>")
    return "".join(out)


def coupling_flips(c, h, ctx):
    """This run's flips (the trajectory file) beside the other coupling's (its JSON)."""
    mine, theirs = list(h.flip_time), ctx["other"]["flip_times"]
    exact_first = h.attr("coupling") == "exact"
    n = max(len(mine), len(theirs))
    frow = []
    for k in range(n):
        this = (c.h5(hp("events/flip_time", k), unit="s", dec=3) if k < len(mine)
                else "<td class='t'>\u2014</td>")
        that = (c.js(ptr("flip_times", k), unit="s", dec=3) if k < len(theirs)
                else "<td class='t'>\u2014</td>")
        r = f"<tr><th>{k + 1}</th>" + (this + that if exact_first else that + this)
        if k < len(mine) and k < len(theirs):
            ex, qr = (mine[k], theirs[k]) if exact_first else (theirs[k], mine[k])
            dd = float(qr - ex)
            r += Cells.src("quasi-rigid minus exact flip time", dd, fmt_num(dd, 3), unit="s")
        else:
            r += "<td></td>"
        frow.append(r + "</tr>")
    return (f"<h3>Flips under each coupling</h3><p class='note'>This run's flips from its "
            f"trajectory file, the {esc(ctx['other_coupling'])} run's from its "
            "<code>analyze --json</code>.</p>"
            "<table class='kv'><thead><tr><th>#</th><th>exact t [s]</th>"
            "<th>quasi-rigid t [s]</th><th>difference [s]</th></tr></thead><tbody>"
            + "".join(frow) + "</tbody></table>")


def section_plots(c, h, ctx):
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


def section_integrator(c, h, ctx):
    settings = h.attr_fields("integrator_settings")
    out = ['<section id="integrator"><h2>7. Integrator and accuracy</h2>']
    rows = ["<tr><th>method</th>" + c.h5("@integrator", cls="t") + "</tr>"]
    for k in ("rtol", "atol", "step", "max_step", "output_dt"):
        if k in settings:
            unit = {"step": "s", "max_step": "s", "output_dt": "s"}.get(k, "1")
            rows.append(f"<tr><th>{esc(k)}{' [s]' if unit == 's' else ''}</th>"
                        + c.h5("@integrator_settings#" + k, shown=esc(settings[k]), unit=unit)
                        + "</tr>")
    rows.append("<tr><th>termination</th>" + c.h5("@termination", cls="t") + "</tr>")
    stats = h.attr_fields("statistics")
    for label, key in (("accepted steps", "steps"), ("rejected steps", "rejected"),
                       ("right-hand-side evaluations", "evaluations")):
        if key in stats:
            rows.append(f"<tr><th>{label}</th>" + c.h5("@statistics#" + key) + "</tr>")
    rows.append("<tr><th>wall time of the simulate run (incl. writing HDF5) [s]</th>"
                + Cells.src("measured by tools/report.py around deploysim simulate",
                            ctx["sim_seconds"], fmt_num(ctx["sim_seconds"], 3), unit="s")
                + "</tr>")
    out.append("<table class='kv'><caption>Settings and work</caption><tbody>"
               + "".join(rows) + "</tbody></table>")
    out.append("<p class='note'>The wall time is measured by tools/report.py around the "
               "<code>deploysim simulate</code> process (the trajectory file holds no wall "
               "time); everything else is read from the trajectory file.</p>")
    out.append(accuracy(c, h, ctx))
    out.append("</section>")
    return "".join(out)


def accuracy(c, h, ctx):
    """The accuracy evidence: h_N drift, energy drift on rigid stages, flip times."""
    stages = ctx["stages"]
    arow = ["<tr><th>max |h_N(t) \u2212 h_N(0)| / |h_N(0)| over the run (inertial momentum, "
            "conserved exactly)</th>" + c.h5("@max_h_N_drift", digits=3) + "</tr>"]
    for i, s in enumerate(stages):
        if ctx["energy_drift"][i] is None:
            continue
        d, n = ctx["energy_drift"][i]
        arow.append("<tr><th>energy drift on stage "
                    + c.h5(hp("stages/index", i), tag="span", cls=None) + " \u201c"
                    + esc(s["name"]) + "\u201d ("
                    + c.h5(hp("stages/t_begin", i), tag="span", cls=None, dec=2) + "\u2013"
                    + c.h5(hp("stages/t_end", i), tag="span", cls=None, dec=2)
                    + f" s, {n} samples): max |E \u2212 E<sub>first</sub>| / E</th>"
                    + Cells.src(f"h5: /energy over /time in (t_begin, t_end) of stage {i}", d,
                                fmt_num(d, 3)) + "</tr>")
    wi = max(range(len(stages)), key=lambda i: stages[i]["max_flip_time_difference"])
    arow.append("<tr><th>max |located \u2212 closed-form flip time| [s]</th>"
                + c.h5(hp("stages/max_flip_time_difference", wi), unit="s", digits=3)
                + "</tr>")
    return ("<table class='kv'><caption>Accuracy evidence</caption><tbody>" + "".join(arow)
            + "</tbody></table>"
            "<p class='note'>Rigid (constant-inertia) stages conserve the kinetic energy "
            "exactly; its drift there, like the drift of the inertial momentum h_N over the "
            "whole run, measures the integration error. The closed-form flip times are an "
            "independent analytic oracle for the located ones.</p>")


def section_inputs(c, h, ctx):
    a = h.attrs
    out = ['<section id="inputs" class="inputs"><h2>8. Inputs and provenance</h2>']

    def attr(name, tag="span"):
        return c.h5("@" + name, tag=tag, cls=None)
    build = (" " + Cells.src("deploysim --version", ctx["build_id"],
                             f"({esc(ctx['build_id'])})", tag="span", cls=None)
             if ctx["build_id"] else "")
    rows = [
        ("deploysim version", attr("deploysim_version") + build),
        ("HDF5 schema version", attr("schema_version")),
        ("report generated", Cells.src("clock of tools/report.py (UTC)", ctx["generated"],
                                       esc(ctx["generated"]), tag="span", cls=None)),
        ("profile", attr("profile_source", "code") + " (name " + attr("profile_name") + ")"),
        ("model", attr("model_source", "code") + " (name " + attr("model_name") + ")"),
        ("mode, coupling", attr("mode") + ", " + attr("coupling")),
        ("integrator", attr("integrator") + ": " + attr("integrator_settings", "code")),
    ]
    cmds = "".join(f"<li><code>{esc(cmd)}</code></li>" for cmd in ctx["commands"])
    out.append("<table class='kv'><tbody>" + "".join(
        f"<tr><th>{k}</th><td class='t'>{cell}</td></tr>" for k, cell in rows)
        + "</tbody></table>")
    out.append(f"<p>Commands run for this report:</p><ul class='note'>{cmds}</ul>")
    out.append("<p class='note'>To reproduce the run from the texts below: save the profile, "
               "save the model at the path its <code>model:</code> key names, and run "
               "<code>deploysim simulate</code> with the settings above (the trajectory is the "
               "same bit for bit; docs/file_formats.md).</p>")
    out.append(f"<h3>Profile ({esc(a.get('profile_source', ''))})</h3>"
               f"<pre>{esc(a.get('profile_text', ''))}</pre>")
    out.append(f"<h3>Model ({esc(a.get('model_source', ''))})</h3>"
               f"<pre>{esc(a.get('model_text', ''))}</pre>")
    out.append(
        "<h3>Reading the numbers by machine</h3><p class='note'>Every number of the run "
        "carries <code>data-h5</code>, a pointer into the trajectory file that "
        "<code>deploysim simulate</code> writes with the settings above "
        "(docs/file_formats.md, \u201cTrajectory files\u201d): a dataset and its row, "
        "<code>/stages/t_end#2</code>, or row and column, <code>/stages/moments_end#2,0</code>; "
        "a root attribute, <code>@max_h_N_drift</code>, or a field of one, "
        "<code>@statistics#steps</code>. <code>data-value</code> is its full-precision value "
        "(SI units even where the cell shows degrees). Numbers computed from the file carry "
        "<code>data-derived</code> (<code>/a#i - /b#j</code>, <code>len /a</code>, "
        "<code>sum /a</code>, <code>norm /a#i</code>); the comparison with the other coupling "
        "carries <code>data-json</code>, a JSON pointer into that run's <code>analyze "
        "--json</code>, with <code>data-doc=\"other-coupling\"</code>; numbers from the model "
        "text or measured by the report carry <code>data-src</code>.</p>")
    out.append("</section>")
    return "".join(out)


def build_html(h, ctx):
    c = Cells(h, ctx["other"])
    a = h.attrs
    profile = ctx["profile_doc"] or {}
    desc = profile.get("description") or ""
    title = f"Mission report: {h.profile_name}"
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
        f"{esc(a.get('integrator', '?'))} \u00b7 generated {esc(ctx['generated'])}</div>",
        section_summary(c, h, ctx),
        toc,
    ] + [section(c, h, ctx) for section in (
        section_configuration, section_stability, section_flips, section_timeline,
        section_coupling, section_plots, section_integrator, section_inputs)]
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
                    "coupling comparison, plots, integrator accuracy, inputs). It runs "
                    "deploysim simulate once and reads every number of the run from its "
                    "trajectory file.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n"
               "  deploysim report deployment_profiles/smallsat_spring_deploy.yaml -o spring.html\n"
               "  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_spring_deploy.yaml"
               " \\\n      -o spring_report.html --deploysim build/release/bin/deploysim\n"
               "  /usr/bin/python3 tools/report.py deployment_profiles/smallsat_three_stage.yaml"
               " \\\n      -o three_stage.html --method rkmk-rkf78 --rtol 1e-12 --dt 0.05\n\n"
               "Exit codes: 0 written; 1 bad input or command line (deploysim's message "
               "passed through);\n3 integration stopped early; 5 a plot tool, the trajectory "
               "file or the output failed\n(4 is not used). On an error no file is written.")
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


def check_output(out, inputs):
    """The folder of -o (which must exist and be no input); ReportError otherwise."""
    for inp in inputs:
        if same_file(out, inp):
            raise ReportError(f"-o {out}: is an input ({inp}); refusing to overwrite it",
                              EXIT_BAD_INPUT)
    if os.path.isdir(out):
        raise ReportError(f"-o {out}: is a folder", EXIT_BAD_INPUT)
    out_dir = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(out_dir):
        raise ReportError(f"-o {out}: folder {out_dir} does not exist", EXIT_BAD_INPUT)
    return out_dir


def yaml_text(text):
    """A YAML text (the file's profile or model) as a dict, {} if it is none."""
    import yaml
    try:
        doc = yaml.safe_load(text)
    except yaml.YAMLError:
        return {}
    return doc if isinstance(doc, dict) else {}


def simulate(args, exe, profile, work, ctx):
    """Runs deploysim simulate into work/ and reads its trajectory file: (path, run)."""
    h5 = os.path.join(work, "trajectory.h5")
    cmd = [exe, "simulate", profile, "-o", h5, *overrides(args), "-q"]
    ctx["commands"].append(" ".join(["deploysim"] + cmd[1:]).replace(h5, "TRAJECTORY.h5"))
    # The first run also validates the input: the progress line comes after it, so that
    # bad input gives deploysim's one line and nothing else.
    _, ctx["sim_seconds"] = run(cmd, "simulate")
    try:
        h = read_trajectory(h5)
        ctx["stages"], ctx["events"] = h.stages, h.hinge_events
    except TrajectoryError as e:
        raise ReportError(str(e).replace(h5, "the trajectory file"), EXIT_TOOL) from None
    progress(args, f"simulated {profile} (deploysim simulate, {ctx['sim_seconds']:.1f} s): "
                   f"{len(ctx['stages'])} stage(s), {len(h.flip_time)} flip(s)")
    return h5, h


def compare_couplings(args, exe, profile, h, ctx):
    """Stage profiles in geometry mode: the other coupling's analyze --json (deploysim runs
    both couplings and compares them) into ctx["other"]."""
    ctx["other"], ctx["other_coupling"], ctx["comparison"] = None, None, False
    if ctx["is_hinge"] or h.attrs.get("mode") != "geometry":
        return
    other = "quasi-rigid" if h.attrs.get("coupling") == "exact" else "exact"
    ctx["other_coupling"] = other
    progress(args, f"comparing with {other} coupling (deploysim analyze --json)")
    cmd = [exe, "analyze", profile, "--json", *overrides(args), "--coupling", other]
    ctx["commands"].append(" ".join(["deploysim"] + cmd[1:]))
    text, _ = run(cmd, "analyze")
    try:
        ctx["other"] = json.loads(text)
    except ValueError as e:
        raise ReportError(f"deploysim analyze --json: not JSON ({e})", EXIT_TOOL)
    ctx["comparison"] = "coupling_comparison" in ctx["other"]


def plots(args, h5, work, ctx):
    """The figures of tools/plot_trajectory.py and tools/plot_geometry.py into work/."""
    progress(args, "plotting (tools/plot_trajectory.py)")
    ctx["plot_dir"] = os.path.join(work, "plots")
    run([sys.executable, os.path.join(TOOLS, "plot_trajectory.py"), h5, "-o",
         ctx["plot_dir"]], "plot_trajectory.py")
    geo = os.path.join(TOOLS, "plot_geometry.py")
    ctx["geometry_dir"] = os.path.join(work, "geometry")
    ctx["geometry_note"] = ""
    if not os.path.isfile(geo):
        ctx["geometry_note"] = ("tools/plot_geometry.py is not installed next to "
                                "tools/report.py.")
        return
    progress(args, "plotting (tools/plot_geometry.py)")
    try:
        run([sys.executable, geo, h5, "-o", ctx["geometry_dir"]], "plot_geometry.py")
    except ReportError as e:
        # e.g. two equal principal moments in the last stage: no separatrix to draw.
        # The rest of the report stands; the note says why the figures are missing.
        why = str(e).replace(h5, "the trajectory")
        ctx["geometry_note"] = f"tools/plot_geometry.py could not draw them ({why})"
        progress(args, f"no geometry figures: {e}")


def write_page(out, out_dir, page):
    """Writes the page to a temporary file in out_dir and renames it to out."""
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


def make_report(args):
    t_start = time.monotonic()
    exe = find_deploysim(args.deploysim)
    profile, out = args.profile, args.output
    mp = model_path_of(profile)
    out_dir = check_output(out, [profile, exe] + ([mp] if mp else []))
    ctx = {"commands": [], "generated": generated_stamp(), "build_id": ""}
    with tempfile.TemporaryDirectory(prefix="deploysim-report-") as work:
        h5, h = simulate(args, exe, profile, work, ctx)
        try:
            v = subprocess.run([exe, "--version"], stdout=subprocess.PIPE,
                               stderr=subprocess.DEVNULL, text=True, timeout=30)
            ctx["build_id"] = v.stdout.strip()
        except (OSError, subprocess.SubprocessError):
            pass
        ctx["model"] = yaml_text(h.attrs.get("model_text", ""))
        ctx["profile_doc"] = yaml_text(h.attrs.get("profile_text", ""))
        ctx["is_hinge"] = "hinges" in ctx["profile_doc"]
        compare_couplings(args, exe, profile, h, ctx)
        ctx["axis_name"], ctx["axis_role0"] = initial_spin_axis(h)
        ctx["energy_drift"] = rigid_energy_drift(h, ctx["stages"])
        plots(args, h5, work, ctx)
        page = build_html(h, ctx)
    write_page(out, out_dir, page)
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
