#!/usr/bin/python3
"""Plots a deploysim trajectory file (HDF5, docs/file_formats.md) as PNGs.

Usage: /usr/bin/python3 tools/plot_trajectory.py TRAJECTORY.h5 [-o OUTDIR]

Writes into OUTDIR (default: next to the file, <stem>_plots/):
  momentum.png          H_B components and |H_B| against time (the seed's Fig. 3.1)
  angular_velocity.png  w_NB_B components against time
  spin_axis.png         angle between the body spin axis and h_N (the flip as seen),
                        with the located flips and 45-degree crossings marked
  inertia.png           principal moments of J(t), stages shaded
  energy.png            kinetic, stored (spring) and total energy, and the change of the
                        total against the energy ledger (the work of each source: dampers,
                        friction, motors, prescribed drives, latch and stop impacts)
  polhode.png           H_B/|H_B| on the momentum sphere and its three plane
                        projections, with the separatrix of the final inertia
                        (the seed's Figs. 2.3-2.8)
  hinge_angles.png      hinge angles [deg] and rates [deg/s] per panel, with the hinge
                        events marked (only when the file has hinge angles: geometry mode)
On the time plots, hinge events (free-hinge profiles) are marked: releases, latches, jams
and rests as labelled vertical lines, stop impacts as ticks at the bottom, a burst of
bounces with one label.
The file is read through tools/deploysim_results.py (older version 2 files included).
Needs Debian's python3-matplotlib, python3-h5py, python3-numpy (run with /usr/bin/python3).
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from deploysim_results import TrajectoryError, read_trajectory  # noqa: E402

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
    d["events"] = sorted((dict(t=e["time"], panel=e["panel"], name=e["panel_name"],
                               kind=e["kind"], angle=e["angle"],
                               dissipated=e["energy_dissipated"],
                               rate_before=e["rate_before"], rate_after=e["rate_after"])
                          for e in run.hinge_events), key=lambda e: e["t"])
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
    """Stages shaded by kind, with their names (at the middle of their part inside `xlim`,
    the plot's time range when it shows only part of the run)."""
    # A hinge profile's phases are named after the events, which are marked themselves:
    # shade them without labels.
    label = label and not d["events"]
    x0, x1 = xlim if xlim is not None else (d["stage_begin"][0], d["stage_end"][-1])
    for i, (a, b) in enumerate(zip(d["stage_begin"], d["stage_end"])):
        law = d["stage_law"][i]
        color = STAGE_COLORS["hold" if law == "hold" else "free" if law == "free" else "move"]
        ax.axvspan(a, b, color=color, zorder=0, lw=0)
        va, vb = max(a, x0), min(b, x1)
        if label and len(d["stage_begin"]) > 1 and vb > va:
            ax.text((va + vb) / 2, 0.985, d["stage_name"][i], transform=ax.get_xaxis_transform(),
                    ha="center", va="top", fontsize=7, color="0.3", rotation=90 if
                    (vb - va) < 0.08 * (x1 - x0) else 0,
                    zorder=5, bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none",
                                        alpha=0.7))
    if label:
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


