#!/usr/bin/python3
"""Writes the answers README.md and docs/ publish about shipped runs and sweeps, from
those runs, so that a document never states a number the run does not give.

Usage: /usr/bin/python3 tools/published.py BIN [--update] [--check]
  BIN       the deploysim command (build/release/bin/deploysim)
  --update  rewrite every marked passage of README.md and docs/*.md from the runs
  --check   exit 1, naming each passage, where a document differs from the runs

A marked passage is the text between `<!-- published:NAME -->` and
`<!-- /published:NAME -->` (inline or over several lines); NAME is one of the GENERATORS
below. Wall-clock figures ("0.0183 s wall") are written but not compared. The runs take
about 30 s (the three shipped sweeps and a few profiles).
Exit status: 0 up to date (or updated); 1 a passage differs, an unknown NAME or a run
failed.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = ["README.md"] + sorted(
    os.path.join("docs", f) for f in os.listdir(os.path.join(ROOT, "docs")) if f.endswith(".md"))
MARK = re.compile(r"<!-- published:([\w.-]+) -->(.*?)<!-- /published:\1 -->", re.S)
WALL = re.compile(r"[0-9.e+-]+ s wall")
RPM = 60.0 / (2.0 * np.pi)
DEG = 180.0 / np.pi
MAIN_JOB = "deployment_profiles/smallsat_spring_deploy.yaml"


def g3(x):
    """A figure to 3 significant digits, as the documents quote them."""
    return f"{x:.3g}"


class Runs:
    """The runs the passages quote, each run once, in a temporary folder."""

    def __init__(self, binary, tmp):
        self.binary, self.tmp, self.cache = binary, tmp, {}

    def _run(self, *args):
        r = subprocess.run([self.binary, *args], cwd=ROOT, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"deploysim {' '.join(args)}: exit {r.returncode}: {r.stderr}")
        return r.stdout

    def simulate(self, profile):
        key = ("simulate", profile)
        if key not in self.cache:
            out = os.path.join(self.tmp, os.path.basename(profile) + ".h5")
            self.cache[key] = self._run("simulate", profile, "-o", out)
        return self.cache[key]

    def analyze_json(self, profile):
        key = ("analyze", profile)
        if key not in self.cache:
            self.cache[key] = json.loads(self._run("analyze", profile, "--json"))
        return self.cache[key]

    def sweep(self, sweep):
        """The sweep's `cases` columns as numpy arrays (strings decoded)."""
        key = ("sweep", sweep)
        if key not in self.cache:
            out = os.path.join(self.tmp, os.path.basename(sweep) + ".h5")
            self._run("sweep", sweep, "-o", out, "-q")
            with h5py.File(out, "r") as f:
                cols = {}
                for name, d in f["cases"].items():
                    a = d[()]
                    if a.dtype.kind in "OS":
                        a = np.array([x.decode() if isinstance(x, bytes) else x for x in a])
                    cols[name] = a
                limit = f.attrs.get("latch_shock_limit", "")
                cols["_limit"] = float(limit) if limit not in ("", b"") else float("nan")
            self.cache[key] = cols
        return self.cache[key]


# ---- the main job ----

def main_job_output(runs):
    """What `tools/run.sh` prints of the main job: the summary and the timeline."""
    text = runs.simulate(MAIN_JOB)
    text = text[:text.rfind("\nwrote ")].rstrip("\n")
    return "\n```\n" + text + "\n```\n"


def main_job_verdict(runs):
    """The verdict line the main job prints first."""
    line = next(x for x in runs.simulate(MAIN_JOB).splitlines() if x.startswith("verdict: "))
    return "\n```\n" + line + "\n```\n"


def dual_spin_rotor_verdict(runs):
    line = next(x for x in runs.simulate("deployment_profiles/dual_spin_rotor.yaml").splitlines()
                if x.startswith("verdict: "))
    return "\n```\n" + line + "\n```\n"


def three_stage_attitude_offset(runs):
    """The hub's attitude offset, quasi-rigid against exact coupling, at the end of the
    three-stage deployment (simulate --compare-coupling, analyze --json)."""
    c = runs.analyze_json("deployment_profiles/smallsat_three_stage.yaml")["coupling_comparison"]
    a = c["attitude_offset_at_deployment_end"]
    return f"{a:.2f} rad ({a * DEG:.0f}°)"


# ---- sweeps/smallsat_spring_stiffness_spin.yaml ----

