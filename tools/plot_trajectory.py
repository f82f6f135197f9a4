#!/usr/bin/python3
"""Plots a deploysim trajectory file (HDF5, docs/file_formats.md) as PNGs.

Usage: /usr/bin/python3 tools/plot_trajectory.py TRAJECTORY.h5 [-o OUTDIR]

Writes into OUTDIR (default: next to the file, <stem>_plots/):
  momentum.png          H_B components and |H_B| against time (the seed's Fig. 3.1)
  angular_velocity.png  w_NB_B components [deg/s] against time
  spin_axis.png         angle between the body spin axis and h_N (the flip as seen),
                        with the located flips and 45-degree crossings marked
  inertia.png           principal moments of J(t), stages shaded
  energy.png            kinetic, stored (spring) and total energy, and the change of the
                        total against the energy ledger (the work of each source: dampers,
                        friction, motors, prescribed drives, latch and stop impacts)
  polhode.png           H_B/|H_B| on the momentum sphere and its three plane
                        projections, a colour per stage, with the separatrix of the final
                        inertia (the seed's Figs. 2.3-2.8); below, one small panel per
                        stage, zoomed to it, against the separatrix of its own inertia
  hinge_angles.png      hinge angles [deg] and rates [deg/s] per panel, with the hinge
                        events marked (only when the file has hinge angles: geometry mode)
Units: time s, angles deg, rates deg/s, on every plot; every axis names its unit.
On the time plots, hinge events (free-hinge profiles) are marked: releases, latches, jams,
rests, lift-offs, sticks and slips as vertical lines, stop impacts as ticks at the bottom.
Each event (a burst of bounces: one) has a number, the same on every plot, in a strip
above the axes (the data keep their own range); the key under the plot says what and when
each number is. Stage profiles have their stage names in that strip.
Each PNG carries its axes' labels and limits and the numbered events as JSON in a tEXt
chunk "deploysim-axes" (what tests/tools/plots_render_test.sh checks).
The file is read through tools/deploysim_results.py (older version 2 files included).
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy (run with /usr/bin/python3).
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.font_manager  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.transforms as transforms  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from deploysim_results import TrajectoryError, read_trajectory  # noqa: E402
from deploysim_scene import bending_owners, hinge_channels  # noqa: E402

STAGE_COLORS = {"hold": "#f2f2f2", "move": "#dde8f5", "free": "#e4f2e0"}

# Hinge events: line colour and style of the labelled vertical lines.
EVENT_STYLE = {
    "release": dict(color="#1b7837", ls="--", lw=0.9),
    "latch": dict(color="#b2182b", ls="-", lw=1.0),
    "jam": dict(color="tab:purple", ls="-", lw=1.2),
    "rest": dict(color="tab:brown", ls=":", lw=1.1),
    "lift-off": dict(color="tab:olive", ls="-.", lw=1.0),
    "stick": dict(color="tab:gray", ls=":", lw=1.1),
    "slip": dict(color="tab:cyan", ls="-.", lw=1.0),
}
STOP_COLOR = "0.3"
EVENT_MARKERS = {"release": "^", "latch": "s", "jam": "X", "rest": "D", "lift-off": "v",
                 "stick": "o", "slip": "P", "stop": "|"}


# The energy ledger's terms (/work_<term>), their labels and colours.
LEDGER = ("damper", "friction", "motor", "drive", "impacts")
LEDGER_STYLE = {
    "damper": ("dampers", "tab:blue"),
    "friction": ("friction", "tab:brown"),
    "motor": ("motors", "tab:green"),
    "drive": ("prescribed drives", "tab:purple"),
    "impacts": ("latch and stop impacts", "tab:red"),
}


# The per-sample datasets the plots draw (hinge angles and rates where the file has them).
PLOTTED = ("time", "H_B", "w_NB_B", "J_B", "principal_moments", "spin_axis_angle", "energy",
           "energy_rigid", "energy_spring", "energy_total")


def read(path):
    """The trajectory file as the plots use it: a dict of its per-sample arrays, events and
    stage stretches (tools/deploysim_results.py reads it; TrajectoryError if it cannot)."""
    run = read_trajectory(path)
    d = {k: run[k] for k in PLOTTED}
    d["hinge_angles"], d["hinge_rates"] = run.get("hinge_angles"), run.get("hinge_rates")
    # The energy ledger (files written before it have none).
    ledger = {k: run.get("work_" + k) for k in LEDGER}
    d["ledger"] = ledger if all(v is not None for v in ledger.values()) else None
    d["flips"] = run.flip_time
    d["panel_names"] = run.panel_names
    d["latch_time"] = run["hinge_latch_time"]
    d["cross45"] = run.spin_axis_45_time
    # The appendages' generated hinges are free from the start and carry no other event:
    # their releases are left out, as the CLI's text leaves them out.
    d["appendages"] = run.appendages
    owner = bending_owners(d["appendages"])
    d["events"] = sorted((dict(t=e["time"], panel=e["panel"], name=e["panel_name"],
                               kind=e["kind"], angle=e["angle"],
                               dissipated=e["energy_dissipated"],
                               rate_before=e["rate_before"], rate_after=e["rate_after"])
                          for e in run.hinge_events if int(e["panel"]) not in owner),
                         key=lambda e: e["t"])
    st = run.stage_columns
    begin, end, names, laws = st["t_begin"], st["t_end"], st["name"], st["law"]
    d["name"] = run.profile_name
    # Consecutive stages with the same name and law are one stretch on the plots (a hinge
    # profile's phases: every stop bounce starts a new phase of the same hinges).
    d["stage_begin"], d["stage_end"], d["stage_name"], d["stage_law"] = [], [], [], []
    for a, b, nm, law in zip(begin, end, names, laws):
        if d["stage_name"] and d["stage_name"][-1] == nm and d["stage_law"][-1] == law:
            d["stage_end"][-1] = b
            continue
        d["stage_begin"].append(a)
        d["stage_end"].append(b)
        d["stage_name"].append(nm)
        d["stage_law"].append(law)
    d["stage_begin"] = np.array(d["stage_begin"])
    d["stage_end"] = np.array(d["stage_end"])
    return d


def span(d):
    return max(d["time"][-1] - d["time"][0], 1e-300)


def shade_stages(ax, d, label=True, xlim=None):
    """Stages shaded by kind; with label, their names in the strip above the axes (at the
    middle of their part inside `xlim`, the plot's time range when it shows only part of
    the run), so that no name covers a curve."""
    # A hinge profile's phases are named after the events, which are marked themselves:
    # shade them without labels.
    label = label and not d["events"]
    x0, x1 = xlim if xlim is not None else (d["stage_begin"][0], d["stage_end"][-1])
    names = []
    for i, (a, b) in enumerate(zip(d["stage_begin"], d["stage_end"])):
        law = d["stage_law"][i]
        color = STAGE_COLORS["hold" if law == "hold" else "free" if law == "free" else "move"]
        ax.axvspan(a, b, color=color, zorder=0, lw=0)
        va, vb = max(a, x0), min(b, x1)
        if label and len(d["stage_begin"]) > 1 and vb > va:
            names.append(dict(t=(va + vb) / 2, text=d["stage_name"][i], color="0.25",
                              edge="none"))
    if names:
        ax._strip = names
        for a in d["stage_begin"][1:]:
            ax.axvline(a, color="0.6", lw=0.6, ls=":", zorder=1)


def stop_bursts(d):
    """The stop impacts grouped into bursts: a panel's consecutive stops (the bounces
    between its release and its rest or latch; other panels' events do not split them)."""
    bursts, open_burst = [], {}
    for e in d["events"]:
        p = e["panel"]
        if e["kind"] == "stop":
            if p not in open_burst:
                open_burst[p] = []
                bursts.append(open_burst[p])
            open_burst[p].append(e)
        else:
            open_burst.pop(p, None)
    return bursts


