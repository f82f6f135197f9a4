#!/usr/bin/python3
"""Stability maps from a deploysim sweep results file (HDF5, docs/sweeps.md) as a PNG.

Usage: /usr/bin/python3 tools/plot_stability_map.py RESULTS.h5 [-o MAP.png]
           [--x COLUMN] [--y COLUMN] [--fix COLUMN=VALUE ...] [--absolute]
           [--map auto|flips|hinges|tumble] [--shock-limit DEG_S]

Panels over two swept grid parameters (default: the sweep's first two grid axes, x the
first, y the second). With Monte Carlo samples, every cell aggregates its samples.

Flip map (stage sweeps; --map flips):
  1  flip / no flip within the simulated time (with samples: the fraction that flipped);
  2  "will flip, every X s" or "stable": the torque-free motion after the end, whatever
     the simulated time (will_flip, predicted_flip_half_period; median over the samples
     that will flip, where at least half of them will; blue: stable). A slow spin that
     did not flip before the end of the run is marked by when it will, not "no flip".
     (Results files from before these columns: not drawn.)
  3  time to the first flip, from the end of the deployment (--absolute: from t = 0),
     median over the samples that flipped; grey where nothing flipped.
Hinge map (sweeps over hinge profiles, the default for them; --map hinges):
  1  latch shock: the hub's angular-velocity jump at the hardest latch (or jam or stop)
     impact (max_latch_w_jump, median over the samples), with the limit drawn: a solid
     line where the median reaches it, a dashed one where the worst sample does. The
     limit is the sweep's outcome.latch_shock_limit_deg_s, or --shock-limit.
  2  tumble, whatever the simulated time: a case tumbles if its final motion will flip
     (the spin axis is then the intermediate axis) or its final momentum cone is wider
     than the sweep's tumble angle. Colour: the median time between flips of the
     tumbling samples where at least half the samples tumble; blue: stable (fewer than
     half tumble). The share of samples that tumble is written in each cell where it
     varies over the map (up to 150 cells), and the panel states how many cases tumble
     and how many of those that do not were not fully deployed.
Tumble map (--map tumble; sweeps with the outcome columns):
  1  the outcome measured from the motion (the verdict `deploysim analyze` prints: flat
     spin, growing, decaying, flipping, ...; with samples: the most common);
  2  time to tumble: from the final phase's start (the deployment's end) to the spin axis
     45 deg from h_N, measured where the run gets there and predicted from the
     linearization's growth rate where it does not (hatched): a map that is not cut off
     at the simulated horizon (median over the samples; blue: the spin does not grow).
Other grid axes are held at their first value unless --fix COLUMN=VALUE picks another
(the nearest grid value). Units as stored in the file are converted for reading:
rad/s -> rpm (spin rates) or deg/s (shocks), rad -> deg, and a deploy_duration_scale axis
is shown as the total deployment duration in seconds (the deploy_duration column).
Log-spaced axes are drawn on log scales.
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
from matplotlib.colors import ListedColormap, LogNorm  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
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
    "spring_stiffness": "hinge spring stiffness",
    "spring_stiffness_scale": "spring stiffness scale",
    "damping": "hinge damper coefficient",
    "latch_angle": "latch angle",
    "motor_torque": "motor torque",
    "motor_torque_scale": "motor torque scale",
    "release_time": "release time",
    "release_delay": "release delay after the latch",
    "friction_torque": "hinge friction torque",
    "stick_fraction": "jam at this fraction of the swing",
}
# Stored unit -> (display unit, factor).
CONVERSIONS = {"rad/s": ("rpm", 60.0 / (2.0 * np.pi)), "rad": ("deg", 180.0 / np.pi)}
DEG = 180.0 / np.pi
STABLE = "#4575b4"
TUMBLING = "#d73027"
# Colour-bar ticks for times between flips [s].
NICE_DURATIONS = [1, 2, 5, 10, 20, 30, 60, 120, 300, 600, 1200, 1800, 3600, 7200, 18000, 36000,
                  86400, 172800, 432000, 864000]


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read(path):
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"{path}: cannot open as HDF5 ({e.strerror or e})")
    with f:
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


def duration(seconds):
    """A time between flips for a colour bar tick: s, min, h or days."""
    if not np.isfinite(seconds):
        return "never"
    if seconds < 120:
        return f"{seconds:.3g} s"
    if seconds < 7200:
        return f"{seconds / 60:.3g} min"
    if seconds < 172800:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 86400:.3g} d"


class Cells:
    """The selected cases grouped by grid cell (x index, y index)."""

    def __init__(self, col, keep, xname, yname):
        self.col = col
        self.keep = keep
        self.xs = np.unique(col[xname][keep]).astype(float)
        self.ys = np.unique(col[yname][keep]).astype(float)
        self.ix = np.searchsorted(self.xs, col[xname].astype(float))
        self.iy = np.searchsorted(self.ys, col[yname].astype(float))

    def map(self, reduce):
        """reduce(selection mask) -> value, for every cell (NaN where a cell is empty)."""
        out = np.full((len(self.ys), len(self.xs)), np.nan)
        for j in range(len(self.ys)):
            for i in range(len(self.xs)):
                sel = self.keep & (self.ix == i) & (self.iy == j)
                if sel.any():
                    out[j, i] = reduce(sel)
        return out


def median_where(values, cond):
    """reduce(): the median of `values` over the selected cases where `cond` holds."""
    def reduce(sel):
        s = sel & cond
        return np.median(values[s]) if s.any() else np.nan
    return reduce


def period_panel(fig, ax, xe, ye, period, stable_mask, title, samples, what):
    """Median time between flips (log colours), stable cells blue."""
    ax.set_facecolor("0.85")
    finite = period[np.isfinite(period)]
    stable = np.where(stable_mask, 1.0, np.nan)
    ax.pcolormesh(xe, ye, np.ma.masked_invalid(stable), cmap=ListedColormap([STABLE]),
                  vmin=0, vmax=1, shading="flat")
    if finite.size:
        lo, hi = finite.min(), finite.max()
        if hi <= lo * 1.01:
            lo, hi = lo / 1.1, hi * 1.1
        m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(period), cmap="magma_r",
                          norm=LogNorm(vmin=lo, vmax=hi), shading="flat")
        ticks = [t for t in NICE_DURATIONS if lo <= t <= hi]
        cb = fig.colorbar(m, ax=ax, ticks=ticks if len(ticks) >= 2 else None)
        cb.set_label(what + (" (median)" if samples > 1 else ""))
        cb.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: duration(v)))
        cb.ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_title(title)


# Outcome name -> colour, most severe first (docs/file_formats.md, "The outcome").
OUTCOME_COLOURS = {"incomplete": "0.55", "flipping": "#67001f", "flat spin": TUMBLING,
                   "transition": "#f46d43", "growing": "#fdae61", "tumbling": "#762a83",
                   "decaying": STABLE, "bounded": "#abd9e9"}


def tumble_panels(col, cells, xe, ye, samples):
    """The tumble map: the outcome per cell and the time to tumble."""
    fig, axes = plt.subplots(1, 2, figsize=(14.5, 6.0), constrained_layout=True)
    names = list(OUTCOME_COLOURS)
    outcome = np.array([names.index(text(v)) if text(v) in names else 0 for v in col["outcome"]])
    ax = axes[0]
    mode = cells.map(lambda s: np.bincount(outcome[s], minlength=len(names)).argmax())
    ax.pcolormesh(xe, ye, mode, cmap=ListedColormap(list(OUTCOME_COLOURS.values())),
                  vmin=-0.5, vmax=len(names) - 0.5, shading="flat")
    present = [names[int(i)] for i in np.unique(mode[np.isfinite(mode)])]
    ax.legend(handles=[Patch(color=OUTCOME_COLOURS[n], label=n) for n in present],
              loc="upper right", fontsize=8, framealpha=0.85)
    ax.set_title("outcome measured from the motion"
                 + (" (most common of the samples)" if samples > 1 else ""))
    ax = axes[1]
    ttt = col["time_to_tumble"]
    measured = col["time_to_tumble_measured"] > 0
    grows = np.isfinite(ttt)
    share = cells.map(lambda s: grows[s].mean())
    median = cells.map(median_where(ttt, grows))
    period_panel(fig, ax, xe, ye, np.where(share >= 0.5, median, np.nan), share < 0.5,
                 "time to tumble (spin axis 45 deg from h_N) from the last release, latch or\n"
                 "stage change: measured, or predicted from the linear growth where hatched",
                 samples, "time to tumble")
    predicted = cells.map(lambda s: float((~measured[s] & grows[s]).mean()))
    hatch = np.ma.masked_where(~((predicted >= 0.5) & (share >= 0.5)), np.ones_like(predicted))
    handles = []
    if hatch.count():
        ax.pcolor(xe, ye, hatch, hatch="//", facecolor="none", edgecolor="0.35", lw=0)
        handles.append(Patch(facecolor="white", edgecolor="0.35", hatch="//",
                             label="predicted (not reached in the run)"))
    if (share < 0.5).any():
        handles.append(Patch(color=STABLE, label="does not grow (linearization)"))
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.85)
    return fig, axes


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
    ap.add_argument("--map", choices=("auto", "flips", "hinges", "tumble"), default="auto",
                    help="flip map, hinge map or tumble map (time to tumble; default: hinges "
                         "for sweeps of hinge profiles, else flips)")
    ap.add_argument("--shock-limit", type=float, metavar="DEG_S",
                    help="latch shock limit to draw [deg/s] (default: the sweep's own)")
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
    hinge_columns = "max_latch_w_jump" in col
    kind = args.map if args.map != "auto" else ("hinges" if hinge_columns else "flips")
    if kind == "hinges" and not hinge_columns:
        sys.exit(f"{args.results}: --map hinges needs a sweep of a hinge profile (no latch columns)")
    if kind == "tumble" and "time_to_tumble" not in col:
        sys.exit(f"{args.results}: --map tumble needs the outcome columns (time_to_tumble): "
                 "a results file of this deploysim version")

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

    cells = Cells(col, keep, xname, yname)
    samples = int(attrs.get("monte_carlo_samples", "1") or 1)
    xlog, ylog = is_log(cells.xs), is_log(cells.ys)

    def axis(name, values, log):
        """Cell edges in display units and the axis label."""
        e = edges(values, log)
        if name == "deploy_duration_scale" and "deploy_duration" in col:
            ratio = col["deploy_duration"][keep] / col[name][keep]
            if np.allclose(ratio, ratio[0], rtol=1e-9):
                return e * ratio[0], "total deployment duration (move stages) [s]"
        return convert(e, units[name]), label(name, units[name])

    xe, xlabel = axis(xname, cells.xs, xlog)
    ye, ylabel = axis(yname, cells.ys, ylog)
    # Cell centres in display units (for contours).
    xc = convert(cells.xs, units[xname]) if xname != "deploy_duration_scale" else None
    yc = convert(cells.ys, units[yname]) if yname != "deploy_duration_scale" else None

    have_prediction = "will_flip" in col
    tumble_angle = float(attrs.get("tumble_angle", "0.3490658503988659") or 0.3490658503988659)
    if kind == "tumble":
        fig, axes = tumble_panels(col, cells, xe, ye, samples)
    elif kind == "flips":
        panels = 3 if have_prediction else 2
        fig, axes = plt.subplots(1, panels, figsize=(6.6 * panels, 5.6), constrained_layout=True)
        # 1: flip / no flip within the simulated time.
        ax = axes[0]
        flipped = cells.map(lambda s: col["flipped"][s].astype(float).mean())
        if samples > 1:
            m = ax.pcolormesh(xe, ye, flipped, cmap="RdYlBu_r", vmin=0, vmax=1, shading="flat")
            cb = fig.colorbar(m, ax=ax)
            cb.set_label(f"fraction of the {samples} Monte Carlo samples that flipped")
            ax.set_title("flipped within the simulated time")
        else:
            m = ax.pcolormesh(xe, ye, flipped, cmap=ListedColormap([STABLE, TUMBLING]), vmin=0,
                              vmax=1, shading="flat")
            cb = fig.colorbar(m, ax=ax, ticks=[0.25, 0.75])
            cb.ax.set_yticklabels(["no flip (yet)", "flipped"])
            ax.set_title("Dzhanibekov flip within the simulated time")
        rest = list(axes[1:])
        # 2: will flip (whatever the horizon), every X s.
        if have_prediction:
            ax = rest.pop(0)
            will = col["will_flip"].astype(float)
            period = cells.map(median_where(col["predicted_flip_half_period"], will > 0))
            will_share = cells.map(lambda s: will[s].mean())
            period_panel(fig, ax, xe, ye, np.where(will_share >= 0.5, period, np.nan),
                         will_share < 0.5,
                         "will flip, every X s (colour) or stable (blue):\n"
                         "the motion after the end, whatever the simulated time",
                         samples, "time between flips after the end")
            if (will_share < 0.5).any():
                ax.legend(handles=[Patch(color=STABLE, label="stable: will not flip")],
                          loc="upper right", fontsize=8, framealpha=0.85)
        # 3: time to the first flip.
        ax = rest.pop(0)
        ax.set_facecolor("0.85")
        t_flip = col["first_flip_time"] - (0.0 if args.absolute else col["deploy_end_time"])
        first = cells.map(median_where(t_flip, col["flipped"] > 0))
        finite = first[np.isfinite(first)]
        if finite.size:
            m = ax.pcolormesh(xe, ye, np.ma.masked_invalid(first), cmap="viridis", shading="flat",
                              vmin=finite.min(), vmax=finite.max())
            cb = fig.colorbar(m, ax=ax)
            what = "time of the first flip [s]" if args.absolute else \
                "time from the end of deployment to the first flip [s]"
            cb.set_label(what + (" (median)" if samples > 1 else ""))
        ax.set_title("time to the first flip (grey: none within the simulated time)")
    else:
        fig, axes = plt.subplots(1, 2, figsize=(14.5, 6.0), constrained_layout=True)
        limit = args.shock_limit / DEG if args.shock_limit else (
            float(attrs["latch_shock_limit"]) if attrs.get("latch_shock_limit") else None)
        # 1: latch shock with the limit.
        ax = axes[0]
        shock = col["max_latch_w_jump"] * DEG
        med = cells.map(lambda s: np.median(shock[s]))
        worst = cells.map(lambda s: np.max(shock[s]))
        m = ax.pcolormesh(xe, ye, med, cmap="YlOrRd", shading="flat", vmin=0.0,
                          vmax=np.nanmax(med))
        cb = fig.colorbar(m, ax=ax)
        cb.set_label("hub angular-velocity jump at the hardest latch [deg/s]"
                     + (f" (median of {samples} samples)" if samples > 1 else ""))
        handles = []
        if limit is not None and xc is not None and yc is not None:
            lim = limit * DEG
            cb.ax.axhline(lim, color="k", lw=2)
            if np.nanmin(med) < lim < np.nanmax(med):
                ax.contour(xc, yc, med, levels=[lim], colors="k", linewidths=2.2)
            handles.append(Line2D([], [], color="k", lw=2.2,
                                  label=f"limit {lim:g} deg/s" + (" (median)" if samples > 1 else "")))
            above = np.ma.masked_where(~(med > lim), np.ones_like(med))
            if above.count():
                ax.pcolor(xe, ye, above, hatch="//", facecolor="none", edgecolor="0.35", lw=0)
                handles.append(Patch(facecolor="white", edgecolor="0.35", hatch="//",
                                     label="above the limit" + (" (median)" if samples > 1 else "")))
            if samples > 1 and np.nanmin(worst) < lim < np.nanmax(worst):
                ax.contour(xc, yc, worst, levels=[lim], colors="k", linewidths=1.4,
                           linestyles="dashed")
                handles.append(Line2D([], [], color="k", lw=1.4, ls="--",
                                      label=f"limit {lim:g} deg/s (worst sample)"))
            below = med <= lim
            ax.set_title(f"latch shock against the limit of {lim:g} deg/s:\n"
                         + ("below it in the plain cells, above it in the hatched ones"
                            if below.any() and (~below).any() else
                            ("below it everywhere" if below.all() else "above it everywhere")))
        else:
            ax.set_title("latch shock (no limit given: --shock-limit)")
        if handles:
            ax.legend(handles=handles, loc="lower left", fontsize=8, framealpha=0.85)
        # 2: tumble, whatever the horizon.
        ax = axes[1]
        will = col["will_flip"].astype(float)
        tumbles = (will > 0) | (col["final_class"] == "tumbling")
        share = cells.map(lambda s: tumbles[s].mean())
        period = cells.map(median_where(col["predicted_flip_half_period"], will > 0))
        period_panel(fig, ax, xe, ye, np.where(share >= 0.5, period, np.nan), share < 0.5,
                     "tumble, whatever the simulated time:\n"
                     f"will flip, every X s (colour), or cone > {tumble_angle * DEG:g} deg; "
                     "blue: stable",
                     samples, "time between flips after the deployment")
        # The share of samples that tumble, per cell, where it varies over the map.
        if samples > 1 and np.nanmax(share) > np.nanmin(share) and share.size <= 150:
            xm = np.sqrt(xe[:-1] * xe[1:]) if xlog else 0.5 * (xe[:-1] + xe[1:])
            ym = np.sqrt(ye[:-1] * ye[1:]) if ylog else 0.5 * (ye[:-1] + ye[1:])
            for j in range(share.shape[0]):
                for i in range(share.shape[1]):
                    if np.isfinite(share[j, i]):
                        ax.text(xm[i], ym[j], f"{100 * share[j, i]:.0f}%", ha="center",
                                va="center", fontsize=7,
                                color="white" if share[j, i] < 0.5 else "black")
        sel = keep
        deployed = col["all_latched"][sel] > 0
        tumbled = tumbles[sel]
        calm = ~tumbled
        lines = [f"tumble: {100 * tumbled.mean():.0f}% of the cases shown"
                 f" ({100 * np.nanmin(share):.0f}-{100 * np.nanmax(share):.0f}% per cell)",
                 f"fully deployed (every latch caught its panel): {100 * deployed.mean():.0f}%"]
        if calm.any():
            lines.append(f"no tumble: {100 * calm.mean():.0f}%, of which "
                         f"{100 * (calm & ~deployed).sum() / calm.sum():.0f}% "
                         "did not deploy fully")
        ax.text(0.02, 0.02, "\n".join(lines), transform=ax.transAxes, fontsize=8.5,
                va="bottom", ha="left", bbox=dict(boxstyle="round", fc="white", alpha=0.85))
        if (share < 0.5).any():
            ax.legend(handles=[Patch(color=STABLE, label="stable (most samples)")],
                      loc="upper right", fontsize=8, framealpha=0.85)
    plain = FuncFormatter(lambda v, _: f"{v:g}")
    for ax in axes:
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if xlog:
            ax.set_xscale("log")
        if ylog:
            ax.set_yscale("log")
        for log, a, e in ((xlog, ax.xaxis, xe), (ylog, ax.yaxis, ye)):
            if log:
                # Fewer ticks per decade over a wide range, so that the labels do not overlap.
                wide = np.log10(np.max(e) / np.min(e)) > 2.5
                a.set_major_locator(LogLocator(base=10, subs=(1.0, 3.0) if wide else
                                               (1.0, 2.0, 3.0, 5.0)))
                a.set_major_formatter(plain)
                a.set_minor_formatter(NullFormatter())
    title = f"sweep '{attrs.get('sweep_name', '')}': base profile '{attrs.get('profile_name', '')}'" \
            f" (model '{attrs.get('model_name', '')}', {attrs.get('case_count', '?')} cases" + \
            (f", {samples} Monte Carlo samples per cell" if samples > 1 else "") + ")"
    if notes:
        title += "; " + ", ".join(notes)
    fig.suptitle(title, fontsize=11)
    out = args.output or os.path.splitext(args.results)[0] + "_stability.png"
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
