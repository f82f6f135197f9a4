#!/usr/bin/python3
"""Reproduces the seed thesis's time series, Figs. 3.1-3.3, each beside its closed form.

For each shipped profile (deployment_profiles/wing_nut.yaml: Fig. 3.1, the wing nut's
flips; seed_limit_j2_to_j1.yaml: Fig. 3.2; seed_limit_j2_to_j3.yaml: Fig. 3.3) it runs
`deploysim simulate` twice, with the seed's numerical scheme (default: explicit Euler,
`--method thesis-euler`, with the seed's step h = 2e-5 s) and with the closed form
(`--method exact`: the Jacobi elliptic solution, or the sin/cos limits 3.17-3.23), and
writes OUTDIR/seed_fig3_<n>_<profile>.png: H1, H2, H3 (the seed's colours red, green,
blue) and |H| (black) against time for both runs, side by side, and their difference.

In these three models the body axes x, y, z carry J1 >= J2 >= J3, so the body components
of H_B are the thesis's H1C, H2C, H3C (checked; a profile without it is refused).

Examples:
  /usr/bin/python3 tools/plot_seed_figures.py --deploysim build/release/bin/deploysim -o seed
  /usr/bin/python3 tools/plot_seed_figures.py --deploysim BIN --method rk4 --step 1e-3 -o seed
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy (run with /usr/bin/python3).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

import plot_trajectory  # sets the Agg backend
from plot_trajectory import read

import matplotlib.pyplot as plt  # noqa: E402

assert plot_trajectory

DPI = 150
SEED_STEP = 2e-5                       # s, the seed's Euler step (its listing: h = 0.00002)
COLORS = ("red", "green", "blue")      # H1C, H2C, H3C as in the seed's Figs. 3.1-3.3
SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIGURES = [  # (figure number, profile stem, caption)
    ("3.1", "wing_nut", "Dzhanibekov wing nut: flips about the intermediate axis"),
    ("3.2", "seed_limit_j2_to_j1", r"$J_2 \to J_1$: $H_3$ constant, no flip (3.16-3.19)"),
    ("3.3", "seed_limit_j2_to_j3", r"$J_2 \to J_3$: $H_1$ constant, no flip (3.20-3.23)"),
]


def simulate(deploysim, profile, out, method, step=None):
    cmd = [deploysim, "simulate", profile, "-q", "--method", method, "-o", out]
    if step is not None:
        cmd += ["--step", repr(step)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        err = (r.stderr.strip().splitlines() or ["failed"])[-1]
        raise RuntimeError(f"{profile}: deploysim simulate --method {method}: {err}")
    d = read(out)
    J = d["J_B"][0]
    if np.abs(J - np.diag(np.diag(J))).max() > 0 or np.any(np.diff(np.diag(J)) > 0):
        raise RuntimeError(f"{profile}: body axes x, y, z do not carry J1 >= J2 >= J3")
    return d


def series(ax, t, H, title):
    for i in range(3):
        ax.plot(t, H[:, i], color=COLORS[i], lw=0.9, label=rf"$H_{{{i + 1}C}}$")
    ax.plot(t, np.linalg.norm(H, axis=1), color="k", lw=1.1, label=r"$\|\mathbf{H}_C\|$")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel("t [s]")
    ax.grid(True, lw=0.3, alpha=0.6)


def figure(num, caption, name, num_run, exact_run, scheme):
    """One seed figure: the numerical run, the closed form and their difference."""
    t = num_run["time"]
    if not np.array_equal(t, exact_run["time"]):
        raise RuntimeError(f"{name}: the two runs are sampled at different times")
    Hn, He = num_run["H_B"], exact_run["H_B"]
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.6))
    series(axes[0], t, Hn, f"numerical: {scheme}")
    series(axes[1], t, He, "closed form (--method exact)")
    lim = 1.08 * np.abs(np.concatenate([Hn, He])).max()
    for ax in axes[:2]:
        ax.set_ylim(-lim, lim)
        ax.set_ylabel(r"$H$ [kg m$^2$/s]")
    diff = Hn - He
    for i in range(3):
        axes[2].plot(t, diff[:, i], color=COLORS[i], lw=0.9,
                     label=rf"$\Delta H_{{{i + 1}C}}$")
    axes[2].plot(t, np.linalg.norm(Hn, axis=1) - np.linalg.norm(He, axis=1), color="k",
                 lw=1.1, label=r"$\Delta\|\mathbf{H}_C\|$")
    axes[2].set_title("numerical - closed form: max "
                      f"{np.abs(diff).max() / np.abs(He).max():.2g} of max |H|", fontsize=9)
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel(r"$\Delta H$ [kg m$^2$/s]")
    axes[2].grid(True, lw=0.3, alpha=0.6)
    h, lab = axes[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=9, frameon=False)
    axes[2].legend(loc="upper left", fontsize=7, ncol=4)
    fig.suptitle(f"seed thesis Fig. {num}, {name}: {caption}", fontsize=11)
    fig.subplots_adjust(left=0.05, right=0.98, bottom=0.2, top=0.86, wspace=0.28)
    return fig, float(np.abs(diff).max())


def build_figures(deploysim, method, step):
    """[(png name, figure, max |numerical - closed form|)] for the three seed figures."""
    scheme = f"--method {method}" + (f" --step {step:g} s" if step is not None else "")
    figs = []
    with tempfile.TemporaryDirectory() as tmp:
        for num, stem, caption in FIGURES:
            profile = os.path.join(SOURCE, "deployment_profiles", stem + ".yaml")
            num_run = simulate(deploysim, profile, os.path.join(tmp, "num.h5"), method, step)
            exact = simulate(deploysim, profile, os.path.join(tmp, "exact.h5"), "exact")
            fig, err = figure(num, caption, stem, num_run, exact, scheme)
            figs.append((f"seed_fig{num.replace('.', '_')}_{stem}.png", fig, err))
    return figs


def main(argv):
    ap = argparse.ArgumentParser(
        prog="plot_seed_figures.py", description=__doc__.split("\n")[0],
        epilog=__doc__[__doc__.index("For each"):],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--deploysim", help="deploysim binary (default: $DEPLOYSIM_BIN, PATH)")
    ap.add_argument("--method", default="thesis-euler",
                    help="the numerical scheme (default thesis-euler, the seed's)")
    ap.add_argument("--step", type=float,
                    help=f"its fixed step [s] (default for thesis-euler: {SEED_STEP})")
    ap.add_argument("-o", "--outdir", required=True, help="output folder")
    a = ap.parse_args(argv)
    exe = a.deploysim or os.environ.get("DEPLOYSIM_BIN") or shutil.which("deploysim")
    if not exe:
        print("plot_seed_figures: no deploysim binary (--deploysim)", file=sys.stderr)
        return 1
    step = a.step if a.step is not None else SEED_STEP if a.method == "thesis-euler" else None
    try:
        figs = build_figures(exe, a.method, step)
    except (RuntimeError, OSError, KeyError) as e:
        print(f"plot_seed_figures: {e}", file=sys.stderr)
        return 1
    os.makedirs(a.outdir, exist_ok=True)
    for name, fig, err in figs:
        fig.savefig(os.path.join(a.outdir, name), dpi=DPI)
        plt.close(fig)
        print(f"wrote {os.path.join(a.outdir, name)} (max |numerical - closed form| "
              f"{err:.3g} kg m^2/s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