def time_decimals(d):
    """Decimals of the event times in the key: 0.01 s on a 100-999 s run, 0.001 s on a
    10-99 s run."""
    return int(min(4, max(1, 4 - np.floor(np.log10(span(d))))))


def event_items(d):
    """The hinge events the time plots mark, numbered 1, 2, ... in time order (the same
    numbers on every plot): one item per release, latch, jam, rest, lift-off, stick or
    slip (several panels at the same time with the same kind: one item naming them all)
    and one per burst of stop impacts. Each: dict(n, t, t_end, kind, names, count, color,
    text), text being the key's line without the number."""
    # A release at the run's start (a hinge free from the start) says nothing: not shown.
    t_start = d["time"][0]
    items = []
    for e in d["events"]:
        if e["kind"] == "stop" or (e["kind"] == "release" and e["t"] <= t_start):
            continue
        last = items[-1] if items else None
        if last and last["kind"] == e["kind"] and last["t"] == e["t"]:
            last["names"].append(e["name"])
            continue
        items.append(dict(t=e["t"], t_end=e["t"], kind=e["kind"], names=[e["name"]], count=1))
    for b in stop_bursts(d):
        items.append(dict(t=b[0]["t"], t_end=b[-1]["t"], kind="stop", names=[b[0]["name"]],
                          count=len(b)))
    items.sort(key=lambda x: (x["t"], x["kind"]))
    dec = time_decimals(d)
    for n, it in enumerate(items, 1):
        it["n"] = n
        it["color"] = EVENT_STYLE.get(it["kind"], {}).get("color", STOP_COLOR)
        if it["kind"] == "stop" and it["count"] > 1:
            when = f"{it['t']:.{dec}f}\u2013{it['t_end']:.{dec}f} s"
            what = f"{it['count']} stops"
        else:
            when, what = f"{it['t']:.{dec}f} s", it["kind"]
        it["text"] = f"{when}  {what} {', '.join(it['names'])}"
    return items


def mark_events(ax, d, labels=True):
    """Hinge events on a time axis. Returns legend handles for the kinds shown.

    Releases, latches, jams and rests: a vertical line each. Stop impacts: ticks at the
    bottom. With labels, each event's number (event_items) stands in the strip above the
    axes, where it covers no data; the key under the plot (figure(..., key=True)) says what
    each number is."""
    t_start = d["time"][0]
    evs = [e for e in d["events"] if not (e["kind"] == "release" and e["t"] <= t_start)]
    if not evs:
        return []
    handles = {}
    for e in evs:
        if e["kind"] == "stop":
            continue
        st = EVENT_STYLE.get(e["kind"], EVENT_STYLE["latch"])
        ax.axvline(e["t"], zorder=2, alpha=0.85, **st)
        handles.setdefault(e["kind"], Line2D([], [], **st, label=e["kind"]))
    tr = ax.get_xaxis_transform()
    bursts = stop_bursts(d)
    for burst in bursts:
        for e in burst:
            ax.plot([e["t"], e["t"]], [0.0, 0.035], transform=tr, color=STOP_COLOR, lw=0.7,
                    zorder=6)
    if bursts:
        handles["stop"] = Line2D([], [], color=STOP_COLOR, lw=0.7, marker="|", ls="none",
                                 markersize=8, label="stop impact (tick)")
    if labels:
        ax._strip = [dict(t=it["t"], text=str(it["n"]), color=it["color"], edge=it["color"],
                          bold=True) for it in event_items(d)]
    order = ["release", "latch", "jam", "rest", "lift-off", "stick", "slip", "stop"]
    return [handles[k] for k in order if k in handles]


STRIP_FONT = 8.0  # pt: the strip's labels (event numbers, stage names)
STRIP_ROW = 14.0  # pt between the strip's rows