def _spring_grid(runs):
    c = runs.sweep("sweeps/smallsat_spring_stiffness_spin.yaml")
    ks = np.unique(c["spring_stiffness"])
    ss = np.unique(c["spin_rate"])
    shock = c["max_latch_w_jump"] * DEG
    med = np.full((ks.size, ss.size), np.nan)
    worst = np.full_like(med, np.nan)
    for i, k in enumerate(ks):
        for j, s in enumerate(ss):
            m = (c["spring_stiffness"] == k) & (c["spin_rate"] == s)
            med[i, j] = np.median(shock[m])
            worst[i, j] = np.max(shock[m])
    return c, ks, ss * RPM, med, worst


def _stiffest_below(ks, values, limit):
    """The largest stiffness up to which every value stays below the limit (None: none)."""
    best = None
    for k, v in zip(ks, values):
        if not v < limit:
            break
        best = k
    return best


def _stiffest_safe_to(ks, rpm, worst, limit, top_rpm):
    """The stiffest spring whose worst case stays below the limit at every spin rate up to
    the grid's fastest one not above top_rpm; and that rate."""
    j = int(np.max(np.nonzero(rpm <= top_rpm * (1 + 1e-9))))
    return _stiffest_below(ks, np.max(worst[:, :j + 1], axis=1), limit), rpm[j]


def spring_answer(runs):
    c, ks, rpm, med, worst = _spring_grid(runs)
    k, s = _stiffest_safe_to(ks, rpm, worst, c["_limit"] * DEG, 5.0)
    return (f"at most {g3(k)} N m/rad at spin rates up to {g3(s)} rpm, every sampled failure "
            f"included")


def spring_table(runs):
    """Per spin rate: the stiffest spring whose median and whose worst case stay below
    the limit, and the shocks at the grid's softest and stiffest springs."""
    c, ks, rpm, med, worst = _spring_grid(runs)
    limit = c["_limit"] * DEG
    rows = ["| spin rate [rpm] | stiffest spring, median below the limit [N m/rad] | "
            "stiffest spring, worst case below the limit [N m/rad] | median shock at "
            f"{g3(ks[0])} / {g3(ks[-1])} N m/rad [deg/s] | deployment time at {g3(ks[0])} / "
            f"{g3(ks[-1])} N m/rad [s] |",
            "|---:|---:|---:|---:|---:|"]
    dur = c["deploy_duration"]
    for j, s in enumerate(rpm):
        km, kw = _stiffest_below(ks, med[:, j], limit), _stiffest_below(ks, worst[:, j], limit)
        d = [np.median(dur[(c["spring_stiffness"] == k) & (np.isclose(c["spin_rate"] * RPM, s))
                           & (c["all_latched"] == 1)]) for k in (ks[0], ks[-1])]
        rows.append(f"| {g3(s)} | {'none' if km is None else g3(km)} | "
                    f"{'none' if kw is None else g3(kw)} | {g3(med[0, j])} / {g3(med[-1, j])} | "
                    f"{g3(d[0])} / {g3(d[1])} |")
    return "\n" + "\n".join(rows) + "\n"


def spring_tumble(runs):
    c = runs.sweep("sweeps/smallsat_spring_stiffness_spin.yaml")
    n = c["outcome"].size
    latched = c["all_latched"] == 1
    rpm = c["spin_rate"] * RPM
    calm = ~np.isin(c["outcome"], ["flipping", "transition", "growing", "tumbling"])
    period = c["predicted_flip_half_period"]
    grid = np.unique(rpm)
    rates = (grid[0], grid[np.argmin(np.abs(grid - 5.0))], grid[-1])  # 5 rpm: the main job
    minutes = [np.median(period[latched & (rpm == s)]) / 60.0 for s in rates]
    within = np.sum(latched & (rpm == grid[0]) & (c["flip_count"] > 0))
    return (f"{np.sum(latched & (c['will_flip'] == 1))} of the {np.sum(latched)} cases whose "
            f"wings both latch will flip: every {g3(minutes[0])} min at {g3(rates[0])} rpm, "
            f"every {g3(minutes[1])} min at {g3(rates[1])} rpm and every "
            f"{g3(minutes[2])} min at {g3(rates[2])} rpm; at {g3(rates[0])} rpm "
            f"{within if within else 'none'} of them flip"
            f"{'s' if not within else ''} within the profile's {g3(np.max(c['end_time']))} s. "
            f"{np.sum(calm)} of the {n} cases ({g3(100.0 * np.sum(calm) / n)} %) do not "
            f"tumble, and {np.sum(calm & ~latched)} of those are failures that left a wing "
            f"unlatched")


def _outcomes(c):
    """"flipping 194, bounded 121, ..." of a sweep's cases."""
    return ", ".join(f"{k} {v}" for k, v in zip(*np.unique(c["outcome"], return_counts=True)))


