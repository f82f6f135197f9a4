#!/usr/bin/python3
"""Writes the answers README.md and docs/ publish about shipped runs and sweeps, from
those runs, so that a document never states a number the run does not give.

Usage: /usr/bin/python3 tools/published.py BIN [--update] [--check] [--runs DIR]
  BIN       the deploysim command (build/release/bin/deploysim)
  --update  rewrite every marked passage of README.md and docs/*.md from the runs
  --check   exit 1, naming each passage, where a document differs from the runs
  --runs    take the shipped profiles' plain runs (simulate, analyze --json) from DIR,
            written by tools/shipped_runs.py with the same BIN (the test suite does so)
  --only NAMES / --except NAMES
            the passages named (comma-separated) or all others (the test suite checks the
            Explorer-1-like example's 6900 s run, the one long run, as a test of its own)

A marked passage is the text between `<!-- published:NAME -->` and
`<!-- /published:NAME -->` (inline or over several lines); NAME is one of the GENERATORS
below. Wall-clock figures ("0.0183 s wall") are neither compared nor rewritten: a passage
that differs only in them is left as it is. The runs take about 10-20 s (the three
shipped sweeps, a few profiles and variants of them).
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

from shipped_runs import ShippedRuns

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


def e(x, digits=2):
    """A small figure in e-notation to this many significant digits: 2.6e-4."""
    m, x_exp = f"{x:.{digits - 1}e}".split("e")
    return f"{m}e{int(x_exp)}"


class Runs:
    """The runs the passages quote, each run once, in a temporary folder."""

    def __init__(self, binary, tmp, shipped=None):
        self.binary, self.tmp, self.cache = binary, tmp, {}
        if shipped:   # tools/shipped_runs.py's runs: the plain run of each shipped profile
            for profile in shipped.runs:
                files = shipped.get(profile)
                self.cache[("simulate", profile, ())] = (shipped.stdout(profile), files["h5"])
                self.cache[("analyze", profile)] = shipped.analyzed(profile)

    def _run(self, *args):
        r = subprocess.run([self.binary, *args], cwd=ROOT, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"deploysim {' '.join(args)}: exit {r.returncode}: {r.stderr}")
        return r.stdout

    def _h5_name(self, profile, opts):
        key = ("simulate", profile, opts)
        name = os.path.join(self.tmp, f"{len(self.cache)}_{os.path.basename(profile)}.h5")
        return key, name

    def simulate(self, profile, *opts):
        """What `deploysim simulate PROFILE [OPTS]` prints (its trajectory file: h5())."""
        key, out = self._h5_name(profile, opts)
        if key not in self.cache:
            self.cache[key] = (self._run("simulate", profile, *opts, "-o", out), out)
        return self.cache[key][0]

    def h5(self, profile, *opts):
        """The trajectory file of `deploysim simulate PROFILE [OPTS]`."""
        self.simulate(profile, *opts)
        return self.cache[("simulate", profile, opts)][1]

    def prefetch(self, runs):
        """Runs several (profile, *opts) simulations at once (the slow ones), so that
        h5() finds them done."""
        procs = []
        for profile, *opts in runs:
            key, out = self._h5_name(profile, tuple(opts))
            if key in self.cache:
                continue
            self.cache[key] = None
            args = ["simulate", profile, *opts, "-o", out]
            procs.append((key, out, args, subprocess.Popen(
                [self.binary, *args], cwd=ROOT, stdout=subprocess.PIPE,
                stderr=subprocess.PIPE, text=True)))
        for key, out, args, proc in procs:
            stdout, stderr = proc.communicate()
            if proc.returncode != 0:
                raise RuntimeError(f"deploysim {' '.join(args)}: exit {proc.returncode}: {stderr}")
            self.cache[key] = (stdout, out)

    def analyze_json(self, profile):
        key = ("analyze", profile)
        if key not in self.cache:
            self.cache[key] = json.loads(self._run("analyze", profile, "--json"))
        return self.cache[key]

    def write(self, name, text):
        """A file of this text in the temporary folder (a variant of a shipped input)."""
        path = os.path.join(self.tmp, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

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


# ---- docs/design.md: the linearization and its textbook estimates ----

DUAL_SPIN_ROTOR = "deployment_profiles/dual_spin_rotor.yaml"
FLAT_SPIN = "deployment_profiles/minor_axis_flat_spin.yaml"


def quasi_rigid_rates(runs):
    """The quasi-rigid energy-sink rate against the linear rate (analyze --json)."""
    a = runs.analyze_json(DUAL_SPIN_ROTOR)["outcome"]["linear"]
    b = runs.analyze_json(FLAT_SPIN)["outcome"]["linear"]
    return (f"On `dual_spin_rotor.yaml` {g3(a['quasi_rigid_rate'])} 1/s against the linear "
            f"{g3(a['growth_rate'])} 1/s; on `minor_axis_flat_spin.yaml` "
            f"{g3(b['quasi_rigid_rate'])} against {g3(b['growth_rate'])}")


def dual_spin_rotor_disagreement(runs):
    """What the headline says where the rigid-body rule and the linearization disagree."""
    return runs.analyze_json(DUAL_SPIN_ROTOR)["outcome"]["disagreement"]


def _outcome_only(runs, profile, damping):
    """The outcome-only record of a profile: a sweep of one case that sets the damper to
    the profile's own coefficient (a sweep takes no samples)."""
    stem = os.path.splitext(os.path.basename(profile))[0]
    path = runs.write(f"one_case_{stem}.yaml",
                      f"name: one_case_{stem}\nbase: {os.path.join(ROOT, profile)}\n"
                      f"grid:\n  - {{parameter: damping, values: [{damping!r}]}}\n")
    c = runs.sweep(path)
    return float(c["nutation_rate"][0])


