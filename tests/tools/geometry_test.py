#!/usr/bin/python3
"""tools/plot_geometry.py draws what the seed thesis's Figs. 2.3-2.8 claim, checked on the
arrays that are actually drawn: the figures for the wing nut are built through the
function the CLI uses (build_figures) and the curves are read back from the matplotlib
artists (Line3D.get_data_3d, Line2D.get_xydata).

Usage: geometry_test.py [DEPLOYSIM_BINARY]   (or $DEPLOYSIM_BIN; ctest passes the built
binary). Without a binary the checks on a simulated run are skipped.
The measured residuals are printed (stderr) next to their tolerances.
"""

import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

import numpy as np

TOOLS = pathlib.Path(__file__).resolve().parents[2] / "tools"
SOURCE = TOOLS.parent
sys.path.insert(0, str(TOOLS))
import plot_geometry  # noqa: E402

DEPLOYSIM = os.environ.get("DEPLOYSIM_BIN")

# The wing nut (models/wing_nut.yaml), thesis numbering J1 > J2 > J3; given to the tool in
# another order on purpose.
J1, J2, J3 = 3.036e-6, 2.741e-6, 0.699e-6
SLOPE_2_43 = np.sqrt(J3 * (J1 - J2) / (J1 * (J2 - J3)))  # eq. 2.43, H3 = +-slope * H1

# Tolerances, a few times above the measured maxima (printed by the tests):
TOL_SURFACE = 4e-15      # drawn curves on (2.36) and (2.37); measured 8.9e-16
TOL_PLANE = 1e-14        # drawn projections on (2.40), (2.41), (2.42); measured 3.1e-15
TOL_AXIS = 1e-15         # separatrix through (0, +-1, 0); measured 1.2e-16
TOL_SLOPE = 1e-14        # asymptote slope, relative; measured 0 (same formula, fixed typo)
TOL_RUN = 1e-14          # the run's polhode (rkmk-rkf78, rtol 1e-12); measured 2.9e-15
CONIC_MARGIN = 1e-2      # |B^2 - 4AC| / (A^2 + B^2 + C^2) must exceed it; measured 0.13
TOL_SEED_RK4 = 1e-9      # seed Figs. 3.1-3.3, rk4 h = 1e-3 s vs closed form, relative to
#                          max |H|; measured 2.3e-10 (the wing nut)
TOL_NORM = 1e-14         # closed-form |H| constant over 40 s, relative; measured 2.7e-15
CONIC_FIT = 1e-13        # smallest / largest singular value of the fit; measured 8.5e-16


def report(what, measured, tol):
    print(f"  {what}: measured {measured:.3g}, tolerance {tol:.3g}", file=sys.stderr)


def gid_kind(line):
    gid = line.get_gid() or ""
    kind, _, d = gid.partition("|")
    return kind, (1.0 if kind == "separatrix" else float(d) if d else None)


def curves3d(fig, kinds):
    """[(kind, dbar, (n, 3) array)] of the Line3D curves of fig with a gid in kinds."""
    out = []
    for ax in fig.axes:
        for ln in ax.get_lines():
            kind, d = gid_kind(ln)
            if kind in kinds:
                out.append((kind, d, np.column_stack(ln.get_data_3d())))
    return out


def curves2d(ax, kinds):
    out = []
    for ln in ax.get_lines():
        kind, d = gid_kind(ln)
        if kind in kinds:
            out.append((kind, d, ln.get_xydata()))
    return out


def ellipsoid(H):
    """(2.36) minus 1, with the test's own J."""
    return (J2 / J1) * H[:, 0] ** 2 + H[:, 1] ** 2 + (J2 / J3) * H[:, 2] ** 2 - 1.0


def plane_residual(plane, d, xy):
    """(2.40), (2.41), (2.42): left side minus right side, written as in the thesis."""
    x, y = xy[:, 0], xy[:, 1]
    a, c = J2 / J1, J2 / J3
    if plane == (1, 2):
        return (1 - a) * x ** 2 + (c - a) * y ** 2 - (1 - a * d)
    if plane == (0, 1):
        return (c - a) * x ** 2 + (c - 1) * y ** 2 - (c * d - 1)
    return -(1 - a) * x ** 2 + (c - 1) * y ** 2 - (1 - d)


