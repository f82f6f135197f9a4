#!/usr/bin/python3
"""The 3D viewer (tools/view.py) and the animation (tools/animate.py), issue 12.

Usage: viewer_test.py DEPLOYSIM SOURCE_DIR ARTEFACT_DIR
Runs deploysim on deployment_profiles/smallsat_spring_deploy.yaml (and wing_nut.yaml, and
a short cross-check), writes the pages and a short MP4, and checks them in Debian's
headless Chromium with no network. Screenshots and pages are kept in ARTEFACT_DIR (look
at them: spring_t30.png before the release, spring_t200.png mid-flip).
"""
import json
import pathlib
import subprocess
import sys
import time
import unittest

import h5py
import numpy as np

DEPLOYSIM, SRC, ART = None, None, None
PY = "/usr/bin/python3"

# Named tolerances and limits.
INERTIA_REL_TOL = 1e-12      # drawn boxes vs /J_B (measured 1e-16: the same formulas)
MAX_PAGE_BYTES = 5_000_000   # issue 12: the main job's page under 5 MB
# The 2 s opening target is a benchmark row (bench/pages_bench.py), not a timed test.
MIN_CHANGED_FRACTION = 0.02  # of the pixels around the body between two times
MIN_SCENE_STDDEV = 0.02      # grey-level spread of a scene that is not blank (0..1)
MAX_DRAWN_ATTITUDE_ERROR_DEG = 0.5   # slerp between kept samples vs every sample (0.04)


def run(*args, **kw):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)


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
        page = self.browser.open(self.html.as_uri())
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
        # The 3D view is the left part (the side panel is 446 px wide); the body sits in
        # the middle of it.
        view_w = a.shape[1] - 446
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
        page = self.browser.open(out.as_uri())
        self.assertTrue(page.evaluate("window.deploysimReady === true"))
        self.assertEqual(page.evaluate("window.deploysimInfo.sides"), 2)
        page.evaluate("window.deploysimSetTime(68)")
        page.screenshot(ART / "spring_crosscheck_t68.png")
        self.assertEqual(page.errors(), [])
        img = load_png(ART / "spring_crosscheck_t68.png")
        view_w = img.shape[1] - 446
        left, right = img[:, : view_w // 2], img[:, view_w // 2: view_w]
        self.assertGreater(left.std(), MIN_SCENE_STDDEV)   # a body on each side
        self.assertGreater(right.std(), MIN_SCENE_STDDEV)

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
                "--seconds", self.SECONDS, "--size", "320x240", "--gif")
        self.assertEqual(r.returncode, 0, r.stderr)
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