def outcome_only_fits(runs):
    """The envelope's fitted rate from the samples (analyze) and from the steps (a sweep
    case): their relative difference, and the larger distance of the two from the linear
    rate, on dual_spin_rotor and minor_axis_flat_spin."""
    diff, off, peaks = [], [], None
    for profile, damping in ((DUAL_SPIN_ROTOR, 0.5), (FLAT_SPIN, 1.0)):
        o = runs.analyze_json(profile)["outcome"]
        sampled, linear = o["trend"]["rate"], o["linear"]["growth_rate"]
        steps = _outcome_only(runs, profile, damping)
        diff.append(abs(steps - sampled) / abs(sampled))
        off.append(max(abs(sampled - linear), abs(steps - linear)) / abs(linear))
        peaks = o["trend"]["points"]
    return (f"the fitted rates differ by {e(diff[0])} (`dual_spin_rotor`) and {e(diff[1])} "
            f"(`minor_axis_flat_spin`, {peaks} peaks), relative, and lie within {e(off[0])} "
            f"and {e(off[1])} of the linear rate")


# ---- docs/geometry.md ----

WING_NUT = "deployment_profiles/wing_nut.yaml"
SEED_PROFILES = (WING_NUT, "deployment_profiles/seed_limit_j2_to_j1.yaml",
                 "deployment_profiles/seed_limit_j2_to_j3.yaml")
SEED_SCHEME = ("--method", "thesis-euler", "--step", "2e-05")   # plot_seed_figures' default
SEED_RK4 = ("--method", "rk4", "--step", "0.001")


def _plot_geometry():
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import plot_geometry
    return plot_geometry


def wing_nut_min_radicand(runs):
    """plot_geometry.min_radicand over the wing nut's family of polhodes (the run's
    principal moments)."""
    g = _plot_geometry()
    J = g.read_trajectory(runs.h5(WING_NUT))["J"]
    g.min_radicand[0] = np.inf
    for d in g.dbar_family(J):
        g.polhode(J, d)
    return g3(g.min_radicand[0])