# ---- sweeps/smallsat_duration_spin.yaml ----

def duration_findings(runs):
    c = runs.sweep("sweeps/smallsat_duration_spin.yaml")
    n = c["outcome"].size
    rpm = c["spin_rate"] * RPM
    flipped = c["flip_count"] > 0
    never = rpm[~flipped]
    # Flips after the deployment's end (a fast spin may flip while the wings still move).
    late = flipped & (c["first_flip_after_deploy"] > 0)
    after = c["first_flip_after_deploy"][late] * rpm[late]
    half = c["predicted_flip_half_period"][~flipped] / 60.0
    return (f"{n} cases; outcomes: {_outcomes(c)}; final momentum cone {g3(np.min(c['final_cone_angle']) * DEG)}"
            f" deg and more; `will_flip` = 1 in {np.sum(c['will_flip'] == 1)} of {n}. The "
            f"time from the deployment's end to the first flip, times the spin rate, lies in "
            f"{g3(after.min())}-{g3(after.max())} s rpm ({np.sum(flipped & ~late)} cases flip "
            f"while the wings still move); no case flips within the profile at "
            f"{g3(never.max()) if never.size else 'no'} rpm and below, where the craft flips "
            f"every {g3(half.min()) if half.size else '-'}-{g3(half.max()) if half.size else '-'}"
            f" min after the deployment")


# ---- sweeps/minor_axis_damper_spin.yaml ----

def damper_findings(runs):
    c = runs.sweep("sweeps/minor_axis_damper_spin.yaml")
    n = c["outcome"].size
    d = c["damping"] if "damping" in c else c[[k for k in c if k.startswith("damping")][0]]
    t = c["time_to_tumble"]
    weak = t[d == d.min()]
    ds = np.unique(d)
    fastest = [np.median(t[d == x]) for x in ds]
    best = ds[int(np.nanargmin(fastest))]
    return (f"{n} cases; outcomes: {_outcomes(c)}; time to tumble {g3(np.nanmin(t))} s to "
            f"{g3(np.nanmax(t) / 3600.0)} h ({g3(np.nanmin(weak) / 3600.0)}-"
            f"{g3(np.nanmax(weak) / 3600.0)} h at {g3(d.min())} N m s/rad); the median is "
            f"shortest at {g3(best)} N m s/rad ({g3(np.nanmin(fastest))} s) and "
            f"{g3(fastest[-1])} s at {g3(ds[-1])} N m s/rad")


GENERATORS = {
    "main-job-output": main_job_output,
    "main-job-verdict": main_job_verdict,
    "dual-spin-rotor-verdict": dual_spin_rotor_verdict,
    "three-stage-attitude-offset": three_stage_attitude_offset,
    "spring-sweep-answer": spring_answer,
    "spring-sweep-table": spring_table,
    "spring-sweep-tumble": spring_tumble,
    "duration-sweep-findings": duration_findings,
    "damper-sweep-findings": damper_findings,
}


def comparable(text):
    return WALL.sub("<wall> s wall", text)


def process(runs, update):
    """Rewrites (update) or compares every marked passage; returns the differences."""
    problems = []
    for rel in DOCS:
        path = os.path.join(ROOT, rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()

        def replace(m):
            name, old = m.group(1), m.group(2)
            if name not in GENERATORS:
                problems.append(f"{rel}: unknown passage '{name}' (known: {', '.join(GENERATORS)})")
                return m.group(0)
            new = GENERATORS[name](runs)
            if comparable(new) != comparable(old):
                problems.append(f"{rel}: passage '{name}' differs from the run:\n  document: "
                                f"{old.strip()[:400]}\n  run:      {new.strip()[:400]}")
            return f"<!-- published:{name} -->{new}<!-- /published:{name} -->"

        new_text = MARK.sub(replace, text)
        if update and new_text != text:
            tmp = path + ".tmp"
            with open(tmp, "w", encoding="utf-8") as f:
                f.write(new_text)
            os.chmod(tmp, os.stat(path).st_mode & 0o777)
            os.replace(tmp, path)
            print(f"updated {rel}")
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("binary")
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--update", action="store_true")
    mode.add_argument("--check", action="store_true")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        try:
            problems = process(Runs(os.path.abspath(a.binary), tmp), a.update)
        except RuntimeError as e:
            print(f"published.py: error: {e}", file=sys.stderr)
            return 1
    unknown = [p for p in problems if "unknown passage" in p]
    if a.check or unknown:
        for p in (problems if a.check else unknown):
            print(p, file=sys.stderr)
        if problems if a.check else unknown:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