def build_strip(fig, ax):
    """The labels of ax._strip above the axes: one row if they fit side by side, else as
    many rows as needed (alternating). Each label sits over its time, or as near to it as
    its neighbours allow, with a leader line down to the axes' top at its time."""
    items = sorted(ax._strip, key=lambda x: x["t"])
    r = fig.canvas.get_renderer()
    pad = 0.25  # of the font size, the label box's padding
    for it in items:
        w, _, _ = r.get_text_width_height_descent(
            it["text"], matplotlib.font_manager.FontProperties(
                size=STRIP_FONT, weight="bold" if it.get("bold") else "normal"), ismath=False)
        it["w_px"] = w + 2 * pad * STRIP_FONT * fig.dpi / 72.0 + 4.0  # and a small gap
    width_px = ax.get_window_extent(r).width
    rows = max(1, int(np.ceil(sum(it["w_px"] for it in items) / (0.9 * width_px))))
    ax._strip_artists = []
    for k, it in enumerate(items):
        it["row"] = k % rows
        it["artist"] = ax.annotate(
            it["text"], xy=(0.0, 1.0), xycoords=ax.get_xaxis_transform(),
            xytext=(0.0, 1.0),
            textcoords=transforms.offset_copy(ax.transAxes, fig=fig,
                                              y=4.0 + STRIP_ROW * it["row"], units="points"),
            ha="center", va="bottom", fontsize=STRIP_FONT, color=it["color"],
            fontweight="bold" if it.get("bold") else "normal", annotation_clip=False,
            bbox=dict(boxstyle=f"round,pad={pad}", fc="white", ec=it["edge"], lw=0.8),
            arrowprops=dict(arrowstyle="-", color=it["color"], lw=0.6, shrinkA=0, shrinkB=0))
    ax._strip_items = items
    place_strip(fig, ax)


def place_strip(fig, ax):
    """Spreads each strip row's labels along the axes' width (axes fractions, from their
    widths in pixels on the laid-out figure): over their times where there is room."""
    items = ax._strip_items
    width_px = ax.get_window_extent(fig.canvas.get_renderer()).width
    x0, x1 = ax.get_xlim()
    for row in {it["row"] for it in items}:
        its = [it for it in items if it["row"] == row]
        f = [(it["t"] - x0) / (x1 - x0) for it in its]
        w = [it["w_px"] / width_px for it in its]
        x = list(f)
        for i in range(1, len(x)):
            x[i] = max(x[i], x[i - 1] + (w[i - 1] + w[i]) / 2)
        x[-1] = min(x[-1], 1.0 - w[-1] / 2)
        for i in range(len(x) - 2, -1, -1):
            x[i] = min(x[i], x[i + 1] - (w[i] + w[i + 1]) / 2)
        x[0] = max(x[0], w[0] / 2 - 0.02)
        for i in range(1, len(x)):
            x[i] = max(x[i], x[i - 1] + (w[i - 1] + w[i]) / 2)
        for it, xi in zip(its, x):
            it["artist"].xy = (it["t"], 1.0)
            it["artist"].xyann = (xi, 1.0)


def event_key(fig, kax, d):
    """The key under the plot: each event's number (coloured as its line) and what and
    when it was, in columns."""
    items = event_items(d)
    kax.axis("off")
    ncols = key_columns(items)
    nrows = int(np.ceil(len(items) / ncols))
    kax.set_xlim(0, 1)
    kax.set_ylim(0, 1)
    kax.text(0.0, 1.0, "Hinge events (numbered above the plot" + (
        "; the ticks at the bottom are stop impacts)" if any(it["kind"] == "stop" for it in items)
        else ")"), fontsize=8, color="0.3", va="top", ha="left")
    line = 1.0 / (nrows + 1)
    for k, it in enumerate(items):
        col, row = divmod(k, nrows)
        x, y = col / ncols, 1.0 - (row + 1.5) * line
        kax.text(x + 0.022, y, str(it["n"]), fontsize=8.5, fontweight="bold",
                 color=it["color"], ha="right", va="center")
        kax.text(x + 0.03, y, it["text"], fontsize=8.5, color="0.1", ha="left",
                 va="center")


def key_columns(items):
    """Columns of the key: three where the lines are short enough (the width of the plot,
    10 in, holds three lines of about 48 characters at 8.5 pt)."""
    longest = max(len(it["text"]) for it in items)
    return max(1, min(len(items), 3 if longest <= 46 else 2 if longest <= 72 else 1))


def figure(d, heights, width=10.0, key=True, **kw):
    """A figure of len(heights) axes [in] stacked (sharing time), and, with key and hinge
    events to mark, the event key under them. Returns fig and the list of axes."""
    items = event_items(d) if key else []
    rows = int(np.ceil(len(items) / key_columns(items))) if items else 0
    key_h = 0.3 + 0.19 * rows if items else 0.0
    fig = plt.figure(figsize=(width, sum(heights) + key_h + 0.9))
    gs = fig.add_gridspec(len(heights) + (1 if items else 0), 1,
                          height_ratios=list(heights) + ([key_h] if items else []))
    axes = []
    for k in range(len(heights)):
        axes.append(fig.add_subplot(gs[k, 0], sharex=axes[0] if axes and kw.get("sharex")
                                    else None))
    if items:
        event_key(fig, fig.add_subplot(gs[len(heights), 0]), d)
    return fig, axes


def legend(ax, d, event_handles, **kw):
    """The axes' legend with the hinge events' kinds; with events, outside the plot on the
    right, so that it hides neither the curves nor the event lines."""
    handles, labels = ax.get_legend_handles_labels()
    handles += event_handles
    labels += [h.get_label() for h in event_handles]
    if event_handles:
        kw = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.legend(handles, labels, fontsize=8, framealpha=0.9, **kw)