def geometry_run_dbar(runs):
    """dbar of the wing nut's run and of the main job's last stage, as plot_geometry
    puts them in its legend, and which side of the separatrix that is."""
    g = _plot_geometry()
    wn, mj = g.read_trajectory(runs.h5(WING_NUT)), g.read_trajectory(runs.h5(MAIN_JOB))
    side = {True: "inside the separatrix, around the minor axis",
            False: "outside the separatrix, around the major axis"}
    if (wn["dbar"] < 1) != (mj["dbar"] < 1):
        raise RuntimeError("geometry-run-dbar: the two runs lie on different sides")
    flips = [len(runs.analyze_json(p)["flip_times"]) for p in (WING_NUT, MAIN_JOB)]
    return (f"The wing nut (`dbar = {wn['dbar']:.8f}`) and the main job's last stage "
            f"(`{mj['name']}`, `dbar = {mj['dbar']:.4f}`) both run just {side[wn['dbar'] < 1]}"
            f": they flip ({flips[0]} and {flips[1]} times)")


def _seed_runs(runs):
    runs.prefetch([(p, *SEED_SCHEME) for p in SEED_PROFILES] +
                  [(p, *o) for p in SEED_PROFILES for o in (SEED_RK4, ("--method", "exact"))])


def _H_B(path):
    with h5py.File(path, "r") as f:
        return f["H_B"][()]


def seed_h_growth(runs):
    """How much |H| grows over the run under the seed's explicit Euler at h = 2e-5 s."""
    _seed_runs(runs)
    growth = []
    for p in SEED_PROFILES:
        n = np.linalg.norm(_H_B(runs.h5(p, *SEED_SCHEME)), axis=1)
        growth.append(n[-1] / n[0] - 1.0)
    return (f"by {e(growth[0])} (wing nut), {e(growth[1])} (J2 → J1) and {e(growth[2])} "
            f"(J2 → J3)")


def seed_rk4_difference(runs):
    """rk4 at h = 1e-3 s against the closed form on the three seed profiles: the largest
    difference of H1, H2, H3 or |H|, relative to the largest |H| (as the test measures)."""
    _seed_runs(runs)
    worst = 0.0
    for p in SEED_PROFILES:
        a, b = _H_B(runs.h5(p, *SEED_RK4)), _H_B(runs.h5(p, "--method", "exact"))
        na, nb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
        worst = max(worst, max(np.abs(a - b).max(), np.abs(na - nb).max()) / nb.max())
    return e(worst)


# ---- docs/viewer.md ----

def _scene():
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    import deploysim_scene
    return deploysim_scene


def viewer_page_size(runs):
    """The size of the main job's viewer page (deploysim view)."""
    page = os.path.join(runs.tmp, "main_job.html")
    if not os.path.exists(page):
        runs._run("view", runs.h5(MAIN_JOB), "-o", page)
    return f"{os.path.getsize(page) / 1e6:.1f} MB"


def viewer_decimation(runs):
    """The samples the viewer keeps of the main job, and how far the attitude it draws
    between them strays from any sample (deploysim_scene.decimate, interpolation_error)."""
    s = _scene()
    r = s.read_run(runs.h5(MAIN_JOB))
    idx = s.decimate(r)
    err = np.degrees(s.interpolation_error(r, idx))
    return (f"keeps {len(idx)} of {len(r['time'])} samples, and the attitude drawn between "
            f"them is within {err:.2f}°")


def viewer_inertia_match(runs):
    """The drawn boxes' inertia against /J_B at every 7th sample of the main job (the
    viewer test's check), relative."""
    s = _scene()
    r = s.read_run(runs.h5(MAIN_JOB))
    worst = 0.0
    for i in range(0, len(r["time"]), 7):
        J, _ = r["geometry"].inertia(r["hinge"][i])
        worst = max(worst, np.abs(J - r["J"][i]).max() / np.abs(r["J"][i]).max())
    return e(worst, 1)


# ---- docs/file_formats.md ----

def spring_example_spin(runs):
    """|w| when the second wing is released: what the first wing left of the spin."""
    with h5py.File(runs.h5(MAIN_JOB), "r") as f:
        t, w = f["time"][()], f["w_NB_B"][()]
        kind = [k.decode() if isinstance(k, bytes) else k for k in f["events/hinge/kind"][()]]
        release = f["events/hinge/time"][()][[i for i, k in enumerate(kind) if k == "release"]]
    i = int(np.searchsorted(t, release[1], side="right")) - 1   # the last sample before it
    return f"{np.linalg.norm(w[i]) * RPM:.1f} rpm"


