#!/usr/bin/python3
"""The 3D viewer (tools/view.py) and the animation (tools/animate.py).

Usage: viewer_test.py DEPLOYSIM SOURCE_DIR ARTEFACT_DIR
Runs deploysim on deployment_profiles/smallsat_spring_deploy.yaml (and wing_nut.yaml, and
a short cross-check), writes the pages and a short MP4, and checks them in Debian's
headless Chromium with no network: the event list and its jumps, the playback slowing
down around events, the fading trail, the layout at 1024x640 and 1920x1080, the files'
modes. Screenshots and pages are kept in ARTEFACT_DIR (look at them: spring_t30.png before
the release, spring_t200.png mid-flip, spring_WxH_swing.png during the first wing's swing,
spring_WxH_after.png after the deployment, crosscheck_WxH.png).
"""
import json
import math
import os
import pathlib
import re
import subprocess
import sys
import time
import unittest

import h5py
import numpy as np

DEPLOYSIM, SRC, ART = None, None, None
PY = "/usr/bin/python3"

# Named tolerances and limits.
INERTIA_REL_TOL = 1e-12      # drawn boxes vs /J_B (measured 3e-16: the same formulas)
MAX_PAGE_BYTES = 5_000_000   # the main job's page under 5 MB
# The 2 s opening target is a benchmark row (bench/pages_bench.py), not a timed test.
MIN_CHANGED_FRACTION = 0.02  # of the pixels around the body between two times
MIN_SCENE_STDDEV = 0.02      # grey-level spread of a scene that is not blank (0..1)
MAX_DRAWN_ATTITUDE_ERROR_DEG = 0.5   # slerp between kept samples vs every sample (0.04)


# Layouts the page must fit (screenshots of each).
SIZES = ((1024, 640), (1920, 1080))
MAX_TRAIL_FRACTION = 0.5     # trail pixels of the default fading trail vs the whole run's


def run(*args, umask=None, **kw):
    pre = (lambda: os.umask(umask)) if umask is not None else None
    return subprocess.run([str(a) for a in args], capture_output=True, text=True,
                          preexec_fn=pre, **kw)


def mode(path):
    return os.stat(path).st_mode & 0o777


def open_at(browser, path, size):
    """Opens path in a tab of the given size (width, height)."""
    browser.width, browser.height = size
    return browser.open(pathlib.Path(path).as_uri())


# A layout check in the page: every box that must stay inside its panel, and whether the
# side panel and the bar below the 3D view hold their content without scrolling.
LAYOUT_JS = """(() => {
  const r = (e) => e.getBoundingClientRect();
  const inside = (a, b) => a.left >= b.left - 0.5 && a.right <= b.right + 0.5 &&
                           a.top >= b.top - 0.5 && a.bottom <= b.bottom + 0.5;
  const side = document.getElementById('side'), bar = document.getElementById('bar');
  const out = [];
  for (const c of side.querySelectorAll('canvas'))
    if (c.offsetParent && !inside(r(c), r(side))) out.push(c.id + ' leaves the side panel');
  for (const c of bar.querySelectorAll('canvas, input, select, button'))
    if (!inside(r(c), r(bar))) out.push((c.id || c.tagName) + ' leaves the bar');
  for (const e of [side, bar])
    if (e.scrollWidth > e.clientWidth + 1) out.push(e.id + ' overflows sideways');
  for (const e of [side, bar, document.getElementById('view')])
    if (!inside(r(e), {left: 0, top: 0, right: innerWidth, bottom: innerHeight}))
      out.push(e.id + ' leaves the window');
  if (side.scrollHeight > side.clientHeight + 1) out.push('side panel scrolls');
  return out;
})()"""