def finish(fig, ax, path, title, d, xlim=None):
    """Time range, notes on the shading, grid, title; lays the figure out with the strips
    of labels above the axes and saves it (with the axes' labels and limits in the PNG's
    metadata, see save)."""
    ax.set_xlim(*(xlim if xlim is not None else (d["time"][0], d["time"][-1])))
    laws = set(d["stage_law"])
    notes = []
    if laws & {"free"}:
        notes.append("shaded green: free hinges")
    if laws - {"hold", "free"}:
        notes.append("blue: panels moving" if notes else "shaded blue: panels moving")
    if notes and "hold" in laws:
        notes.append("grey: constant configuration")
    if notes:
        ax.text(1.0, -0.13, "; ".join(notes), transform=ax.transAxes, ha="right", va="top",
                fontsize=7, color="0.4")
    ax.grid(True, lw=0.3, alpha=0.6)
    fig.suptitle(f"{d['name']}: {title}", fontsize=11)
    fig.tight_layout()
    stripped = [a for a in fig.axes if getattr(a, "_strip", None)]
    for a in stripped:
        build_strip(fig, a)
    if stripped:
        # Again with the strips in the layout (they take room from the top), and the labels
        # spread on the final widths.
        fig.tight_layout()
        for a in stripped:
            place_strip(fig, a)
    save(fig, path, d)


def line_y_range(ax):
    """[min, max] of the y values the axes' curves draw in data coordinates (not the
    lines across the axes, as event lines), or None without any."""
    ys = [np.asarray(ln.get_ydata(), dtype=float) for ln in ax.get_lines()
          if ln.get_transform() == ax.transData and len(ln.get_ydata())]
    ys = [y[np.isfinite(y)] for y in ys]
    ys = [y for y in ys if len(y)]
    return [float(min(y.min() for y in ys)), float(max(y.max() for y in ys))] if ys else None


def save(fig, path, d, dpi=120):
    """Saves the PNG with, in its metadata (a tEXt chunk "deploysim-axes"), each data axes'
    x and y labels and limits, and the numbers of the hinge events marked: the plot test
    reads them to check the ranges and units of what was drawn."""
    axes = [dict(xlabel=a.get_xlabel(), ylabel=a.get_ylabel(), xlim=list(a.get_xlim()),
                 ylim=list(a.get_ylim()), ydata=line_y_range(a), title=a.get_title(),
                 strip=[it["text"] for it in getattr(a, "_strip_items", [])],
                 twin=bool(getattr(a, "_twin", False)))
            for a in fig.axes if a.axison and a.name != "3d"]
    axes += [dict(xlabel=a.get_xlabel(), ylabel=a.get_ylabel(), zlabel=a.get_zlabel(),
                  title=a.get_title()) for a in fig.axes if a.name == "3d"]
    meta = json.dumps(dict(axes=axes, events=[dict(n=it["n"], t=it["t"], kind=it["kind"],
                                                   count=it["count"], names=it["names"])
                                              for it in event_items(d)]))
    fig.savefig(path, dpi=dpi, metadata={"deploysim-axes": meta})
    plt.close(fig)