def spring_example_no_damper(runs):
    """The latch-up rates of the main job with the dampers taken out (a variant written
    to the temporary folder, the model by its full path)."""
    import yaml
    with open(os.path.join(ROOT, MAIN_JOB), encoding="utf-8") as f:
        p = yaml.safe_load(f)
    p["model"] = os.path.normpath(os.path.join(ROOT, os.path.dirname(MAIN_JOB), p["model"]))
    for h in p["hinges"].values():
        h["free"].pop("damper", None)
    path = runs.write("no_damper.yaml", yaml.safe_dump(p))
    rates = [abs(ev["rate_before"]) * DEG for ev in runs.analyze_json(path)["hinge_events"]
             if ev["kind"] == "latch"]
    return " and ".join(f"{r:.0f}" for r in rates) + " deg/s"


def asymmetric_energy_gap(runs):
    """The largest relative difference of /energy_rigid from /energy in the asymmetric
    example (exact coupling, the panels moving)."""
    with h5py.File(runs.h5("deployment_profiles/asymmetric_sat_deploy.yaml"), "r") as f:
        t, r = f["energy"][()], f["energy_rigid"][()]
    return f"{100.0 * np.max(np.abs(t - r) / t):.0f} %"


# ---- appendages (docs/appendages.md) ----

EXPLORER = "examples/long/explorer1.yaml"


def explorer_verdict(runs):
    """The Explorer-1-like example's verdict (the 45-degree time beside the linear
    prediction) and its energy ledger, as `deploysim simulate` prints them."""
    text = runs.simulate(EXPLORER)
    lines = [x for x in text.splitlines()
             if x.startswith("verdict: ") or x.startswith("energy ledger: ")
             or x.strip().startswith("linear stability of the steady spin:")]
    return "\n```\n" + "\n".join(lines) + "\n```\n"


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
    "quasi-rigid-rates": quasi_rigid_rates,
    "dual-spin-rotor-disagreement": dual_spin_rotor_disagreement,
    "outcome-only-fits": outcome_only_fits,
    "wing-nut-min-radicand": wing_nut_min_radicand,
    "geometry-run-dbar": geometry_run_dbar,
    "seed-h-growth": seed_h_growth,
    "seed-rk4-difference": seed_rk4_difference,
    "viewer-page-size": viewer_page_size,
    "viewer-decimation": viewer_decimation,
    "viewer-inertia-match": viewer_inertia_match,
    "spring-example-spin": spring_example_spin,
    "spring-example-no-damper": spring_example_no_damper,
    "asymmetric-energy-gap": asymmetric_energy_gap,
    "explorer-verdict": explorer_verdict,
}


def comparable(text):
    return WALL.sub("<wall> s wall", text)


def process(runs, update, wanted=None):
    """Rewrites (update) or compares every marked passage (or those named in wanted);
    returns the differences."""
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
            if wanted is not None and name not in wanted:
                return m.group(0)
            new = GENERATORS[name](runs)
            if comparable(new) == comparable(old):
                return m.group(0)   # a new wall-clock time alone does not rewrite a document
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
    ap.add_argument("--runs", metavar="DIR")
    pick = ap.add_mutually_exclusive_group()
    pick.add_argument("--only", metavar="NAMES")
    pick.add_argument("--except", dest="skip", metavar="NAMES")
    a = ap.parse_args()
    wanted = None
    if a.only or a.skip:
        names = set((a.only or a.skip).split(","))
        unknown = sorted(names - set(GENERATORS))
        if unknown:
            print(f"published.py: error: unknown passage(s) {', '.join(unknown)} "
                  f"(known: {', '.join(GENERATORS)})", file=sys.stderr)
            return 1
        wanted = names if a.only else set(GENERATORS) - names
    with tempfile.TemporaryDirectory() as tmp:
        try:
            shipped = ShippedRuns(a.binary, a.runs) if a.runs else None
            problems = process(Runs(os.path.abspath(a.binary), tmp, shipped), a.update, wanted)
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