def conic_fit(xy):
    """Least-squares general conic A x^2 + B xy + C y^2 + D x + E y + F = 0 through the
    points (the right singular vector of the smallest singular value): (coefficients,
    normalised discriminant (B^2 - 4AC)/(A^2+B^2+C^2), smallest/largest singular value)."""
    x, y = xy[:, 0], xy[:, 1]
    M = np.column_stack([x * x, x * y, y * y, x, y, np.ones_like(x)])
    _, s, vt = np.linalg.svd(M, full_matrices=False)
    A, B, C = vt[-1][:3]
    return vt[-1], (B * B - 4 * A * C) / (A * A + B * B + C * C), s[-1] / s[0]


class GeometryFiguresTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        J = plot_geometry.thesis_moments([J3, J1, J2])
        plot_geometry.min_radicand[0] = np.inf
        cls.fig3d, cls.fig2d = plot_geometry.build_figures(J, count=5)
        cls.min_radicand = plot_geometry.min_radicand[0]
        cls.planes = {}
        for ax in cls.fig2d.axes:
            for i, j, *_ in plot_geometry.PLANES:
                if ax.get_xlabel() == rf"$\bar H_{i + 1}$" and \
                        ax.get_ylabel() == rf"$\bar H_{j + 1}$":
                    cls.planes[(i, j)] = ax

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_three_planes_drawn(self):
        self.assertEqual(sorted(self.planes), [(0, 1), (0, 2), (1, 2)])

    def test_polhodes_lie_on_ellipsoid_and_sphere(self):
        curves = curves3d(self.fig3d, ("polhode", "separatrix"))
        dbars = {d for k, d, _ in curves if k == "polhode"}
        self.assertGreaterEqual(sum(d < 1 for d in dbars), 5)
        self.assertGreaterEqual(sum(d > 1 for d in dbars), 5)
        self.assertTrue(all(J3 / J2 < d < J1 / J2 for d in dbars))
        worst_e = max(np.abs(ellipsoid(H)).max() for _, _, H in curves)
        worst_s = max(np.abs(np.sum(H * H, axis=1) - d).max() for _, d, H in curves)
        report("3D curves on the ellipsoid (2.36)", worst_e, TOL_SURFACE)
        report("3D curves on the sphere (2.37)", worst_s, TOL_SURFACE)
        self.assertLess(worst_e, TOL_SURFACE)
        self.assertLess(worst_s, TOL_SURFACE)
        report("smallest square-root argument (clamped at 0)", self.min_radicand, 0.0)
        self.assertGreaterEqual(self.min_radicand, 0.0)

    def test_polhodes_close_around_the_stable_axes(self):
        """dbar < 1 curves keep the sign of H3 (about H3), dbar > 1 that of H1."""
        for _, d, H in curves3d(self.fig3d, ("polhode",)):
            axis = 2 if d < 1 else 0
            self.assertTrue(np.all(H[:, axis] > 0) or np.all(H[:, axis] < 0), d)
            self.assertLess(np.abs(H[0] - H[-1]).max(), 1e-15, d)  # closed

    def test_projections_lie_on_the_plane_conics(self):
        worst = 0.0
        for plane, ax in self.planes.items():
            curves = curves2d(ax, ("polhode", "separatrix"))
            self.assertGreaterEqual(len(curves), 20, plane)
            for _, d, xy in curves:
                worst = max(worst, np.abs(plane_residual(plane, d, xy)).max())
        report("2D projections on (2.40)-(2.42)", worst, TOL_PLANE)
        self.assertLess(worst, TOL_PLANE)

    def test_conic_type_of_each_projection(self):
        """docs/design.md 2.4: ellipses on (H2,H3), ellipses on (H1,H2), hyperbolas on
        (H1,H3)."""
        want = {(1, 2): -1, (0, 1): -1, (0, 2): +1}
        margin, fit = np.inf, 0.0
        for plane, ax in self.planes.items():
            for _, d, xy in curves2d(ax, ("polhode",)):
                _, disc, sv = conic_fit(xy)
                self.assertEqual(np.sign(disc), want[plane], (plane, d, disc))
                margin, fit = min(margin, abs(disc)), max(fit, sv)
        report("conic discriminant margin |B^2-4AC|/(A^2+B^2+C^2)", margin, CONIC_MARGIN)
        report("conic fit smallest/largest singular value", fit, CONIC_FIT)
        self.assertGreater(margin, CONIC_MARGIN)
        self.assertLess(fit, CONIC_FIT)

    def test_conic_fit_tells_ellipse_from_hyperbola(self):
        """The classifier itself: an arc of each kind, the hyperbola arc as short as ours."""
        u = np.linspace(-0.4, 0.4, 200)
        self.assertLess(conic_fit(np.column_stack([2 * np.cos(u), np.sin(u)]))[1], 0)
        self.assertGreater(conic_fit(np.column_stack([np.cosh(u), np.sinh(u)]))[1], 0)

    def test_separatrix_passes_through_the_intermediate_axis(self):
        seps = curves3d(self.fig3d, ("separatrix",))
        self.assertGreaterEqual(len(seps), 4)   # two ellipses, in two panels
        worst = 0.0
        for _, _, H in seps:
            for p in ([0, 1, 0], [0, -1, 0]):
                worst = max(worst, np.linalg.norm(H - p, axis=1).min())
        for plane, p in (((1, 2), [1, 0]), ((0, 1), [0, 1])):
            for _, _, xy in curves2d(self.planes[plane], ("separatrix",)):
                for q in (np.array(p), -np.array(p)):
                    worst = max(worst, np.linalg.norm(xy - q, axis=1).min())
        report("separatrix distance from (0, +-1, 0)", worst, TOL_AXIS)
        self.assertLess(worst, TOL_AXIS)

    def test_asymptote_slope_is_2_43_with_h1(self):
        ax = self.planes[(0, 2)]
        lines = curves2d(ax, ("asymptote",))
        self.assertEqual(len(lines), 2)
        slopes = sorted((xy[-1, 1] - xy[0, 1]) / (xy[-1, 0] - xy[0, 0]) for _, _, xy in lines)
        err = max(abs(slopes[0] + SLOPE_2_43), abs(slopes[1] - SLOPE_2_43)) / SLOPE_2_43
        report("asymptote slope vs sqrt(J3(J1-J2)/(J1(J2-J3))), relative", err, TOL_SLOPE)
        self.assertLess(err, TOL_SLOPE)
        # The separatrix dbar = 1 projects onto the asymptotes (thesis, after Fig. 2.8).
        for _, _, xy in curves2d(ax, ("separatrix",)):
            off = np.abs(np.abs(xy[:, 1]) - SLOPE_2_43 * np.abs(xy[:, 0])).max()
            self.assertLess(off, TOL_PLANE)