def plot_momentum(d, out):
    t, H = d["time"], d["H_B"]
    fig, (ax,) = figure(d, [3.9])
    shade_stages(ax, d)
    ev = mark_events(ax, d)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, H[:, i], color=c, lw=1.0, label=f"$H_{{{i + 1}}}$ (body {'xyz'[i]})")
    ax.plot(t, np.linalg.norm(H, axis=1), color="k", lw=1.2, label=r"$|H_B|$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"angular momentum $H_B$ [kg m$^2$/s]")
    legend(ax, d, ev, loc="upper right")
    finish(fig, ax, os.path.join(out, "momentum.png"), "body-frame angular momentum", d)


def plot_angular_velocity(d, out):
    t, w = d["time"], d["w_NB_B"]
    fig, (ax,) = figure(d, [3.9])
    shade_stages(ax, d)
    ev = mark_events(ax, d)
    # Rates in deg/s on every plot (the hinge rates too).
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, np.degrees(w[:, i]), color=c, lw=1.0, label=rf"$\omega_{{{'xyz'[i]}}}$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"angular velocity $\omega_{NB}^B$ [deg/s]")
    legend(ax, d, ev, loc="upper right")
    finish(fig, ax, os.path.join(out, "angular_velocity.png"), "body angular velocity", d)


def plot_spin_axis(d, out):
    t = d["time"]
    fig, (ax,) = figure(d, [3.9])
    shade_stages(ax, d)
    ev = mark_events(ax, d)
    ax.plot(t, np.degrees(d["spin_axis_angle"]), color="tab:purple", lw=1.2,
            label="spin axis to $h_N$")
    for i, tf in enumerate(d["flips"]):
        ax.axvline(tf, color="tab:orange", lw=0.8, ls="--", label="located flip" if i == 0 else None)
    if len(d["cross45"]):
        ax.plot(d["cross45"], np.full(len(d["cross45"]), 45.0), "o", color="tab:purple",
                ms=4, mfc="white", label="45° crossing")
    top = float(np.max(np.degrees(d["spin_axis_angle"])))
    if top < 30.0 and not len(d["flips"]):
        # A spin that stays near its axis (a stable spin, a decaying nutation): on the 0-180
        # deg scale it would be a flat line at the bottom.
        ax.set_ylim(0.0, 1.15 * max(top, 1e-6))
    else:
        ax.set_ylim(-5, 185)
        ax.set_yticks([0, 45, 90, 135, 180])
    ax.set_xlabel("time [s]")
    ax.set_ylabel("angle between body spin axis and $h_N$ [deg]")
    legend(ax, d, ev, loc="upper right")
    finish(fig, ax, os.path.join(out, "spin_axis.png"),
           f"the flip as seen ({len(d['flips'])} flips)", d)


def plot_inertia(d, out):
    t, m = d["time"], d["principal_moments"]
    fig, (ax,) = figure(d, [3.9])
    shade_stages(ax, d)
    ev = mark_events(ax, d)
    for i, (c, n) in enumerate(zip(("tab:blue", "tab:green", "tab:red"),
                                   ("minor", "intermediate", "major"))):
        ax.plot(t, m[:, i], color=c, lw=1.4, label=f"{n} $I_{i + 1}$")
    diag = np.stack([d["J_B"][:, i, i] for i in range(3)], axis=1)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, diag[:, i], color=c, lw=0.8, ls="--", alpha=0.7,
                label=f"$J_{{{'xyz'[i] * 2}}}$ (body {'xyz'[i]})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"moment of inertia [kg m$^2$]")
    legend(ax, d, ev, loc="best", ncol=2)
    finish(fig, ax, os.path.join(out, "inertia.png"),
           "principal moments of J(t) (solid) and body-axis moments (dashed)", d)


def plot_energy(d, out):
    """Kinetic T, stored spring energy V and the total E = T + V; below, for free-hinge
    runs, E - E(t0) against minus the energy dissipated at hinge events (the two coincide
    without dampers, motors and friction: E steps down at each latch, flat between).
    Runs without springs or hinge events (stage profiles): T and its rigid-body part."""
    t = d["time"]
    T, V, E = d["energy"], d["energy_spring"], d["energy_total"]
    springs = bool(np.any(V != 0.0))
    if not springs and not d["events"]:
        fig, (ax,) = figure(d, [3.9], key=False)
        shade_stages(ax, d)
        ax.plot(t, T, color="tab:blue", lw=1.2, label="kinetic $T$")
        if np.any(d["energy_rigid"] != T):
            ax.plot(t, d["energy_rigid"], color="tab:blue", lw=0.9, ls="--",
                    label=r"its rigid part $\frac{1}{2}\,\omega \cdot J_B\,\omega$")
        handles, labels = ax.get_legend_handles_labels()
        if any(law not in ("hold", "free") for law in d["stage_law"]):
            handles.append(Line2D([], [], ls="none"))
            labels.append("prescribed hinge motion: the drives do work, T is not conserved")
        ax.legend(handles, labels, fontsize=8, framealpha=0.9, loc="upper right")
        ax.set_xlabel("time [s]")
        ax.set_ylabel("energy [J]")
        finish(fig, ax, os.path.join(out, "energy.png"), "kinetic energy (no springs)", d)
        return
    fig, (ax, ax2) = figure(d, [3.5, 1.9], sharex=True)
    for a in (ax, ax2):
        shade_stages(a, d, label=a is ax)
    ev = mark_events(ax, d)
    mark_events(ax2, d, labels=False)
    ax.plot(t, T, color="tab:blue", lw=1.1, label="kinetic $T$")
    if springs:
        ax.plot(t, V, color="tab:orange", lw=1.1, label="stored in springs $V$")
        ax.plot(t, E, color="k", lw=1.6, label="total $E = T + V$")
    ax.set_ylabel("energy [J]")
    ax.set_xlabel("time [s]")
    legend(ax, d, ev, loc="upper right")
    ax.grid(True, lw=0.3, alpha=0.6)

    dE = E - E[0]
    ax2.plot(t, dE, color="k", lw=1.3, label="$E(t) - E(t_0)$")
    if d["ledger"] is not None:
        note = plot_ledger(ax2, t, dE, E[0], d["ledger"])
    else:
        note = energy_note_without_ledger(ax2, t, dE, E, d)
    scale = max(np.max(np.abs(E)), 1e-300)
    lo, hi = np.min(dE), np.max(dE)
    if hi - lo < 1e-6 * scale:  # rounding noise only: show it as the flat line it is
        mid = 0.5 * (hi + lo)
        ax2.set_ylim(mid - 1e-6 * scale, mid + 1e-6 * scale)
    handles, labels = ax2.get_legend_handles_labels()
    handles.append(Line2D([], [], ls="none"))
    labels.append(note)
    ax2.set_ylabel("change of $E$ [J]")
    ax2.set_xlabel("time [s]")
    # Right of the middle: the curves run along the top (0, the event losses) and, once
    # the hinges are done, along the bottom; the deployment's drop is usually early.
    ax2.legend(handles, labels, fontsize=7.5, framealpha=0.9, loc="center right")
    title = ("kinetic, stored (spring) and total energy" if springs
             else "kinetic energy (no springs)")
    finish(fig, ax2, os.path.join(out, "energy.png"), title, d)


def plot_ledger(ax, t, dE, E0, ledger):
    """The energy ledger under E - E(t0): each source's cumulative work (those that did
    any) and their sum, which E - E(t0) follows; the note says how closely."""
    total = np.zeros_like(dE)
    for k in LEDGER:
        w = np.asarray(ledger[k])
        total = total + w
        if np.max(np.abs(w)) > 1e-9 * max(abs(E0), 1e-300):
            name, color = LEDGER_STYLE[k]
            ax.plot(t, w, color=color, lw=1.0, label=f"work of the {name}")
    ax.plot(t, total, color="0.6", lw=1.0, ls="--", label="sum of the work (the ledger)")
    gap = np.max(np.abs(dE - total))
    return (f"max |E - E(t0) - ledger| = {gap:.2g} J ({gap / max(abs(E0), 1e-300):.2g} of "
            "E(t0)):\nevery joule accounted for, to the integration's accuracy")


def energy_note_without_ledger(ax2, t, dE, E, d):
    """Files written before the energy ledger: E - E(t0) against the losses at hinge
    events only."""
    diss = [(e["t"], e["dissipated"]) for e in d["events"] if e["dissipated"] > 0.0]
    if diss:
        times = np.array([x[0] for x in diss])
        lost = np.cumsum([x[1] for x in diss])
        steps = np.concatenate([[0.0], -lost])
        ax2.step(np.concatenate([[t[0]], times, [t[-1]]]), np.concatenate([steps, [steps[-1]]]),
                 where="post", color="tab:red", lw=1.0, ls="--",
                 label="$-$ energy dissipated at hinge events (cumulative)")
        k = np.searchsorted(times, t, side="right")
        resid = np.max(np.abs(dE - steps[k]))
        note = f"max |E - E(t0) + dissipated at events| = {resid:.2g} J"
        if resid > 1e-9 * max(abs(E[0]), 1e-300):
            note += (":\nthe work of dampers, friction and motors between the events "
                     "(not itemized in the file)")
        else:
            note += " (integration error: nothing else dissipates)"
    else:
        worst = np.max(np.abs(dE))
        rel = worst / max(abs(E[0]), 1e-300)
        note = f"max |E - E(t0)| = {worst:.2g} J ({rel:.2g} of E(t0))"
        note += (":\nthe work of dampers, friction and motors (not itemized in the file)"
                 if rel > 1e-9 else " (integration error: nothing dissipates)")
    return note


def hinge_activity_window(d):
    """(t_a, t_b) around the hinge motion and events when they fill less than a quarter of
    the run (a few seconds of deployment in a 600 s run are a sliver otherwise), else None.
    Outside the window no hinge moves (the rates are exactly 0: locked or latched)."""
    t, rates = d["time"], d["hinge_rates"]
    times = [e["t"] for e in d["events"]]
    if rates is not None:
        moving = np.nonzero(np.any(rates != 0.0, axis=1))[0]
        if len(moving):
            times += [t[max(moving[0] - 1, 0)], t[min(moving[-1] + 1, len(t) - 1)]]
    if not times:
        return None
    a, b = min(times), max(times)
    if b - a > 0.25 * span(d):
        return None
    pad = max(0.25 * (b - a), 0.01 * span(d))
    return max(t[0], a - pad), min(t[-1], b + pad)


def rates_with_jumps(t, rate, events):
    """One panel's rate samples with its impulsive events inserted (the rate before and after
    each latch, jam, stop or rest, at the event's time): the jump is drawn at the event
    instead of as a ramp to the next output sample."""
    jumps = [e for e in events if e["kind"] != "release" and e["rate_before"] is not None]
    if not jumps:
        return t, rate
    tt = np.concatenate([t, [e["t"] for e in jumps], [e["t"] for e in jumps]])
    rr = np.concatenate([rate, [e["rate_before"] for e in jumps],
                         [e["rate_after"] for e in jumps]])
    # At equal times: before, after, then the output sample (which holds the value after).
    order = np.concatenate([np.full(len(t), 2), np.zeros(len(jumps)), np.ones(len(jumps))])
    idx = np.lexsort((order, tt))
    return tt[idx], rr[idx]


def hinge_lines(d):
    """d with its hinge columns as the chart's lines (deploysim_scene.hinge_channels: an
    appendage's bending hinges summed per beam and plane) and each event's panel as its
    line's index."""
    if not d["appendages"]:
        return d
    names, columns = hinge_channels(d["panel_names"], d["appendages"])
    line_of = {cols[0]: i for i, cols in enumerate(columns) if len(cols) == 1}
    g = dict(d)
    g["panel_names"] = names
    g["hinge_angles"] = np.stack([d["hinge_angles"][:, c].sum(axis=1) for c in columns], axis=1)
    if d["hinge_rates"] is not None:
        g["hinge_rates"] = np.stack([d["hinge_rates"][:, c].sum(axis=1) for c in columns],
                                    axis=1)
    g["events"] = [dict(e, panel=line_of[e["panel"]]) for e in d["events"]
                   if e["panel"] in line_of]
    return g


def plot_hinge_angles(d, out):
    d = hinge_lines(d)
    th = d["hinge_angles"]
    t = d["time"]
    rates = d["hinge_rates"]
    xlim = hinge_activity_window(d)
    rows = 2 if rates is not None else 1
    fig, axes = figure(d, [3.0] + [2.4] * (rows - 1), sharex=True)
    cmap = plt.get_cmap("tab10")
    for a in axes:
        shade_stages(a, d, label=a is axes[0], xlim=xlim)
    ev = mark_events(axes[0], d)
    for a in axes[1:]:
        mark_events(a, d, labels=False)
    # Rotors (a hinge that turns more than a full turn) would flatten every other curve:
    # their angle is left out (its turns are named in the legend), their rate goes on a
    # right-hand axis of its own.
    deg = np.degrees(th)
    spinning = [k for k in range(th.shape[1]) if np.ptp(deg[:, k]) > 360.0]
    right = axes[1].twinx() if rates is not None and spinning else None
    if right is not None:
        right._twin = True  # its time axis is axes[1]'s (for save's metadata)
    # Line styles differ too: symmetric panels move alike and their curves coincide.
    styles = ["-", "--", "-.", ":"]
    for k in range(th.shape[1]):
        ls = styles[k % len(styles)]
        name = d["panel_names"][k]
        if k in spinning:
            axes[0].plot([], [], color=cmap(k % 10), lw=1.3, ls=ls,
                         label=f"{name}: {np.ptp(deg[:, k]) / 360.0:.4g} turns (not drawn; "
                               "rate below, right axis)")
        else:
            axes[0].plot(t, deg[:, k], color=cmap(k % 10), lw=1.3, ls=ls, label=name)
        if rates is not None:
            tk, rk = rates_with_jumps(t, rates[:, k], [e for e in d["events"] if e["panel"] == k])
            (right if k in spinning else axes[1]).plot(tk, np.degrees(rk), color=cmap(k % 10),
                                                        lw=1.0, ls=ls, label=name)
    if right is not None:
        right.set_ylabel("rate of " + ", ".join(d["panel_names"][k] for k in spinning) +
                         " [deg/s]")
        lo, hi = right.get_ylim()
        right.set_ylim(min(lo, 0.0), max(hi, 0.0) + 0.1 * (hi - lo))
    # The latch-up rate, the figure a mechanism engineer looks for, next to each latch.
    if rates is not None:
        for e in d["events"]:
            if e["kind"] in ("latch", "jam") and e["rate_before"] is not None:
                rb = np.degrees(e["rate_before"])
                axes[1].annotate(f"{e['kind']} at {abs(rb):.3g} deg/s", (e["t"], rb),
                                 xytext=(4, 0), textcoords="offset points", fontsize=7,
                                 va="center", color=cmap(e["panel"] % 10))
    # Each event as a marker on its panel's curve (shape by kind, colour by panel).
    for kind, marker in EVENT_MARKERS.items():
        sel = [e for e in d["events"] if e["kind"] == kind]
        if not sel:
            continue
        axes[0].scatter([e["t"] for e in sel], [np.degrees(e["angle"]) for e in sel],
                        marker=marker, s=16 if kind == "stop" else 34,
                        c=[cmap(e["panel"] % 10) for e in sel],
                        edgecolors="k" if kind != "stop" else None, linewidths=0.6, zorder=7)
    axes[0].set_ylabel("hinge angle [deg]")
    for a in axes:
        a.set_xlabel("time [s]")
    legend(axes[0], d, ev, loc="best")
    axes[0].grid(True, lw=0.3, alpha=0.6)
    if rates is not None:
        axes[1].set_ylabel("hinge rate [deg/s]")
        axes[1].axhline(0.0, color="0.5", lw=0.5)
    axes[-1].set_xlabel("time [s]")
    latched = [f"{d['panel_names'][k]} {lt:.4g} s" for k, lt in enumerate(d["latch_time"])
               if np.isfinite(lt)]
    title = "hinge angles" + (" and rates" if rates is not None else "")
    if latched:
        title += " (locked: " + ", ".join(latched) + ")"
    if xlim is not None:
        axes[-1].text(0.0, -0.13, f"zoom on {xlim[0]:.4g}-{xlim[1]:.4g} s of the run "
                      f"({t[0]:.4g}-{t[-1]:.4g} s): no hinge moves outside it",
                      transform=axes[-1].transAxes, ha="left", va="top", fontsize=7,
                      color="0.4")
    finish(fig, axes[-1], os.path.join(out, "hinge_angles.png"), title, d, xlim=xlim)


def separatrix_circles(J, n=400):
    """Great circles on the unit momentum sphere separating the polhode families of J.

    Each circle is n points from the angle 0 to 2 pi, starting at the intermediate axis;
    an odd n also has a sample exactly on its opposite end (plot_geometry uses that)."""
    vals, vecs = np.linalg.eigh(J)
    i1, i2, i3 = vals
    if not (i2 - i1 > 1e-9 * i3 and i3 - i2 > 1e-9 * i3):
        return []
    # x1^2 (1/i1 - 1/i2) = x3^2 (1/i2 - 1/i3) on the unit sphere: two planes through axis 2.
    a = np.sqrt(1 / i1 - 1 / i2)
    b = np.sqrt(1 / i2 - 1 / i3)
    s = np.linspace(0, 2 * np.pi, n)
    circles = []
    for sign in (1, -1):
        n = np.array([a, 0.0, -sign * b])  # plane normal in the principal frame
        n /= np.linalg.norm(n)
        u = np.array([0.0, 1.0, 0.0])
        v = np.cross(n, u)
        pts = np.outer(np.cos(s), u) + np.outer(np.sin(s), v)
        circles.append(pts @ vecs.T)  # back to body components
    return circles


def stage_colors(n):
    """n colours for the stages, as different as they come (tab10, tab20, then a ramp)."""
    if n <= 10:
        return [plt.get_cmap("tab10")(k) for k in range(n)]
    if n <= 20:
        return [plt.get_cmap("tab20")(k) for k in range(n)]
    return [plt.get_cmap("viridis")(k / (n - 1)) for k in range(n)]


POLHODE_COLUMNS = 5  # small multiples per row


def plot_polhode(d, out):
    """Top row: the polhode H_B/|H_B| of the whole run on the momentum sphere and its three
    plane projections, a colour per stage (short stages drawn over long ones, each stage's
    start a dot), with the separatrix of the final inertia. Below, small multiples: one
    panel per stage, zoomed to it and seen along the body axis nearest its mean momentum,
    the other stages in grey and the separatrix of the inertia at that stage's end; a stage
    that stays near one axis (a stowed spin, a slow deployment) is a point on the sphere
    and only its own zoomed panel shows its shape."""
    H = d["H_B"]
    h = H / np.linalg.norm(H, axis=1)[:, None]
    t = d["time"]
    n_st = len(d["stage_end"])
    # A sample on a stage boundary belongs to both stages: the curves join.
    sel = [np.nonzero((t >= a) & (t <= b))[0] for a, b in zip(d["stage_begin"], d["stage_end"])]
    shown = [k for k in range(n_st) if len(sel[k])]
    colors = stage_colors(n_st)
    dec = time_decimals(d)
    labels = [f"{k + 1}. {d['stage_name'][k]} ({d['stage_begin'][k]:.{dec}f}\u2013"
              f"{d['stage_end'][k]:.{dec}f} s)" for k in range(n_st)]
    sm_rows = int(np.ceil(len(shown) / POLHODE_COLUMNS))
    fig = plt.figure(figsize=(14, 3.1 + 3.0 * sm_rows + 0.5))
    outer = fig.add_gridspec(1 + sm_rows, 1, height_ratios=[3.1] + [3.0] * sm_rows)
    # (an empty column right of the sphere: its z label reaches into the next panel)
    top = outer[0].subgridspec(1, 6, width_ratios=[1.15, 0.15, 1, 1, 1, 1.0], wspace=0.5)
    ax3 = fig.add_subplot(top[0], projection="3d")
    u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:16j]
    ax3.plot_wireframe(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.85",
                       lw=0.4)
    planes = [(0, 1), (1, 2), (0, 2)]
    axes2 = [fig.add_subplot(top[k + 2]) for k in range(3)]
    # Long stages first: a short one (a few samples) drawn over them stays visible.
    for z, k in enumerate(sorted(shown, key=lambda k: -len(sel[k]))):
        s = sel[k]
        ax3.plot(h[s, 0], h[s, 1], h[s, 2], color=colors[k], lw=1.0 + 0.4 * (z > 0))
        ax3.scatter(*h[s[0]], color=colors[k], s=14, depthshade=False)
        for ax, (i, j) in zip(axes2, planes):
            ax.plot(h[s, i], h[s, j], color=colors[k], lw=1.0 + 0.4 * (z > 0), zorder=3 + z)
            ax.plot(h[s[0], i], h[s[0], j], "o", color=colors[k], ms=4, mec="k", mew=0.4,
                    zorder=30 + z)
    circles = separatrix_circles(d["J_B"][-1])
    for c in circles:
        ax3.plot(c[:, 0], c[:, 1], c[:, 2], color="k", lw=0.8, ls="--")
        for ax, (i, j) in zip(axes2, planes):
            ax.plot(c[:, i], c[:, j], color="k", lw=0.6, ls="--", zorder=2)
    ax3.set_xlabel(r"$H_x/|H|$ [-]", fontsize=8)
    ax3.set_ylabel(r"$H_y/|H|$ [-]", fontsize=8)
    ax3.set_zlabel(r"$H_z/|H|$ [-]", fontsize=8)
    ax3.tick_params(labelsize=7)
    ax3.set_title("on the momentum sphere", fontsize=9)
    for ax, (i, j) in zip(axes2, planes):
        ax.set_xlabel(rf"$H_{'xyz'[i]}/|H|$ [-]")
        ax.set_ylabel(rf"$H_{'xyz'[j]}/|H|$ [-]")
        ax.set_aspect("equal")
        ax.set_xlim(-1.05, 1.05)
        ax.set_ylim(-1.05, 1.05)
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.set_title(f"projection on the {'xyz'[i]}{'xyz'[j]} plane", fontsize=9)
    handles = [Line2D([], [], color=colors[k], lw=1.6, marker="o", ms=4, mec="k", mew=0.4,
                      label=labels[k]) for k in shown]
    if circles:
        handles.append(Line2D([], [], color="k", lw=0.8, ls="--",
                              label="separatrix (final J; below: J at each stage's end)"))
    handles.append(Line2D([], [], color="none", label="dot: a stage's start"))
    axes2[2].legend(handles=handles, fontsize=7.5, loc="upper left", bbox_to_anchor=(1.08, 1.0),
                    borderaxespad=0.0, frameon=False)

    # The small multiples.
    for m, k in enumerate(shown):
        row, col = divmod(m, POLHODE_COLUMNS)
        sub = outer[1 + row].subgridspec(1, POLHODE_COLUMNS, wspace=0.45)
        ax = fig.add_subplot(sub[col])
        s = sel[k]
        mean = h[s].mean(axis=0)
        look = int(np.argmax(np.abs(mean)))  # seen along this body axis
        i, j = [a for a in range(3) if a != look]
        for o in shown:
            if o != k:
                ax.plot(h[sel[o], i], h[sel[o], j], color="0.8", lw=0.6, zorder=1)
        ang = np.linspace(0, 2 * np.pi, 361)
        ax.plot(np.cos(ang), np.sin(ang), color="0.6", lw=0.6, zorder=1)
        for c in separatrix_circles(d["J_B"][s[-1]]):
            ax.plot(c[:, i], c[:, j], color="k", lw=0.6, ls="--", zorder=2)
        ax.plot(h[s, i], h[s, j], color=colors[k], lw=1.3, zorder=3)
        ax.plot(h[s[0], i], h[s[0], j], "o", color=colors[k], ms=5, mec="k", mew=0.5, zorder=4)
        ax.plot(h[s[-1], i], h[s[-1], j], "s", color=colors[k], ms=4.5, mec="k", mew=0.5,
                zorder=4)
        # Zoomed to the stage (at least +-0.03 of the unit sphere, at most all of it).
        lo, hi = h[s][:, [i, j]].min(axis=0), h[s][:, [i, j]].max(axis=0)
        mid, half = (lo + hi) / 2, max(0.6 * np.max(hi - lo), 0.03)
        half = min(half, 1.08)
        mid = np.clip(mid, -1.08 + half, 1.08 - half)
        ax.set_xlim(mid[0] - half, mid[0] + half)
        ax.set_ylim(mid[1] - half, mid[1] + half)
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.tick_params(labelsize=7)
        ax.set_xlabel(rf"$H_{'xyz'[i]}/|H|$ [-]", fontsize=8, labelpad=1)
        ax.set_ylabel(rf"$H_{'xyz'[j]}/|H|$ [-]", fontsize=8, labelpad=1)
        sign = "+" if mean[look] >= 0 else "\u2212"
        ax.set_title(f"{k + 1}. {d['stage_name'][k]}\n{d['stage_begin'][k]:.{dec}f}\u2013"
                     f"{d['stage_end'][k]:.{dec}f} s, seen from {sign}{'xyz'[look]}",
                     fontsize=8, color=colors[k])
    fig.suptitle(f"{d['name']}: polhode (normalized body momentum), a colour per stage; "
                 "below, each stage zoomed (square: its end)", fontsize=11)
    fig.tight_layout()
    save(fig, os.path.join(out, "polhode.png"), d, dpi=100)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("trajectory", help="HDF5 file written by deploysim simulate")
    ap.add_argument("-o", "--outdir", help="output folder (default: <stem>_plots next to the file)")
    a = ap.parse_args(argv)
    try:
        d = read(a.trajectory)
    except TrajectoryError as e:
        print(f"plot_trajectory: {e}", file=sys.stderr)
        return 1
    out = a.outdir or os.path.splitext(a.trajectory)[0] + "_plots"
    os.makedirs(out, exist_ok=True)
    plots = [plot_momentum, plot_angular_velocity, plot_spin_axis, plot_inertia, plot_energy,
             plot_polhode]
    if d["hinge_angles"] is not None:
        plots.append(plot_hinge_angles)
    for f in plots:
        f(d, out)
    names = ", ".join(f.__name__[len("plot_"):] for f in plots)
    print(f"plots written to {out}/ ({names})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