def load_png(path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    return mpimg.imread(str(path))[..., :3]


class ViewerTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        sys.path.insert(0, str(SRC / "tools"))
        import headless_chromium
        import deploysim_scene
        cls.hc, cls.scene = headless_chromium, deploysim_scene
        ART.mkdir(parents=True, exist_ok=True)
        cls.h5 = ART / "spring.h5"
        cls.html = ART / "spring.html"
        r = run(DEPLOYSIM, "simulate", SRC / "deployment_profiles/smallsat_spring_deploy.yaml",
                "-q", "-o", cls.h5)
        assert r.returncode == 0, r.stderr
        r = run(PY, SRC / "tools/view.py", cls.h5, "-o", cls.html)
        assert r.returncode == 0, r.stderr
        cls.browser = headless_chromium.Browser(1280, 800)

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()

    def test_drawn_body_has_the_simulated_inertia(self):
        """The boxes at the file's hinge angles have the file's J_B about the system CoM."""
        r = self.scene.read_run(str(self.h5))
        worst = 0.0
        for i in range(0, len(r["time"]), 7):
            J, _ = r["geometry"].inertia(r["hinge"][i])
            worst = max(worst, np.abs(J - r["J"][i]).max() / np.abs(r["J"][i]).max())
        print(f"\n  drawn body vs /J_B: max relative difference {worst:.2e}")
        self.assertLess(worst, INERTIA_REL_TOL)
        # The panels do swing: the inertia changes from closed to open.
        self.assertGreater(np.abs(r["J"][0] - r["J"][-1]).max(), 1.0)

    def test_decimation_keeps_what_the_eye_needs(self):
        """The attitude the page draws between kept samples (slerp) is within half a
        degree of every sample; the hinge events' swings are kept."""
        r = self.scene.read_run(str(self.h5))
        idx = self.scene.decimate(r)
        err = np.degrees(self.scene.interpolation_error(r, idx))
        print(f"\n  kept {len(idx)} of {len(r['time'])} samples; drawn attitude within "
              f"{err:.3f} deg of every sample")
        self.assertLess(err, MAX_DRAWN_ATTITUDE_ERROR_DEG)
        self.assertLess(len(idx), len(r["time"]) // 2)
        steps = np.abs(np.diff(r["hinge"][idx], axis=0)).max()
        self.assertLessEqual(steps, np.radians(1.0) + np.abs(np.diff(r["hinge"], axis=0)).max())

    def test_page_offline_no_errors_and_moving_body(self):
        size = self.html.stat().st_size
        page = open_at(self.browser, self.html, (1280, 800))
        self.assertTrue(page.evaluate("window.deploysimReady === true"))
        # Self-contained: the page fetched nothing (no script, style, image or data file).
        self.assertEqual(page.evaluate("performance.getEntriesByType('resource').length"), 0)
        ready = page.evaluate("window.deploysimReadyMs") / 1000
        print(f"\n  page {size / 1e6:.2f} MB; load event {page.load_seconds:.3f} s, "
              f"scene drawn {ready:.3f} s")
        self.assertLess(size, MAX_PAGE_BYTES)
        info = page.evaluate("window.deploysimInfo")
        self.assertEqual(info["sides"], 1)
        # The verdict line is the file's outcome record's headline.
        with h5py.File(self.h5, "r") as f:
            attr = f.attrs["outcome"]
            headline = json.loads(attr.decode() if isinstance(attr, bytes) else attr)["headline"]
        self.assertEqual(page.evaluate("document.getElementById('verdict').textContent"),
                         "verdict: " + headline)
        self.assertEqual(info["parts"], ["hub", "wing_plus_x", "wing_minus_x"])
        self.assertEqual(info["flips"], [4])
        shots = {}
        for t in (30.0, 200.0):
            self.assertAlmostEqual(page.evaluate(f"window.deploysimSetTime({t})"), t)
            shots[t] = page.screenshot(ART / f"spring_t{t:g}.png")
        self.assertEqual(page.errors(), [])
        a, b = load_png(shots[30.0]), load_png(shots[200.0])
        # The 3D view is the upper left part; the body sits in the middle of it.
        view_w = page.evaluate("document.getElementById('view').clientWidth")
        view_h = page.evaluate("document.getElementById('view').clientHeight")
        a, b = a[:view_h], b[:view_h]
        for img in (a, b):
            self.assertGreater(img[:, :view_w].std(), MIN_SCENE_STDDEV, "blank scene")
        h, w = a.shape[:2]
        box = (slice(h // 4, 3 * h // 4), slice(view_w // 4, 3 * view_w // 4))
        changed = (np.abs(a[box] - b[box]).max(axis=2) > 0.1).mean()
        print(f"  pixels changed around the body between t = 30 s and 200 s: {changed:.1%}")
        self.assertGreater(changed, MIN_CHANGED_FRACTION)

    def test_crosscheck_side_by_side(self):
        cc = ART / "spring_crosscheck.h5"
        r = run(DEPLOYSIM, "crosscheck", SRC / "deployment_profiles/smallsat_spring_deploy.yaml",
                "--until", "90", "-o", cc)
        self.assertEqual(r.returncode, 0, r.stderr)
        out = ART / "spring_crosscheck.html"
        r = run(PY, SRC / "tools/view.py", cc, "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        page = open_at(self.browser, out, (1280, 800))
        self.assertTrue(page.evaluate("window.deploysimReady === true"))
        self.assertEqual(page.evaluate("window.deploysimInfo.sides"), 2)
        page.evaluate("window.deploysimSetTime(68)")
        page.screenshot(ART / "spring_crosscheck_t68.png")
        self.assertEqual(page.errors(), [])
        img = load_png(ART / "spring_crosscheck_t68.png")
        view_w = page.evaluate("document.getElementById('view').clientWidth")
        view_h = page.evaluate("document.getElementById('view').clientHeight")
        left, right = img[:view_h, : view_w // 2], img[:view_h, view_w // 2: view_w]
        self.assertGreater(left.std(), MIN_SCENE_STDDEV)   # a body on each side
        self.assertGreater(right.std(), MIN_SCENE_STDDEV)
        # The stage band is filled (derived from the motion: before, during and after the
        # hinges move), and the file's maxima are printed with units and three digits.
        stages = page.evaluate("window.deploysimInfo.stages")
        self.assertEqual(stages, 3)
        with h5py.File(cc, "r") as f:
            att = float(f.attrs["max_attitude_difference"])
            rel = float(f.attrs["max_H_B_relative_difference"])
            dflip = float(f.attrs["max_flip_time_difference"])
        foot = page.evaluate("document.getElementById('foot').innerText")
        self.assertIn(f"largest attitude difference: {math.degrees(att):.3g} deg", foot)
        self.assertIn(f"largest |H_B difference| / |H_B(t0)|: {rel:.3g}", foot)
        self.assertIn(f"largest flip-time difference: {dflip:.3g} s", foot)
        self.assertIsNone(re.search(r"\d\.\d{4,}", foot), foot)   # no raw full-precision number
        # The hinges' motion is in the event list (the file has no hinge event table), and
        # slows the playback down.
        kinds = page.evaluate("window.deploysimEvents.map((e) => e.kind)")
        self.assertEqual(kinds.count("moves"), 2)
        self.assertEqual(kinds.count("halts"), 2)
        self.assertLess(page.evaluate("window.deploysimRate(61)"),
                        page.evaluate("window.deploysimState().speed"))

    def test_event_list_and_jump_to(self):
        """Every hinge event, flip and the transition of the file is in the list; a click
        on a row jumps to a little before its event."""
        page = open_at(self.browser, self.html, (1280, 800))
        events = page.evaluate("window.deploysimEvents")
        with h5py.File(self.h5, "r") as f:
            ht = f["events/hinge/time"][()]
            hk = [k.decode() if isinstance(k, bytes) else k for k in f["events/hinge/kind"][()]]
            flips = f["events/flip_time"][()]
            o = f.attrs["outcome"]
            outcome = json.loads(o.decode() if isinstance(o, bytes) else o)
        self.assertGreaterEqual(len(ht), 4)          # two releases, two latches
        listed = [(e["t"], e["kind"]) for e in events]
        for t, k in zip(ht, hk):
            if k != "stop":   # a stop impact may be folded into its burst's row
                self.assertIn((round(float(t), 6), k), listed)
        self.assertEqual([e["t"] for e in events if e["kind"] == "flip"],
                         [round(float(x), 6) for x in flips])
        self.assertEqual(sum(e["kind"] == "transition" for e in events),
                         0 if outcome["transition_time"] is None else 1)
        self.assertEqual([e["t"] for e in events], sorted(e["t"] for e in events))
        self.assertEqual(page.evaluate("document.querySelectorAll('#events .ev').length"),
                         len(events))
        lead = page.evaluate("window.deploysimState().jumpLead")
        self.assertGreater(lead, 0)
        for i, e in enumerate(events):
            page.evaluate("window.deploysimSetTime(0)")
            # The click and the read-out in one task: no animation frame runs between them.
            st = page.evaluate(f"(document.querySelectorAll('#events .ev')[{i}].click(), "
                               "window.deploysimState())")
            self.assertAlmostEqual(st["t"], max(e["t"] - lead, 0.0), places=9, msg=e)
            self.assertTrue(st["playing"])
            now = page.evaluate("document.getElementById('now').textContent")
            self.assertTrue(now.startswith(f"t = {max(e['t'] - lead, 0.0):.2f} s"), now)
            self.assertAlmostEqual(page.evaluate(f"window.deploysimJump({i})"), st["t"])
        # The time axis of the charts: the deployment button shows the hinges' swings
        # (releases and latches inside), the whole-run button all of it.
        view = page.evaluate("(document.getElementById('zoomDep').click(), "
                             "window.deploysimState().view)")
        self.assertLess(view[1] - view[0], 0.1 * (events[-1]["t"] - events[0]["t"]))
        for e in events:
            if e["kind"] in ("release", "latch"):
                self.assertTrue(view[0] < e["t"] < view[1], (view, e))
        view = page.evaluate("(document.getElementById('zoomAll').click(), "
                             "window.deploysimState().view)")
        self.assertEqual(view, [page.evaluate("window.deploysimInfo.t0"),
                                page.evaluate("window.deploysimInfo.t1")])
        self.assertEqual(page.errors(), [])

    def test_playback_slows_down_near_events(self):
        page = open_at(self.browser, self.html, (1280, 800))
        with h5py.File(self.h5, "r") as f:
            release = float(f["events/hinge/time"][0])
            flips = f["events/flip_time"][()]
        st = page.evaluate("window.deploysimState()")
        base = st["speed"]
        self.assertTrue(st["slowDown"])
        # The default speed plays the 600 s run in about a minute, not 20x.
        self.assertEqual(base, 10)
        self.assertAlmostEqual(page.evaluate(f"window.deploysimRate({release})"), 1.0)
        quiet = (release + flips[0]) / 2
        self.assertAlmostEqual(page.evaluate(f"window.deploysimRate({quiet})"), base)
        # Easing: in between on the way into the event, the rate never rises towards it.
        ts = np.linspace(release - 8, release, 33)
        rates = page.evaluate("[" + ",".join(f"window.deploysimRate({t})" for t in ts) + "]")
        self.assertTrue(all(a >= b - 1e-12 for a, b in zip(rates, rates[1:])), rates)
        self.assertTrue(any(1.0 < r < base for r in rates), rates)
        # The playback itself: one real second near the release plays about one simulated
        # second, away from events `base` seconds.
        page.evaluate(f"window.deploysimSetTime({release - 0.5})")
        near = page.evaluate("window.deploysimAdvance(1)") - (release - 0.5)
        page.evaluate(f"window.deploysimSetTime({quiet})")
        far = page.evaluate("window.deploysimAdvance(1)") - quiet
        print(f"\n  one real second of playback: {near:.3f} s at the release, {far:.3f} s "
              "away from events")
        self.assertAlmostEqual(near, 1.0, places=6)
        self.assertAlmostEqual(far, base, places=6)
        # Turned off, the playback keeps its speed through the event.
        page.evaluate("(() => { const c = document.getElementById('slow'); c.click(); })()")
        self.assertFalse(page.evaluate("window.deploysimState().slowDown"))
        self.assertAlmostEqual(page.evaluate(f"window.deploysimRate({release})"), base)
        page.evaluate(f"window.deploysimSetTime({release - 0.5})")
        self.assertAlmostEqual(page.evaluate("window.deploysimAdvance(1)") - (release - 0.5),
                               base, places=6)
        self.assertEqual(page.errors(), [])

    def test_trail_fades(self):
        """The default trail (the last minute, fading) draws far fewer magenta pixels late
        in the run than the whole run's trail."""
        page = open_at(self.browser, self.html, (1280, 800))
        counts = {}
        for which in ("default", "whole run"):
            if which != "default":
                page.evaluate("(() => { const s = document.getElementById('trail'); "
                              "s.selectedIndex = s.options.length - 1; s.onchange(); })()")
            page.evaluate("window.deploysimSetTime(590)")
            png = page.screenshot(ART / f"spring_trail_{which.replace(' ', '_')}.png")
            w = page.evaluate("document.getElementById('view').clientWidth")
            h = page.evaluate("document.getElementById('view').clientHeight")
            img = load_png(png)[:h, :w]
            magenta = (img[..., 0] > 0.45) & (img[..., 2] > 0.45) & (img[..., 1] < 0.35)
            counts[which] = int(magenta.sum())
        print(f"\n  magenta pixels at t = 590 s: {counts}")
        self.assertLess(counts["default"], MAX_TRAIL_FRACTION * counts["whole run"])
        self.assertEqual(page.errors(), [])

    def test_layout_at_two_sizes(self):
        """Screenshots at 1024x640 and 1920x1080 (the main job during the first wing's
        swing and after the deployment, the cross-check); nothing leaves its panel."""
        cc = ART / "spring_crosscheck.h5"
        if not cc.exists():
            r = run(DEPLOYSIM, "crosscheck",
                    SRC / "deployment_profiles/smallsat_spring_deploy.yaml", "--until", "90",
                    "-o", cc)
            self.assertEqual(r.returncode, 0, r.stderr)
        cc_html = ART / "spring_crosscheck.html"
        r = run(PY, SRC / "tools/view.py", cc, "-o", cc_html)
        self.assertEqual(r.returncode, 0, r.stderr)
        for size in SIZES:
            tag = "%dx%d" % size
            page = open_at(self.browser, self.html, size)
            for t, name in ((62.0, "swing"), (200.0, "after")):
                page.evaluate(f"window.deploysimSetTime({t})")
                page.screenshot(ART / f"spring_{tag}_{name}.png")
                self.assertEqual(page.evaluate(LAYOUT_JS), [], (tag, name))
            # Every chart caption states its unit.
            caps = page.evaluate("[...document.querySelectorAll('.cap')].filter((c) => "
                                 "c.offsetParent).map((c) => c.textContent)")
            self.assertTrue(caps and all("[" in c for c in caps), caps)
            self.assertEqual(page.errors(), [])
            page.close()
            page = open_at(self.browser, cc_html, size)
            page.evaluate("window.deploysimSetTime(68)")
            page.screenshot(ART / f"crosscheck_{tag}.png")
            self.assertEqual(page.evaluate(LAYOUT_JS), [], (tag, "crosscheck"))
            self.assertEqual(page.errors(), [])
            page.close()

    def test_written_with_the_umask(self):
        """The page gets 0666 less the umask, like the HDF5 file beside it."""
        for umask, want in ((0o022, 0o644), (0o027, 0o640)):
            out = ART / f"spring_umask_{umask:03o}.html"
            out.unlink(missing_ok=True)
            r = run(PY, SRC / "tools/view.py", self.h5, "-o", out, umask=umask)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(oct(mode(out)), oct(want))
        # The HDF5 file deploysim writes under the same umask: the same mode.
        h5 = ART / "spring_umask.h5"
        r = run(DEPLOYSIM, "simulate", SRC / "deployment_profiles/smallsat_spring_deploy.yaml",
                "-q", "-o", h5, umask=0o022)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(oct(mode(h5)), oct(0o644))
        self.assertEqual(oct(mode(ART / "spring_umask_022.html")), oct(mode(h5)))

    def test_stop_bursts_are_one_row(self):
        """Stop impacts of one panel less than a second apart are one row of the list."""
        sys.path.insert(0, str(SRC / "tools"))
        import view

        def ev(t, kind, panel):
            return dict(t=t, kind=kind, panel=panel, angle=-0.0349, rate_before=0.2,
                        rate_after=-0.06, impulse=0.01)
        fake = dict(kind="trajectory", sides=[dict(label="x", flips=[9.0])], outcome=None,
                    events=[ev(1.0, "release", "a"), ev(2.0, "stop", "a"), ev(2.1, "stop", "b"),
                            ev(2.4, "stop", "a"), ev(3.3, "stop", "a"), ev(3.5, "rest", "a"),
                            ev(6.0, "stop", "a")])
        rows = view.event_list(fake)
        got = [(r["t"], r["kind"], r["panel"], r["count"], r["t_last"]) for r in rows]
        self.assertEqual(got, [(1.0, "release", "a", 1, 1.0), (2.0, "stop", "a", 3, 3.3),
                               (2.1, "stop", "b", 1, 2.1), (3.5, "rest", "a", 1, 3.5),
                               (6.0, "stop", "a", 1, 6.0), (9.0, "flip", None, 1, 9.0)])
        self.assertIn("3 stop impacts at -2.0 deg", rows[1]["text"])
        self.assertIn("11.5 deg/s", rows[1]["text"])

    def test_cli_subcommand_runs_the_tool(self):
        out = ART / "spring_cli.html"
        out.unlink(missing_ok=True)
        r = run(DEPLOYSIM, "view", self.h5, "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(out.read_bytes(), self.html.read_bytes())
        r = run(DEPLOYSIM, "view", "--help")
        self.assertEqual(r.returncode, 0)
        self.assertTrue(r.stdout.startswith("usage: deploysim view"), r.stdout[:80])
        r = run(DEPLOYSIM, "view", self.h5, "-o", self.h5)   # never over its input
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("output is the input file", r.stderr)

    def test_bad_input_one_line_nonzero_no_output(self):
        bad_text = ART / "not_hdf5.h5"
        bad_text.write_text("this is not HDF5\n")
        no_q = ART / "no_q_NB.h5"
        with h5py.File(self.h5, "r") as src, h5py.File(no_q, "w") as dst:
            for k in src.attrs:
                dst.attrs[k] = src.attrs[k]
            for k in ("time", "H_B", "J_B", "h_N", "spin_axis_angle"):
                src.copy(k, dst)
        foreign = ART / "foreign.h5"
        with h5py.File(foreign, "w") as f:
            f["x"] = np.arange(3.0)
        for path, words in ((bad_text, "not an HDF5 file"), (no_q, "/q_NB"),
                            (foreign, "not a deploysim trajectory"),
                            (ART / "missing.h5", "no such file")):
            out = ART / (path.stem + ".html")
            out.unlink(missing_ok=True)
            r = run(PY, SRC / "tools/view.py", path, "-o", out)
            self.assertEqual(r.returncode, 1, (path, r.stderr))
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
            self.assertIn(words, r.stderr)
            self.assertFalse(out.exists())
            self.assertEqual(list(ART.glob(".view-*")), [])


class AppendageViewerTest(unittest.TestCase):
    """A body with flexible appendages (tests/tools/data/soft_boom_swing.yaml: a two-plane
    and a one-plane beam, one deployed while spinning): the scene draws it from the
    file's @body, a beam as thin rods that bend as their hinges turn, a massless link not
    at all; the page groups each beam's bending hinges."""

    @classmethod
    def setUpClass(cls):
        sys.path.insert(0, str(SRC / "tools"))
        import deploysim_scene
        import view
        cls.scene, cls.view = deploysim_scene, view
        ART.mkdir(parents=True, exist_ok=True)
        cls.h5, cls.html = ART / "booms.h5", ART / "booms.html"
        r = run(DEPLOYSIM, "simulate", SRC / "tests/tools/data/soft_boom_swing.yaml", "-q",
                "-o", cls.h5)
        assert r.returncode == 0, r.stderr
        cls.run_ = deploysim_scene.read_run(str(cls.h5))

    def test_plot_draws_one_line_per_beam_and_plane(self):
        """tools/plot_trajectory.py's hinge chart groups the bending hinges as the viewer
        does: one line per beam and plane, the sum of its hinges' angles, no release of a
        generated hinge among the events; the PNG is written."""
        import plot_trajectory
        d = plot_trajectory.read(str(self.h5))
        g = plot_trajectory.hinge_lines(d)
        names, columns = self.view.hinge_channels(self.run_["geometry"])
        self.assertEqual(g["panel_names"], names)
        self.assertIn("boom_px bend 1", names)
        for i, cols in enumerate(columns):
            np.testing.assert_allclose(g["hinge_angles"][:, i],
                                       d["hinge_angles"][:, cols].sum(axis=1), rtol=0,
                                       atol=1e-15)
        owner = self.scene.bending_owners(self.run_["geometry"].appendages)
        self.assertFalse([e for e in d["events"] if e["panel"] in owner])
        out = ART / "booms_plots"
        out.mkdir(parents=True, exist_ok=True)
        plot_trajectory.plot_hinge_angles(d, str(out))
        self.assertTrue((out / "hinge_angles.png").stat().st_size > 10000)

    def test_scene_draws_the_files_body(self):
        """The parts are the file's @body panels (not the model text's, which lists none),
        and at the file's hinge angles they have the file's J_B."""
        g = self.run_["geometry"]
        with h5py.File(self.h5, "r") as f:
            body = json.loads(f.attrs["body"])
            names = [x.decode() if isinstance(x, bytes) else x for x in f["panel_names"][()]]
        self.assertEqual(g.names, names)
        self.assertEqual([p["name"] for p in body["panels"]], names)
        kinds = g.part_kinds
        self.assertEqual(kinds.count("link"), 6)               # boom_px: one per joint
        self.assertEqual(kinds.count("beam"), 2 + 6 + 6)       # stubs and segments
        self.assertEqual([a["name"] for a in g.appendages], ["boom_px", "boom_mx"])
        r, worst = self.run_, 0.0
        for i in range(0, len(r["time"]), 13):
            J, _ = g.inertia(r["hinge"][i])
            worst = max(worst, np.abs(J - r["J"][i]).max() / np.abs(r["J"][i]).max())
        print(f"\n  drawn body with appendages vs /J_B: max relative difference {worst:.2e}")
        self.assertLess(worst, INERTIA_REL_TOL)

    def test_a_bent_beam_is_posed_as_its_hinges_say(self):
        """boom_mx (one plane, along -x, bending about y) with every bending hinge at a:
        rod k (k hinges from the root) points along Rot(y, k a) (-x), and each rod starts
        where the one before ends (a continuous beam of the beam's length)."""
        g = self.run_["geometry"]
        a = math.radians(8.0)
        app = next(x for x in g.appendages if x["name"] == "boom_mx")
        angles = np.zeros(len(g.names))
        angles[app["hinges"]] = a
        poses = g.poses(angles)
        rods = [app["root"]] + app["hinges"]             # stub, then the segments
        ends = []
        for k, panel in enumerate(rods):
            c, R, d = poses[1 + panel]                    # part 0 is the hub
            axis = R[:, 0]
            want = self.scene.axis_angle_matrix([0, 1, 0], k * a) @ np.array([-1.0, 0, 0])
            self.assertLess(np.linalg.norm(axis - want), 1e-12, f"rod {k}")
            self.assertAlmostEqual(d[1], 0.02, places=12)  # 2 x radius
            ends.append((c - d[0] / 2 * axis, c + d[0] / 2 * axis))
        for k in range(1, len(ends)):
            self.assertLess(np.linalg.norm(ends[k][0] - ends[k - 1][1]), 1e-12, f"joint {k}")
        length = sum(np.linalg.norm(e - b) for b, e in ends)
        self.assertAlmostEqual(length, 2.0, places=12)
        # Straight (all angles 0), the tip is 2 m out along -x from the root.
        straight = g.poses(np.zeros(len(g.names)))
        c, R, d = straight[1 + rods[-1]]
        c0, R0, d0 = straight[1 + rods[0]]
        tip, root = c + d[0] / 2 * R[:, 0], c0 - d0[0] / 2 * R0[:, 0]
        self.assertLess(np.linalg.norm(tip - root - np.array([-2.0, 0, 0])), 1e-12)

    def test_files_without_body_draw_from_the_model_text(self):
        """The main job's file without @body (as written before it) draws the same boxes
        from the model text."""
        spring = ART / "spring_nobody.h5"
        r = run(DEPLOYSIM, "simulate", SRC / "deployment_profiles/smallsat_spring_deploy.yaml",
                "-q", "--until", "70", "-o", spring)
        self.assertEqual(r.returncode, 0, r.stderr)
        with_body = self.scene.read_run(str(spring))
        with h5py.File(spring, "r+") as f:
            del f.attrs["body"]
        without = self.scene.read_run(str(spring))
        for i in (0, len(with_body["time"]) - 1):
            for (c1, R1, d1), (c2, R2, d2) in zip(self.scene.poses_at(with_body, i),
                                                  self.scene.poses_at(without, i)):
                self.assertLess(np.abs(c1 - c2).max(), 1e-12)
                # The same box (its axes may come in another order from the inertia).
                self.assertLess(np.abs((R1 * d1) @ (R1 * d1).T - (R2 * d2) @ (R2 * d2).T).max(),
                                1e-12)

    def test_page_groups_the_bending_hinges_and_shows_the_bend(self):
        """The page's event list has one row per beam for its bending hinges' releases, the
        stage names name each beam once, the hinge chart has a bend line per plane; in
        the browser the page has no errors and the bending beam is drawn (screenshots
        booms_t*.png)."""
        data = self.view.build_data(self.run_)
        starts = [e["text"] for e in data["events"] if e["t"] == 0.0]
        self.assertEqual(starts, ["boom_px: its 12 hinges free from the start",
                                  "boom_mx: its 6 hinges free from the start"])
        self.assertEqual(data["stages"][0]["name"], "free: boom_px (12), boom_mx (6)")
        self.assertEqual(data["hinge"]["names"],
                         ["boom_px", "boom_mx", "boom_px bend 1", "boom_px bend 2",
                          "boom_mx bend"])
        self.assertIn("link", data["parts"]["kinds"])
        # The bend: the sum of a plane's hinge angles, tens of degrees during the swing.
        bend = np.array(data["hinge"]["deg"]).reshape(-1, 5)[:, 2]
        self.assertGreater(np.abs(bend).max(), 20.0)
        r = run(PY, SRC / "tools/view.py", self.h5, "-o", self.html)
        self.assertEqual(r.returncode, 0, r.stderr)
        import headless_chromium
        with headless_chromium.Browser(1280, 800) as b:
            page = open_at(b, self.html, (1280, 800))
            self.assertTrue(page.evaluate("window.deploysimReady === true"))
            shots = []
            for t in (0.1, 0.9):
                page.evaluate(f"window.deploysimSetTime({t})")
                shots.append(load_png(page.screenshot(ART / f"booms_t{t:g}.png")))
            self.assertEqual(page.errors(), [])
        view_w = shots[0].shape[1] * 820 // 1280   # the 3D view, left of the side panel
        a, b = shots[0][120:640, :view_w], shots[1][120:640, :view_w]
        changed = (np.abs(a - b).max(axis=2) > 0.1).mean()
        print(f"  3D view pixels changed between 0.1 s and 0.9 s: {changed:.3f}")
        self.assertGreater(changed, MIN_CHANGED_FRACTION / 10)


class AnimationTest(unittest.TestCase):
    """A short, low-resolution MP4 of the wing nut's flips: duration, frame rate, motion."""

    FPS, SECONDS = 10, 4.0

    def test_wing_nut_mp4(self):
        ART.mkdir(parents=True, exist_ok=True)
        h5 = ART / "wing_nut.h5"
        r = run(DEPLOYSIM, "simulate", SRC / "deployment_profiles/wing_nut.yaml", "-q", "-o", h5)
        self.assertEqual(r.returncode, 0, r.stderr)
        mp4 = ART / "wing_nut.mp4"
        t0 = time.monotonic()
        r = run(PY, SRC / "tools/animate.py", h5, "-o", mp4, "--fps", self.FPS,
                "--seconds", self.SECONDS, "--size", "320x240", "--gif", umask=0o022)
        self.assertEqual(r.returncode, 0, r.stderr)
        # Written 0666 less the umask, like the HDF5 file.
        self.assertEqual(oct(mode(mp4)), oct(0o644))
        self.assertEqual(oct(mode(ART / "wing_nut.gif")), oct(0o644))
        print(f"\n  animate.py: {time.monotonic() - t0:.1f} s for "
              f"{int(self.FPS * self.SECONDS)} frames")
        p = run("ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames",
                "-show_entries", "stream=r_frame_rate,nb_read_frames,width,height:format=duration",
                "-of", "json", mp4)
        self.assertEqual(p.returncode, 0, p.stderr)
        info = json.loads(p.stdout)
        st = info["streams"][0]
        num, den = map(int, st["r_frame_rate"].split("/"))
        duration = float(info["format"]["duration"])
        print(f"  {mp4.name}: {num / den:g} fps, {duration:.3f} s, {st['nb_read_frames']} "
              f"frames, {st['width']}x{st['height']}")
        self.assertAlmostEqual(num / den, self.FPS)
        self.assertAlmostEqual(duration, self.SECONDS, delta=1.0 / self.FPS)
        self.assertEqual(int(st["nb_read_frames"]), int(self.FPS * self.SECONDS))
        gif = ART / "wing_nut.gif"
        self.assertEqual(gif.read_bytes()[:6], b"GIF89a")
        g = run("ffprobe", "-v", "error", "-count_frames", "-show_entries",
                "stream=nb_read_frames", "-of", "csv=p=0", gif)
        self.assertEqual(int(g.stdout.strip()), int(self.FPS * self.SECONDS), g.stderr)
        # Frames change: the grey means of a few frames are not all equal.
        frames = ART / "wing_nut_frame_%d.png"
        for old in ART.glob("wing_nut_frame_*.png"):
            old.unlink()
        r = run("ffmpeg", "-v", "error", "-i", mp4, "-vf", "select=not(mod(n\\,10))",
                "-vsync", "vfr", str(frames))
        self.assertEqual(r.returncode, 0, r.stderr)
        imgs = [load_png(p) for p in sorted(ART.glob("wing_nut_frame_*.png"))]
        self.assertGreaterEqual(len(imgs), 3)
        diffs = [np.abs(imgs[i] - imgs[i + 1]).mean() for i in range(len(imgs) - 1)]
        print(f"  mean |frame difference| every 10 frames: {', '.join(f'{d:.4f}' for d in diffs)}")
        self.assertTrue(all(d > 1e-3 for d in diffs), diffs)

    def test_bad_input(self):
        ART.mkdir(parents=True, exist_ok=True)
        bad = ART / "not_hdf5_anim.h5"
        bad.write_text("no\n")
        out = ART / "bad.mp4"
        out.unlink(missing_ok=True)
        r = run(PY, SRC / "tools/animate.py", bad, "-o", out)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertFalse(out.exists())


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    DEPLOYSIM = pathlib.Path(sys.argv[1]).resolve()
    SRC = pathlib.Path(sys.argv[2]).resolve()
    ART = pathlib.Path(sys.argv[3]).resolve()
    unittest.main(argv=[sys.argv[0], "-v"] + sys.argv[4:])