class GeometryRunTest(unittest.TestCase):
    """The wing nut simulated, its polhode overlaid, and the CLI's error handling."""

    @classmethod
    def setUpClass(cls):
        if not DEPLOYSIM:
            raise unittest.SkipTest("no deploysim binary (argument or $DEPLOYSIM_BIN)")
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.h5 = cls.dir / "wing_nut.h5"
        subprocess.run([DEPLOYSIM, "simulate", str(SOURCE / "deployment_profiles/wing_nut.yaml"),
                        "-q", "-o", str(cls.h5)], check=True, capture_output=True)
        cls.traj = plot_geometry.read_trajectory(str(cls.h5))
        cls.figs = plot_geometry.build_figures(cls.traj["J"], cls.traj)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def cli(self, *args):
        return subprocess.run([sys.executable, str(TOOLS / "plot_geometry.py"), *args],
                              capture_output=True, text=True)

    def test_run_polhode_on_its_ellipsoid_and_sphere(self):
        self.assertTrue(np.allclose(self.traj["J"], [J1, J2, J3], rtol=1e-15, atol=0))
        runs = curves3d(self.figs[0], ("run",))
        self.assertEqual(len(runs), 1)
        _, d, H = runs[0]
        self.assertGreater(len(H), 1000)
        self.assertAlmostEqual(d, self.traj["dbar"], delta=0)
        self.assertTrue(0.999 < d < 1.0, d)    # the wing nut: just inside the separatrix
        worst = max(np.abs(ellipsoid(H)).max(), np.abs(np.sum(H * H, axis=1) - d).max())
        report("run polhode on its ellipsoid and sphere", worst, TOL_RUN)
        self.assertLess(worst, TOL_RUN)
        # Drawn on every projection too, with its dbar in the legend.
        for ax in self.figs[1].axes[:3]:
            (run2,) = curves2d(ax, ("run",))
            self.assertEqual(run2[1], d)
        labels = [t.get_text() for t in self.figs[1].legends[0].get_texts()]
        self.assertTrue(any(f"{d:.9g}" in s for s in labels), labels)

    def test_cli_writes_both_pngs(self):
        out = self.dir / "ok"
        r = self.cli(str(self.h5), "-o", str(out))
        self.assertEqual(r.returncode, 0, r.stderr)
        for name in ("geometry_ellipsoid.png", "geometry_projections.png"):
            data = (out / name).read_bytes()
            self.assertEqual(data[:8], b"\x89PNG\r\n\x1a\n")
            self.assertGreater(len(data), 50000)

    def test_seed_time_series_beside_their_closed_form(self):
        """tools/plot_seed_figures.py: three figures; the closed-form panel conserves |H|
        and a 4th-order run (rk4, h = 1e-3 s) draws the same curves as the closed form."""
        import plot_seed_figures
        figs = plot_seed_figures.build_figures(DEPLOYSIM, "rk4", 1e-3)
        self.assertEqual([n for n, _, _ in figs],
                         ["seed_fig3_1_wing_nut.png", "seed_fig3_2_seed_limit_j2_to_j1.png",
                          "seed_fig3_3_seed_limit_j2_to_j3.png"])
        worst_diff = worst_norm = 0.0
        for name, fig, _ in figs:
            num, exact, diff = fig.axes[:3]
            colors = [ln.get_color() for ln in exact.get_lines()]
            self.assertEqual(colors, ["red", "green", "blue", "k"], name)
            norm = exact.get_lines()[3].get_ydata()
            scale = max(np.abs(ln.get_ydata()).max() for ln in exact.get_lines())
            worst_norm = max(worst_norm, np.ptp(norm) / norm.mean())
            for a, b in zip(num.get_lines(), exact.get_lines()):
                worst_diff = max(worst_diff,
                                 np.abs(a.get_ydata() - b.get_ydata()).max() / scale)
            for a, b, c in zip(num.get_lines()[:3], exact.get_lines(), diff.get_lines()):
                self.assertTrue(np.array_equal(c.get_ydata(), a.get_ydata() - b.get_ydata()))
        report("seed figures: rk4 vs closed form, relative", worst_diff, TOL_SEED_RK4)
        report("seed figures: closed-form |H| spread, relative", worst_norm, TOL_NORM)
        self.assertLess(worst_diff, TOL_SEED_RK4)
        self.assertLess(worst_norm, TOL_NORM)

    def test_bad_input_one_line_nonzero_no_files(self):
        """Each bad input: exit status 1, one line on stderr, no output folder. Run through
        main() in this process (a subprocess per case costs a matplotlib import each); one
        case through the real CLI as well."""
        import contextlib
        import io

        import h5py
        other = self.dir / "other.h5"
        with h5py.File(other, "w") as f:
            f["time"] = np.zeros(3)
        limit = self.dir / "j2_to_j3.h5"
        subprocess.run([DEPLOYSIM, "simulate", "-q", "-o", str(limit),
                        str(SOURCE / "deployment_profiles/seed_limit_j2_to_j3.yaml")],
                       check=True, capture_output=True)
        text_file = self.dir / "notes.txt"
        text_file.write_text("not a profile\n")
        cases = {
            "missing file": [str(self.dir / "nope.h5")],
            "not a trajectory": [str(other)],
            "stage out of range": [str(self.h5), "--stage", "1"],
            "negative stage": [str(self.h5), "--stage", "-1"],
            "zero moment": ["--inertia", "3", "0", "1"],
            "negative moment": ["--inertia", "3", "-2", "1"],
            "not finite": ["--inertia", "3", "nan", "1"],
            "two equal to round-off": ["--inertia", "2.741e-6", repr(2.741e-6 * (1 + 4e-16)),
                                       "0.699e-6"],
            "neither HDF5 nor YAML": [str(text_file)],
            "profile with J2 = J1": [str(SOURCE / "deployment_profiles/seed_limit_j2_to_j1.yaml"),
                                     "--deploysim", DEPLOYSIM],
            "trajectory with J2 = J3": [str(limit)],
            "profile stage out of range": [str(SOURCE / "deployment_profiles/wing_nut.yaml"),
                                           "--deploysim", DEPLOYSIM, "--stage", "2"],
            "not a deploysim binary": [str(SOURCE / "deployment_profiles/wing_nut.yaml"),
                                       "--deploysim", str(self.dir / "no_such_binary")],
            "nothing to draw": [],
        }
        for what, args in cases.items():
            out = self.dir / ("bad_" + what.replace(" ", "_"))
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                status = plot_geometry.main([*args, "-o", str(out)])
            self.assertEqual(status, 1, what)
            lines = err.getvalue().strip().splitlines()
            self.assertEqual(len(lines), 1, (what, lines))
            self.assertTrue(lines[0].startswith("plot_geometry: "), (what, lines))
            self.assertFalse(out.exists(), what)
        out = self.dir / "bad_cli"
        r = self.cli(str(self.h5), "--stage", "3", "-o", str(out))
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
        self.assertIn("out of range", r.stderr)
        self.assertFalse(out.exists())

if __name__ == "__main__":
    if len(sys.argv) > 1 and not sys.argv[1].startswith("-"):
        DEPLOYSIM = sys.argv.pop(1)
    unittest.main()