def mark_events(ax, d, labels=True, xlim=None):
    """Hinge events on a time axis. Returns legend handles for the kinds shown.

    Releases, latches, jams and rests: a vertical line each. Stop impacts: ticks at the
    bottom, one label per burst of bounces ('93 stops wing_plus_x'). Labels stand in a
    band at the top of the plot (reserve_label_bands makes room for it); labels of events
    closer than 1.8% of the time span are stacked into one block."""
    # A release at the run's start (a hinge free from the start) says nothing: not shown.
    evs = [e for e in d["events"] if not (e["kind"] == "release" and e["t"] <= d["time"][0])]
    if not evs:
        return []
    handles = {}
    lines = [e for e in evs if e["kind"] != "stop"]
    bursts = stop_bursts(d)
    for e in lines:
        st = EVENT_STYLE.get(e["kind"], EVENT_STYLE["latch"])
        ax.axvline(e["t"], zorder=2, alpha=0.85, **st)
        handles.setdefault(e["kind"], Line2D([], [], **st, label=e["kind"]))
    tr = ax.get_xaxis_transform()
    for burst in bursts:
        for e in burst:
            ax.plot([e["t"], e["t"]], [0.0, 0.035], transform=tr, color=STOP_COLOR, lw=0.7,
                    zorder=6)
    if bursts:
        handles["stop"] = Line2D([], [], color=STOP_COLOR, lw=0.7, marker="|", ls="none",
                                 markersize=8, label="stop impact (tick)")
    if labels:
        items = [(e["t"], f"{e['kind']} {e['name']}",
                  EVENT_STYLE.get(e["kind"], {}).get("color", "k")) for e in lines]
        for b in bursts:
            n = len(b)
            items.append((b[0]["t"], f"{n} stops {b[0]['name']}" if n > 1
                          else f"stop {b[0]['name']}", STOP_COLOR))
        items.sort(key=lambda x: x[0])
        t0, dt = (d["time"][0], span(d)) if xlim is None else (xlim[0], xlim[1] - xlim[0])
        # A label line is about 13 px thick, 1.8% of the plot's width: the labels of closer
        # events are stacked side by side in one block (at most 3 lines, then "+N").
        groups = []
        for item in items:
            if groups:
                g = groups[-1]
                if item[0] - g[-1][0] < 0.018 * dt * min(len(g), 3):
                    g.append(item)
                    continue
            groups.append([item])
        ax._event_labels = []
        for group in groups:
            label = merge_labels([x[1] for x in group])
            t = group[0][0]
            if not t0 <= t <= t0 + dt:
                continue
            ax._event_labels.append(ax.text(t, 0.985, label, transform=tr, rotation=90,
                    ha="right" if t - t0 > 0.97 * dt else "left", va="top", fontsize=6.5,
                    linespacing=1.1, zorder=6, clip_on=True,
                    color=group[0][2] if len({x[2] for x in group}) == 1 else "0.15",
                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8)))
    order = ["release", "latch", "jam", "rest", "lift-off", "stick", "slip", "stop"]
    return [handles[k] for k in order if k in handles]


def merge_labels(texts):
    """The label of events close in time, one line each (rotated: side by side); the same
    kind on several panels on one line: 'latch wing_plus_x, wing_minus_x'."""
    lines = []
    for t in texts:
        kind, _, name = t.partition(" ")
        if lines and lines[-1][0] == kind and not kind[0].isdigit() and len(lines[-1][1]) < 3:
            lines[-1][1].append(name)
        else:
            lines.append((kind, [name]))
    shown = [f"{k} {', '.join(n)}" for k, n in lines[:3]]
    if len(lines) > 3:
        shown[-1] += f" (+{sum(len(n) for _, n in lines[3:])} more)"
    return "\n".join(shown)


def reserve_label_bands(fig):
    """Raises the top of every axes with event labels so that the data stays below them:
    the labels' lowest edge is measured on the laid-out figure (a stack of long labels
    reaches further down than a short one)."""
    labelled = [ax for ax in fig.axes if getattr(ax, "_event_labels", False)]
    if not labelled:
        return
    fig.canvas.draw()
    for ax in labelled:
        box = ax.get_window_extent()
        low = min((t.get_window_extent().y0 - box.y0) / box.height for t in ax._event_labels)
        lo, hi = ax.get_ylim()
        ax.set_ylim(lo, lo + (hi - lo) / max(low - 0.03, 0.3))


def legend(ax, d, event_handles, **kw):
    """The axes' legend with the hinge events' kinds; with events (whose labels fill the
    band at the top), outside the plot on the right, so that it hides neither."""
    handles, labels = ax.get_legend_handles_labels()
    handles += event_handles
    labels += [h.get_label() for h in event_handles]
    if event_handles:
        kw = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    ax.legend(handles, labels, fontsize=8, framealpha=0.9, **kw)


