#!/usr/bin/python3
"""Stability maps from a deploysim sweep results file (HDF5, docs/sweeps.md) as a PNG.

Usage: /usr/bin/python3 tools/plot_stability_map.py RESULTS.h5 [-o MAP.png]
           [--x COLUMN] [--y COLUMN] [--fix COLUMN=VALUE ...] [--absolute]

Two panels over two swept grid parameters (default: the sweep's first two grid axes,
x the first, y the second):
  left   flip / no flip within the simulated time (with Monte Carlo samples per grid
         point: the fraction of samples that flipped);
  right  time to the first flip, measured from the end of the deployment (the last move
         stage; --absolute: from t = 0), median over the samples that flipped; grey where
         nothing flipped.
Other grid axes are held at their first value unless --fix COLUMN=VALUE picks another
(the nearest grid value). Units as stored in the file are converted for reading:
rad/s -> rpm, rad -> deg, and a deploy_duration_scale axis is shown as the total
deployment duration in seconds (the deploy_duration column). Log-spaced axes are drawn
on log scales.
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy (run with /usr/bin/python3).
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402

# Column base name -> axis label (SI units as stored; converted below).
LABELS = {
    "deploy_duration_scale": "deployment duration scale (x the base profile's moves)",
    "stage_duration": "stage duration",
    "spin_rate": "initial spin rate",
    "nutation": "initial nutation (H_B from the spin axis)",
    "nutation_azimuth": "nutation azimuth",
    "panel_mass_scale": "panel mass scale",
    "inertia_scale": "inertia scale",
}
# Stored unit -> (display unit, factor).
CONVERSIONS = {"rad/s": ("rpm", 60.0 / (2.0 * np.pi)), "rad": ("deg", 180.0 / np.pi)}


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read(path):
    with h5py.File(path, "r") as f:
        if text(f.attrs.get("kind", "")) != "deploysim sweep results":
            sys.exit(f"{path}: not a deploysim sweep results file")
        attrs = {k: text(v) for k, v in f.attrs.items()}
        cases = f["cases"]
        columns = {}
        units = {}
        for name in attrs["columns"].split(","):
            data = cases[name][()]
            if data.dtype.kind in ("S", "O"):
                data = np.array([text(v) for v in data])
            columns[name] = data
            units[name] = text(cases[name].attrs.get("units", ""))
    return attrs, columns, units


def label(column, unit):
    base = column.split("[")[0]
    qualifier = column[len(base):]
    shown, _ = CONVERSIONS.get(unit, (unit, 1.0))
    name = LABELS.get(base, base.replace("_", " ")) + (f" {qualifier}" if qualifier else "")
    return f"{name} [{shown}]" if shown not in ("1", "none", "") else f"{name} [-]"


def convert(values, unit):
    return values * CONVERSIONS.get(unit, (unit, 1.0))[1]


def edges(centers, log):
    """Cell edges around sorted grid values (geometric midpoints on log axes)."""
    c = np.asarray(centers, dtype=float)
    if len(c) == 1:
        return np.array([c[0] * 0.9, c[0] * 1.1]) if log else np.array([c[0] - 0.5, c[0] + 0.5])
    if log:
        m = np.sqrt(c[:-1] * c[1:])
        return np.concatenate([[c[0] ** 2 / m[0]], m, [c[-1] ** 2 / m[-1]]])
    m = 0.5 * (c[:-1] + c[1:])
    return np.concatenate([[2 * c[0] - m[0]], m, [2 * c[-1] - m[-1]]])


def is_log(values):
    v = np.asarray(values, dtype=float)
    if len(v) < 3 or np.any(v <= 0):
        return False
    r = v[1:] / v[:-1]
    return np.allclose(r, r[0], rtol=1e-6) and not np.allclose(np.diff(v), np.diff(v)[0], rtol=1e-6)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results")
    ap.add_argument("-o", "--output", help="PNG to write (default: <results stem>_stability.png)")
    ap.add_argument("--x", help="grid column on the x axis")
    ap.add_argument("--y", help="grid column on the y axis")
    ap.add_argument("--fix", action="append", default=[], metavar="COLUMN=VALUE",
                    help="value of another grid column (in the file's SI units)")
    ap.add_argument("--absolute", action="store_true",
                    help="time of the first flip from t = 0 instead of from the deployment end")
    args = ap.parse_args()

    attrs, col, units = read(args.results)
    grid = [c for c in attrs.get("grid_columns", "").split(",") if c]
    if len(grid) < 2:
        sys.exit(f"{args.results}: a stability map needs a sweep with at least two grid axes "
                 f"(grid columns: {', '.join(grid) or 'none'})")
    xname = args.x or grid[0]
    yname = args.y or grid[1] if (args.y or grid[1] != xname) else grid[0]
    for name in (xname, yname):
        if name not in grid:
            sys.exit(f"{args.results}: {name} is not a grid column (grid columns: {', '.join(grid)})")
    if xname == yname:
        sys.exit("--x and --y must differ")

    # Select the cases: other grid axes fixed.
    keep = np.ones(len(col["case_index"]), dtype=bool)
    fixed = {}
    for item in args.fix:
        if "=" not in item:
            sys.exit(f"--fix {item}: expected COLUMN=VALUE")
        k, v = item.split("=", 1)
        fixed[k] = v
    notes = []
    for name in grid:
        if name in (xname, yname):
            continue
        values = np.unique(col[name])
        if name in fixed:
            want = fixed[name]
            if values.dtype.kind in ("U", "S", "O"):
                chosen = want
            else:
                chosen = values[np.argmin(np.abs(values.astype(float) - float(want)))]
        else:
            chosen = values[0]
        keep &= col[name] == chosen
        notes.append(f"{name} = {chosen}")
    if not keep.any():
        sys.exit("no cases match the --fix values")

    xs = np.unique(col[xname][keep]).astype(float)
    ys = np.unique(col[yname][keep]).astype(float)
    nx, ny = len(xs), len(ys)
    flipped = np.full((ny, nx), np.nan)
    first = np.full((ny, nx), np.nan)
    t_flip = col["first_flip_time"] - (0.0 if args.absolute else col["deploy_end_time"])
    ix = np.searchsorted(xs, col[xname].astype(float))
    iy = np.searchsorted(ys, col[yname].astype(float))
    for j in range(ny):
        for i in range(nx):
            sel = keep & (ix == i) & (iy == j)
            if not sel.any():
                continue
            f = col["flipped"][sel].astype(float)
            flipped[j, i] = f.mean()
            if f.any():
                first[j, i] = np.median(t_flip[sel][f > 0])
    samples = int(attrs.get("monte_carlo_samples", "1") or 1)

    xlog, ylog = is_log(xs), is_log(ys)

    def axis(name, values, log):
        """Cell edges in display units and the axis label."""
        e = edges(values, log)
        if name == "deploy_duration_scale" and "deploy_duration" in col:
            ratio = col["deploy_duration"][keep] / col[name][keep]
            if np.allclose(ratio, ratio[0], rtol=1e-9):
                return e * ratio[0], "total deployment duration (move stages) [s]"
        return convert(e, units[name]), label(name, units[name])

    xe, xlabel = axis(xname, xs, xlog)
    ye, ylabel = axis(yname, ys, ylog)

    fig, axes = plt.subplots(1, 2, figsize=(13, 5.4), constrained_layout=True)
    # Left: flip / no flip (or the flipped fraction).
    ax = axes[0]
    if samples > 1:
        m = ax.pcolormesh(xe, ye, flipped, cmap="RdYlBu_r", vmin=0, vmax=1, shading="flat")
        cb = fig.colorbar(m, ax=ax)
        cb.set_label(f"fraction of the {samples} Monte Carlo samples that flipped")
        ax.set_title("flip probability within the simulated time")
    else:
        cmap = ListedColormap(["#4575b4", "#d73027"])
        m = ax.pcolormesh(xe, ye, flipped, cmap=cmap, vmin=0, vmax=1, shading="flat")
        cb = fig.colorbar(m, ax=ax, ticks=[0.25, 0.75])
        cb.ax.set_yticklabels(["no flip", "flipped"])
        ax.set_title("Dzhanibekov flip within the simulated time")
    # Right: time to the first flip.
    ax = axes[1]
    ax.set_facecolor("0.85")
    finite = first[np.isfinite(first)]
    if finite.size:
        m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(first), cmap="viridis", shading="flat",
                          vmin=finite.min(), vmax=finite.max())
        cb = fig.colorbar(m, ax=ax)
        what = "time of the first flip [s]" if args.absolute else \
            "time from the end of deployment to the first flip [s]"
        cb.set_label(what + (" (median)" if samples > 1 else ""))
    ax.set_title("time to the first flip (grey: no flip)")
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    for ax in axes:
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if xlog:
            ax.set_xscale("log")
        if ylog:
            ax.set_yscale("log")
        for log, a in ((xlog, ax.xaxis), (ylog, ax.yaxis)):
            if log:
                a.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 3.0, 5.0)))
                a.set_major_formatter(plain)
                a.set_minor_formatter(NullFormatter())
    title = f"sweep '{attrs.get('sweep_name', '')}': base profile '{attrs.get('profile_name', '')}'" \
            f" (model '{attrs.get('model_name', '')}', {attrs.get('case_count', '?')} cases)"
    if notes:
        title += "; " + ", ".join(notes)
    fig.suptitle(title, fontsize=11)
    out = args.output or os.path.splitext(args.results)[0] + "_stability.png"
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
