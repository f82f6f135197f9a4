#!/usr/bin/python3
"""Draws the seed thesis's geometric picture of torque-free rotation (its Figs. 2.2-2.8).

Writes into OUTDIR:
  geometry_ellipsoid.png    nondimensional energy ellipsoid (thesis eq. 2.36) cut by the
                            momentum sphere (2.37) for dbar < 1, dbar = 1 and dbar > 1
                            (Figs. 2.3-2.5), and the family of polhodes on the ellipsoid
  geometry_projections.png  the family projected on the planes (H2,H3): ellipses (2.40),
                            (H1,H2): ellipses (2.41), (H1,H3): hyperbolas (2.42) with the
                            separatrix asymptotes (2.43) (Figs. 2.6-2.8)

Variables and numbering are the thesis's (docs/geometry.md): J1 > J2 > J3, so H1 is the
component along the major axis of inertia (the code elsewhere sorts ascending,
docs/design.md 1); Hbar = H / sqrt(2T J2), dbar = D / J2 = |H|^2 / (2T J2),
J3/J2 <= dbar <= J1/J2. Every curve is drawn from an exact parametrisation (no contouring).

The principal moments come from one of:
  --inertia A B C        three principal moments, any order, any unit
  TRAJECTORY.h5          a file written by `deploysim simulate`: the moments at the end of
                         stage --stage (default: the last stage); the run's own polhode of
                         that stage is overlaid on both figures
  PROFILE.yaml           a deployment profile: `deploysim simulate` runs it into a
                         temporary trajectory (binary: --deploysim, else $DEPLOYSIM_BIN,
                         else `deploysim` on PATH), whose /stages/moments_end of stage
                         --stage (default: the last) is used

Two principal moments equal (to the 1e-9 relative rule of plot_trajectory's separatrix)
are rejected: there is no intermediate axis, no separatrix, and dbar = D/J2 does not
single out a family (the seed's section 3.3 limits). Non-positive or non-finite moments
are rejected too. Errors: one line on stderr, exit status 1, no files written.

Examples:
  /usr/bin/python3 tools/plot_geometry.py --inertia 3.036e-6 2.741e-6 0.699e-6 -o geo
  deploysim simulate deployment_profiles/wing_nut.yaml -q -o wn.h5
  /usr/bin/python3 tools/plot_geometry.py wn.h5 -o geo_wing_nut
  deploysim simulate deployment_profiles/smallsat_spring_deploy.yaml -q -o spring.h5
  /usr/bin/python3 tools/plot_geometry.py spring.h5 --stage 4 -o geo_spring
  /usr/bin/python3 tools/plot_geometry.py deployment_profiles/smallsat_three_stage.yaml \\
      --deploysim build/release/bin/deploysim --stage 0 -o geo_stowed
Trajectories are read through tools/deploysim_results.py.
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy (run with /usr/bin/python3).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

import deploysim_results
import plot_trajectory  # sets the Agg backend
from plot_trajectory import separatrix_circles

import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from matplotlib import colors as mcolors  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

assert plot_trajectory  # imported for its backend choice and helpers

DPI = 150
N_POINTS = 721            # samples of the angle parameter per closed polhode (odd: the
#                           angles 0, pi/2, pi, 3 pi/2 are all samples)
RUN_COLOR = "#00a651"     # the run's own polhode (not in the dbar colour map)
SEP_COLOR = "k"
CMAP = plt.get_cmap("coolwarm")  # blue: dbar < 1 (about H3), red: dbar > 1 (about H1)

# Planes of the projection figure: (x component, y component, thesis eq., conic, fig.),
# 0-based thesis indices (0 = H1, the major axis).
PLANES = [(1, 2, "2.40", "ellipses", "2.6"),
          (0, 1, "2.41", "ellipses", "2.7"),
          (0, 2, "2.42", "hyperbolas", "2.8")]

# Smallest argument of a square root met while drawing (before the clamp at 0); the
# parametrisations below write every radicand as a sum of non-negative terms, so it stays
# >= 0 (measured by the tests).
min_radicand = [np.inf]


class GeometryError(Exception):
    """Bad user input: reported by main() as one line on stderr."""


def thesis_moments(moments):
    """The principal moments in thesis order J1 > J2 > J3 (a float array of 3).

    Raises GeometryError unless there are three finite positive moments, no two of them
    equal to the relative rule of plot_trajectory.separatrix_circles (one rule, one place).
    """
    m = np.asarray(moments, dtype=float).ravel()
    if m.size != 3:
        raise GeometryError(f"need three principal moments, got {m.size}")
    if not np.all(np.isfinite(m)) or np.any(m <= 0):
        raise GeometryError(f"principal moments must be finite and > 0, got {m.tolist()}")
    J = np.sort(m)[::-1].copy()
    if not separatrix_circles(np.diag(J[::-1])):
        raise GeometryError(
            f"two principal moments are equal (to 1e-9 relative): {J.tolist()}; with no "
            "intermediate axis there is no separatrix and dbar = D/J2 is meaningless")
    return J


def ratios(J):
    """(j1, j3) = (J1/J2, J3/J2): the ellipsoid (2.36) is H1^2/j1 + H2^2 + H3^2/j3 = 1."""
    return J[0] / J[1], J[2] / J[1]


def dbar_range(J):
    """Admissible dbar (2.38): [J3/J2, J1/J2]."""
    j1, j3 = ratios(J)
    return j3, j1


def _sqrt(x):
    min_radicand[0] = min(min_radicand[0], float(np.min(x)))
    return np.sqrt(np.maximum(x, 0.0))


def polhode(J, dbar, n=N_POINTS):
    """The polhode of dbar as its two closed branches, each an (n, 3) array of Hbar.

    dbar < 1 (about H3): (H1, H2) on the ellipse (2.41) by an angle phi,
      H3 = +-sqrt(dbar - H1^2 - H2^2), the radicand written as a sum of non-negative terms
      j3 (j1 - d)/(j1 - j3) cos^2 + j3 (1 - d)/(1 - j3) sin^2.
    dbar > 1 (about H1): (H2, H3) on the ellipse (2.40),
      H1 = +-sqrt(j1 (d - 1)/(j1 - 1) cos^2 + j1 (d - j3)/(j1 - j3) sin^2).
    dbar = 1: the separatrix (separatrix()).
    """
    j1, j3 = ratios(J)
    d = float(dbar)
    if not j3 <= d <= j1:
        raise ValueError(f"dbar = {d} outside [{j3}, {j1}] (2.38)")
    if d == 1.0:
        return separatrix(J)
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    c2, s2 = np.cos(phi) ** 2, np.sin(phi) ** 2
    if d < 1.0:
        h1 = np.sqrt(j1 * (d - j3) / (j1 - j3)) * np.cos(phi)
        h2 = np.sqrt((d - j3) / (1.0 - j3)) * np.sin(phi)
        h3 = _sqrt(j3 * (j1 - d) / (j1 - j3) * c2 + j3 * (1.0 - d) / (1.0 - j3) * s2)
        return [np.column_stack([h1, h2, s * h3]) for s in (1.0, -1.0)]
    h2 = np.sqrt((j1 - d) / (j1 - 1.0)) * np.cos(phi)
    h3 = np.sqrt(j3 * (j1 - d) / (j1 - j3)) * np.sin(phi)
    h1 = _sqrt(j1 * (d - 1.0) / (j1 - 1.0) * c2 + j1 * (d - j3) / (j1 - j3) * s2)
    return [np.column_stack([s * h1, h2, h3]) for s in (1.0, -1.0)]


def separatrix(J):
    """The separatrix dbar = 1: two planar ellipses (great circles of the unit sphere)
    through the intermediate axis (0, +-1, 0), as (n, 3) arrays of Hbar in thesis order.

    On dbar = 1 the sphere is the unit sphere of Hbar, so these are plot_trajectory's
    separatrix circles of the nondimensional inertia diag(J3, J2, J1)/J2 (ascending, the
    code's order), columns reversed to thesis order.
    """
    j1, j3 = ratios(J)
    return [c[:, ::-1] for c in separatrix_circles(np.diag([j3, 1.0, j1]), N_POINTS)]


def asymptote_slope(J):
    """Slope of the separatrix asymptotes H3 = +-slope H1 in the (H1, H3) plane.

    Thesis eq. 2.43 reads H3 = +-sqrt(J3 (J1 - J2) / (J1 (J2 - J3))) H2C; the H2C is a typo
    for H1C: eliminating H2 from (2.36) and (2.37) gives (2.42), whose asymptotes (and its
    dbar = 1 case) lie in the (H1, H3) plane.
    """
    return np.sqrt(J[2] * (J[0] - J[1]) / (J[0] * (J[1] - J[2])))


def dbar_family(J, count=5):
    """count values of dbar on each side of the separatrix, strictly inside (2.38)."""
    j1, j3 = ratios(J)
    f = np.arange(1, count + 1) / (count + 1.0)
    below = 1.0 - (1.0 - j3) * f[::-1]
    above = 1.0 + (j1 - 1.0) * f
    return np.concatenate([below, above])


def ellipsoid_residual(J, H):
    """(2.36) left side minus 1 at the points H (n, 3)."""
    j1, j3 = ratios(J)
    return H[:, 0] ** 2 / j1 + H[:, 1] ** 2 + H[:, 2] ** 2 / j3 - 1.0


def stage_table(path):
    """The trajectory file's run and its stage table (tools/deploysim_results.py), with
    GeometryError for a file that is none."""
    try:
        run = deploysim_results.read_trajectory(path)
        return run, run.stages
    except deploysim_results.TrajectoryError as e:
        raise GeometryError(str(e)) from None


def pick_stage(path, stages, stage, what="file"):
    """The index of stage `stage` (default: the last) of a table of len(stages) rows."""
    n = len(stages)
    k = n - 1 if stage is None else stage
    if not 0 <= k < n:
        raise GeometryError(f"{path}: --stage {stage} out of range (the {what} has "
                            f"{n} stage{'s' if n != 1 else ''}: 0..{n - 1})")
    return k


def read_trajectory(path, stage=None):
    """The principal moments at the end of a stage of a deploysim trajectory, and the run's
    polhode over that stage (dict: J, H (n, 3) Hbar in thesis order, dbar, stage, name,
    rigid, profile).

    H_B at the samples inside [t_begin, t_end] is rotated into the principal frame of J_B
    at the same sample (axes sorted J1 > J2 > J3, each axis's sign kept continuous from
    sample to sample, the first sample's largest component positive) and divided by
    sqrt(2T J2) with the stage end's 2T = H.J^-1.H and J2.
    """
    run, stages = stage_table(path)
    k = pick_stage(path, stages, stage)
    s = stages[k]
    J = _moments(path, k, s["moments_end"])
    try:
        t, HB, JB = run["time"], run["H_B"], run["J_B"]
    except deploysim_results.TrajectoryError as e:
        raise GeometryError(str(e)) from None
    sel = (t >= s["t_begin"]) & (t <= s["t_end"])
    if np.count_nonzero(sel) < 2:
        raise GeometryError(f"{path}: stage {k} has fewer than 2 samples")
    H, Jt = HB[sel], JB[sel]
    vals, vecs = np.linalg.eigh(Jt)
    vals, vecs = vals[:, ::-1], vecs[:, :, ::-1]      # thesis order J1 > J2 > J3
    first = vecs[0]
    first *= np.sign(first[np.argmax(np.abs(first), axis=0), range(3)])
    for i in range(1, len(vecs)):                    # continuous signs
        vecs[i] *= np.where(np.sum(vecs[i] * vecs[i - 1], axis=0) < 0, -1.0, 1.0)
    P = np.einsum("nij,ni->nj", vecs, H)              # principal components
    two_t = float(np.sum(P[-1] ** 2 / vals[-1]))
    D = float(P[-1] @ P[-1]) / two_t
    return dict(J=J, H=P / np.sqrt(two_t * J[1]), dbar=D / J[1], stage=k, name=s["name"],
                rigid=bool(s["rigid"]), profile=run.profile_name)


def profile_moments(path, deploysim, stage=None):
    """The principal moments at the end of a stage of a deployment profile: the profile is
    run (`deploysim simulate PROFILE`, into a temporary file) and the stage table of its
    trajectory read, as for a trajectory file."""
    if not os.path.isfile(path):
        raise GeometryError(f"{path}: no such file")
    exe = deploysim or os.environ.get("DEPLOYSIM_BIN") or shutil.which("deploysim")
    if not exe:
        raise GeometryError(f"{path}: a profile needs the deploysim binary (--deploysim)")
    with tempfile.TemporaryDirectory(prefix="plot_geometry-") as tmp:
        h5 = os.path.join(tmp, "run.h5")
        try:
            r = subprocess.run([exe, "simulate", path, "-q", "-o", h5], capture_output=True,
                               text=True)
        except OSError as e:
            raise GeometryError(f"{path}: cannot run {exe}: {e.strerror}") from None
        if r.returncode != 0:
            err = (r.stderr.strip().splitlines() or ["failed"])[-1]
            raise GeometryError(f"{path}: deploysim simulate: {err}")
        _, stages = stage_table(h5)
    k = pick_stage(path, stages, stage, "profile")
    return _moments(path, k, stages[k]["moments_end"]), k, stages[k]["name"]


def _moments(path, k, moments):
    """thesis_moments() with the file and stage named in the error."""
    try:
        return thesis_moments(moments)
    except GeometryError as e:
        raise GeometryError(f"{path}: stage {k}: {e}") from None


# --- drawing ------------------------------------------------------------------------

def _norm(J):
    j1, j3 = ratios(J)
    return mcolors.TwoSlopeNorm(vmin=j3, vcenter=1.0, vmax=j1)


def _surface(ax, semi, color, alpha, n=40):
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n), np.linspace(0, np.pi, n // 2))
    x, y, z = (semi[0] * np.cos(u) * np.sin(v), semi[1] * np.sin(u) * np.sin(v),
               semi[2] * np.cos(v))
    ax.plot_surface(x, y, z, color=color, alpha=alpha, linewidth=0, shade=False,
                    rstride=1, cstride=1)
    ax.plot_wireframe(x, y, z, color=color, alpha=min(1.0, 2.5 * alpha), lw=0.3,
                      rstride=2, cstride=4)


def _axes3d(ax, J, title):
    j1, _ = ratios(J)
    r = np.sqrt(j1) * 1.05
    for setter in (ax.set_xlim, ax.set_ylim, ax.set_zlim):
        setter(-r, r)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel(r"$\bar H_1$ (major)")
    ax.set_ylabel(r"$\bar H_2$ (interm.)")
    ax.set_zlabel(r"$\bar H_3$ (minor)")
    ax.set_title(title, fontsize=10)
    ax.view_init(elev=22, azim=-58)
    ax.tick_params(labelsize=7)


def _draw_polhode3d(ax, J, dbar, **kw):
    for H in polhode(J, dbar):
        (ln,) = ax.plot(H[:, 0], H[:, 1], H[:, 2], **kw)
        ln.set_gid("separatrix" if dbar == 1.0 else f"polhode|{dbar!r}")
        kw.pop("label", None)


def _run_label(run):
    note = "" if run["rigid"] else ", J changes: off the surfaces"
    return (rf"this run, stage {run['stage']} '{run['name']}' "
            rf"($\bar d$ = {run['dbar']:.9g}{note})")


def _draw_run(ax, run, i=0, j=1, k=None):
    H = run["H"]
    pts = (H[:, i], H[:, j]) if k is None else (H[:, 0], H[:, 1], H[:, 2])
    (ln,) = ax.plot(*pts, color=RUN_COLOR, lw=1.8, label=_run_label(run), zorder=5)
    ln.set_gid(f"run|{run['dbar']!r}")


def figure_ellipsoid(J, run=None, count=5, title=""):
    """Figs. 2.3-2.5 (and 2.2): the ellipsoid (2.36) cut by the sphere (2.37)."""
    j1, j3 = ratios(J)
    semi = np.sqrt([j1, 1.0, j3])
    norm = _norm(J)
    fig = plt.figure(figsize=(12, 11))
    cases = [((j3 + 1.0) / 2, r"$\bar d < 1$ (Fig. 2.4): polhodes about $\bar H_3$"),
             (1.0, r"$\bar d = 1$ (Fig. 2.3): the separatrix"),
             ((1.0 + j1) / 2, r"$\bar d > 1$ (Fig. 2.5): polhodes about $\bar H_1$")]
    for p, (d, ttl) in enumerate(cases):
        ax = fig.add_subplot(2, 2, p + 1, projection="3d")
        _surface(ax, semi, "0.55", 0.10)
        _surface(ax, np.sqrt([d] * 3), "tab:cyan", 0.07)
        color = SEP_COLOR if d == 1.0 else CMAP(norm(d))
        curve = (r"separatrix, $\bar d$ = 1" if d == 1.0
                 else rf"polhode, $\bar d$ = {d:.4g}")
        _draw_polhode3d(ax, J, d, color=color, lw=2.2)
        _axes3d(ax, J, ttl)
        ax.legend(handles=[Line2D([], [], color="0.55", lw=4, alpha=0.5,
                                  label=r"energy ellipsoid (2.36)"),
                           Line2D([], [], color="tab:cyan", lw=4, alpha=0.5,
                                  label=r"momentum sphere (2.37), radius $\sqrt{\bar d}$"),
                           Line2D([], [], color=color, lw=2.2, label=curve)],
                  fontsize=7, loc="upper left", bbox_to_anchor=(0.0, 1.02))
    ax = fig.add_subplot(2, 2, 4, projection="3d")
    _surface(ax, semi, "0.55", 0.08)
    for d in dbar_family(J, count):
        _draw_polhode3d(ax, J, d, color=CMAP(norm(d)), lw=1.0)
    _draw_polhode3d(ax, J, 1.0, color=SEP_COLOR, lw=1.6, label="separatrix")
    if run is not None:
        _draw_run(ax, run, k=True)
    ax.plot([0, 0], [-1, 1], [0, 0], "o", color=SEP_COLOR, ms=4)
    _axes3d(ax, J, r"the family: $J_3/J_2 < \bar d < J_1/J_2$ on the ellipsoid")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0.0, 1.02))
    fig.suptitle(_suptitle(J, title), fontsize=11)
    fig.subplots_adjust(left=0.02, right=0.9, bottom=0.03, top=0.90, wspace=0.05,
                        hspace=0.12)
    _colorbar(fig, J, [0.935, 0.08, 0.012, 0.35])
    return fig


def _colorbar(fig, J, rect):
    sm = plt.cm.ScalarMappable(norm=_norm(J), cmap=CMAP)
    cb = fig.colorbar(sm, cax=fig.add_axes(rect))
    cb.set_label(r"$\bar d = D/J_2 = |H|^2/(2T J_2)$")
    cb.ax.axhline(1.0, color=SEP_COLOR, lw=1.5)
    return cb


def _suptitle(J, title):
    head = f"{title}: " if title else ""
    return (f"{head}torque-free polhodes, thesis numbering $J_1 > J_2 > J_3$ "
            f"($H_1$ along the major axis of inertia)\n"
            rf"$J_1, J_2, J_3$ = {J[0]:.4g}, {J[1]:.4g}, {J[2]:.4g};  "
            r"$\bar H = H/\sqrt{2 T J_2}$,  $\bar d = D/J_2$,  "
            rf"$J_3/J_2$ = {J[2] / J[1]:.4g} $\leq \bar d \leq$ $J_1/J_2$ = {J[0] / J[1]:.4g}")


def figure_projections(J, run=None, count=5, title=""):
    """Figs. 2.6-2.8: the family on the planes (H2,H3), (H1,H2), (H1,H3)."""
    norm = _norm(J)
    j1, _ = ratios(J)
    lim = np.sqrt(j1) * 1.08
    fig, axes = plt.subplots(1, 3, figsize=(16, 6.4))
    slope = asymptote_slope(J)
    for ax, (i, j, eq, kind, fno) in zip(axes, PLANES):
        for d in dbar_family(J, count):
            for H in polhode(J, d):
                (ln,) = ax.plot(H[:, i], H[:, j], color=CMAP(norm(d)), lw=1.0)
                ln.set_gid(f"polhode|{d!r}")
        for s, H in enumerate(separatrix(J)):
            (ln,) = ax.plot(H[:, i], H[:, j], color=SEP_COLOR, lw=1.6,
                            label=r"separatrix $\bar d = 1$" if s == 0 else None)
            ln.set_gid("separatrix")
        if (i, j) == (0, 2):
            x = np.array([-lim, lim])
            for s in (1.0, -1.0):
                # eq. 2.43 with the thesis's typo fixed: H3 = +-slope * H1 (not H2).
                (ln,) = ax.plot(x, s * slope * x, color="0.35", lw=0.9, ls="--",
                                label=(rf"asymptotes (2.43): $\bar H_3 = \pm${slope:.4g}"
                                       r"$\,\bar H_1$" if s > 0 else None), zorder=1)
                ln.set_gid(f"asymptote|{s:+.0f}")
        if run is not None:
            _draw_run(ax, run, i, j)
        ax.plot(0, 0, "+", color="0.5", ms=6)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.set_xlabel(rf"$\bar H_{i + 1}$")
        ax.set_ylabel(rf"$\bar H_{j + 1}$")
        ax.set_title(rf"plane ($\bar H_{i + 1}, \bar H_{j + 1}$): {kind} ({eq}), "
                     f"Fig. {fno}", fontsize=10)
    handles = [Line2D([], [], color=CMAP(0.1), lw=1.2,
                      label=r"$\bar d < 1$: about $\bar H_3$ (minor axis)"),
               Line2D([], [], color=CMAP(0.9), lw=1.2,
                      label=r"$\bar d > 1$: about $\bar H_1$ (major axis)")]
    for ax in (axes[2],):
        h, _ = ax.get_legend_handles_labels()
        handles += h
    fig.legend(handles=handles, loc="lower center", ncol=3, fontsize=8, frameon=False,
               bbox_to_anchor=(0.47, 0.06))
    fig.suptitle(_suptitle(J, title), fontsize=11)
    fig.subplots_adjust(left=0.04, right=0.9, bottom=0.2, top=0.85, wspace=0.22)
    _colorbar(fig, J, [0.92, 0.2, 0.01, 0.65])
    fig.text(0.04, 0.015, "Eq. 2.43 of the thesis prints H2C on its right side: a typo for "
             "H1C (the asymptotes of the (H1, H3) hyperbolas 2.42).", fontsize=7, color="0.4")
    return fig


def build_figures(J, run=None, count=5, title=""):
    """Both figures, as (geometry_ellipsoid, geometry_projections); what the CLI saves."""
    return (figure_ellipsoid(J, run, count, title),
            figure_projections(J, run, count, title))


def load(args):
    """(J, run or None, title) from the parsed command line; GeometryError on bad input."""
    if args.inertia is not None:
        if args.source is not None:
            raise GeometryError("give either --inertia or a trajectory/profile, not both")
        if args.stage is not None:
            raise GeometryError("--stage needs a trajectory or a profile")
        return thesis_moments(args.inertia), None, ""
    if args.source is None:
        raise GeometryError("nothing to draw: give --inertia A B C, a trajectory or a profile")
    if not os.path.isfile(args.source):
        raise GeometryError(f"{args.source}: no such file")
    if deploysim_results.is_hdf5(args.source):
        run = read_trajectory(args.source, args.stage)
        return run["J"], run, f"{run['profile']}, stage {run['stage']} '{run['name']}'"
    if os.path.splitext(args.source)[1].lower() not in (".yaml", ".yml"):
        raise GeometryError(f"{args.source}: neither an HDF5 trajectory nor a YAML profile")
    J, k, name = profile_moments(args.source, args.deploysim, args.stage)
    stem = os.path.splitext(os.path.basename(args.source))[0]
    return J, None, f"{stem}, stage {k} '{name}'"


def parser():
    ap = argparse.ArgumentParser(
        prog="plot_geometry.py", description=__doc__.split("\n")[0],
        epilog=__doc__[__doc__.index("Writes"):],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", nargs="?", help="trajectory (HDF5) or deployment profile (YAML)")
    ap.add_argument("--inertia", nargs=3, type=float, metavar=("A", "B", "C"),
                    help="three principal moments, any order")
    ap.add_argument("--stage", type=int, help="stage index (default: the last stage)")
    ap.add_argument("--deploysim", help="deploysim binary (for a profile)")
    ap.add_argument("--count", type=int, default=5,
                    help="polhodes drawn on each side of the separatrix (default 5)")
    ap.add_argument("-o", "--outdir", required=True, help="output folder")
    return ap


def main(argv):
    a = parser().parse_args(argv)
    try:
        if a.count < 1:
            raise GeometryError(f"--count must be >= 1, got {a.count}")
        J, run, title = load(a)
    except GeometryError as e:
        print(f"plot_geometry: {e}", file=sys.stderr)
        return 1
    figs = build_figures(J, run, a.count, title)
    os.makedirs(a.outdir, exist_ok=True)
    names = ("geometry_ellipsoid.png", "geometry_projections.png")
    for fig, name in zip(figs, names):
        fig.savefig(os.path.join(a.outdir, name), dpi=DPI)
        plt.close(fig)
    print(f"wrote {', '.join(os.path.join(a.outdir, n) for n in names)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