def finish(fig, ax, path, title, d, xlim=None):
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
    reserve_label_bands(fig)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_momentum(d, out):
    t, H = d["time"], d["H_B"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
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
    fig, ax = plt.subplots(figsize=(10, 4.8))
    shade_stages(ax, d)
    ev = mark_events(ax, d)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, w[:, i], color=c, lw=1.0, label=rf"$\omega_{{{'xyz'[i]}}}$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"angular velocity $\omega_{NB}^B$ [rad/s]")
    legend(ax, d, ev, loc="upper right")
    finish(fig, ax, os.path.join(out, "angular_velocity.png"), "body angular velocity", d)


def plot_spin_axis(d, out):
    t = d["time"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
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
    fig, ax = plt.subplots(figsize=(10, 4.8))
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
        fig, ax = plt.subplots(figsize=(10, 4.8))
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
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(10, 6.4), sharex=True,
                                  gridspec_kw=dict(height_ratios=[2, 1]))
    for a in (ax, ax2):
        shade_stages(a, d, label=a is ax)
    ev = mark_events(ax, d)
    mark_events(ax2, d, labels=False)
    ax.plot(t, T, color="tab:blue", lw=1.1, label="kinetic $T$")
    if springs:
        ax.plot(t, V, color="tab:orange", lw=1.1, label="stored in springs $V$")
        ax.plot(t, E, color="k", lw=1.6, label="total $E = T + V$")
    ax.set_ylabel("energy [J]")
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


def plot_hinge_angles(d, out):
    th = d["hinge_angles"]
    t = d["time"]
    rates = d["hinge_rates"]
    xlim = hinge_activity_window(d)
    rows = 2 if rates is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(10, 3.4 + 2.6 * rows), sharex=True,
                             squeeze=False)
    axes = axes[:, 0]
    cmap = plt.get_cmap("tab10")
    for a in axes:
        shade_stages(a, d, label=a is axes[0], xlim=xlim)
    ev = mark_events(axes[0], d, xlim=xlim)
    for a in axes[1:]:
        mark_events(a, d, labels=False)
    # Rotors (a hinge that turns more than a full turn) would flatten every other curve:
    # their angle is left out (its turns are named in the legend), their rate goes on a
    # right-hand axis of its own.
    deg = np.degrees(th)
    spinning = [k for k in range(th.shape[1]) if np.ptp(deg[:, k]) > 360.0]
    right = axes[1].twinx() if rates is not None and spinning else None
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


def plot_polhode(d, out):
    H = d["H_B"]
    h = H / np.linalg.norm(H, axis=1)[:, None]
    t = d["time"]
    fig = plt.figure(figsize=(12, 9))
    ax3 = fig.add_subplot(2, 2, 1, projection="3d")
    u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:16j]
    ax3.plot_wireframe(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.85",
                       lw=0.4)
    cmap = plt.get_cmap("tab10")
    stage_idx = np.clip(np.searchsorted(d["stage_end"], t, side="left"), 0, len(d["stage_end"]) - 1)
    circles = separatrix_circles(d["J_B"][-1])
    planes = [(0, 1), (1, 2), (0, 2)]
    axes2 = [fig.add_subplot(2, 2, k + 2) for k in range(3)]
    for k in range(len(d["stage_end"])):
        sel = stage_idx == k
        if not np.any(sel):
            continue
        lab = d["stage_name"][k]
        ax3.plot(h[sel, 0], h[sel, 1], h[sel, 2], color=cmap(k % 10), lw=0.8, label=lab)
        for ax, (i, j) in zip(axes2, planes):
            ax.plot(h[sel, i], h[sel, j], color=cmap(k % 10), lw=0.8, label=lab)
    for c_i, c in enumerate(circles):
        lab = "separatrix (final J)" if c_i == 0 else None
        ax3.plot(c[:, 0], c[:, 1], c[:, 2], color="k", lw=0.8, ls="--", label=lab)
        for ax, (i, j) in zip(axes2, planes):
            ax.plot(c[:, i], c[:, j], color="k", lw=0.6, ls="--", label=lab)
    ax3.set_xlabel(r"$H_x/|H|$")
    ax3.set_ylabel(r"$H_y/|H|$")
    ax3.set_zlabel(r"$H_z/|H|$")
    ax3.set_title("polhode on the momentum sphere", fontsize=9)
    ax3.legend(fontsize=7, loc="upper left")
    for ax, (i, j) in zip(axes2, planes):
        ax.set_xlabel(rf"$H_{'xyz'[i]}/|H|$ [-]")
        ax.set_ylabel(rf"$H_{'xyz'[j]}/|H|$ [-]")
        ax.set_aspect("equal")
        ax.set_xlim(-1.05, 1.05)
        ax.set_ylim(-1.05, 1.05)
        ax.grid(True, lw=0.3, alpha=0.6)
        ax.set_title(f"projection on the {'xyz'[i]}{'xyz'[j]} plane", fontsize=9)
    axes2[0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"{d['name']}: polhodes (normalized body momentum)", fontsize=11)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "polhode.png"), dpi=110)
    plt.close(fig)


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
