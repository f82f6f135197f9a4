#!/usr/bin/python3
"""Plots a deploysim trajectory file (HDF5, docs/file_formats.md) as PNGs.

Usage: /usr/bin/python3 tools/plot_trajectory.py TRAJECTORY.h5 [-o OUTDIR]

Writes into OUTDIR (default: next to the file, <stem>_plots/):
  momentum.png          H_B components and |H_B| against time (the seed's Fig. 3.1)
  angular_velocity.png  w_NB_B components against time
  spin_axis.png         angle between the body spin axis and h_N (the flip as seen),
                        with the located flips marked
  inertia.png           principal moments of J(t), stages shaded
  polhode.png           H_B/|H_B| on the momentum sphere and its three plane
                        projections, with the separatrix of the final inertia
                        (the seed's Figs. 2.3-2.8)
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

STAGE_COLORS = {"hold": "#f2f2f2", "move": "#dde8f5"}


def read(path):
    with h5py.File(path, "r") as f:
        d = {k: f[k][()] for k in ("time", "H_B", "w_NB_B", "J_B", "principal_moments",
                                   "spin_axis_angle", "h_N", "energy")}
        d["flips"] = f["events/flip_time"][()] if "events/flip_time" in f else np.array([])
        st = f["stages"]
        d["stage_begin"] = st["t_begin"][()]
        d["stage_end"] = st["t_end"][()]
        d["stage_name"] = [n.decode() if isinstance(n, bytes) else str(n) for n in st["name"][()]]
        d["stage_law"] = [n.decode() if isinstance(n, bytes) else str(n) for n in st["law"][()]]
        d["name"] = f.attrs.get("profile_name", os.path.basename(path))
        if isinstance(d["name"], bytes):
            d["name"] = d["name"].decode()
    return d


def shade_stages(ax, d, label=True):
    for i, (a, b) in enumerate(zip(d["stage_begin"], d["stage_end"])):
        moving = d["stage_law"][i] != "hold"
        ax.axvspan(a, b, color=STAGE_COLORS["move" if moving else "hold"], zorder=0, lw=0)
        if label and len(d["stage_begin"]) > 1:
            ax.text((a + b) / 2, 0.985, d["stage_name"][i], transform=ax.get_xaxis_transform(),
                    ha="center", va="top", fontsize=7, color="0.3", rotation=90 if
                    (b - a) < 0.08 * (d["stage_end"][-1] - d["stage_begin"][0]) else 0,
                    zorder=5, bbox=dict(boxstyle="round,pad=0.15", fc="white", ec="none",
                                        alpha=0.7))
    for a in d["stage_begin"][1:]:
        ax.axvline(a, color="0.6", lw=0.6, ls=":", zorder=1)


def finish(fig, ax, path, title, d):
    ax.set_xlim(d["time"][0], d["time"][-1])
    if any(law != "hold" for law in d["stage_law"]):
        ax.text(1.0, -0.13, "shaded blue: panels moving; grey: constant configuration",
                transform=ax.transAxes, ha="right", va="top", fontsize=7, color="0.4")
    ax.grid(True, lw=0.3, alpha=0.6)
    fig.suptitle(f"{d['name']}: {title}", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_momentum(d, out):
    t, H = d["time"], d["H_B"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
    shade_stages(ax, d)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, H[:, i], color=c, lw=1.0, label=f"$H_{{{i + 1}}}$ (body {'xyz'[i]})")
    ax.plot(t, np.linalg.norm(H, axis=1), color="k", lw=1.2, label=r"$|H_B|$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"angular momentum $H_B$ [kg m$^2$/s]")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    finish(fig, ax, os.path.join(out, "momentum.png"), "body-frame angular momentum", d)


def plot_angular_velocity(d, out):
    t, w = d["time"], d["w_NB_B"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
    shade_stages(ax, d)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, w[:, i], color=c, lw=1.0, label=rf"$\omega_{{{'xyz'[i]}}}$")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"angular velocity $\omega_{NB}^B$ [rad/s]")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    finish(fig, ax, os.path.join(out, "angular_velocity.png"), "body angular velocity", d)


def plot_spin_axis(d, out):
    t = d["time"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
    shade_stages(ax, d)
    ax.plot(t, np.degrees(d["spin_axis_angle"]), color="tab:purple", lw=1.2,
            label="spin axis to $h_N$")
    for i, tf in enumerate(d["flips"]):
        ax.axvline(tf, color="tab:orange", lw=0.8, ls="--", label="located flip" if i == 0 else None)
    ax.set_ylim(-5, 185)
    ax.set_yticks([0, 45, 90, 135, 180])
    ax.set_xlabel("time [s]")
    ax.set_ylabel("angle between body spin axis and $h_N$ [deg]")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    finish(fig, ax, os.path.join(out, "spin_axis.png"),
           f"the flip as seen ({len(d['flips'])} flips)", d)


def plot_inertia(d, out):
    t, m = d["time"], d["principal_moments"]
    fig, ax = plt.subplots(figsize=(10, 4.8))
    shade_stages(ax, d)
    for i, (c, n) in enumerate(zip(("tab:blue", "tab:green", "tab:red"),
                                   ("minor", "intermediate", "major"))):
        ax.plot(t, m[:, i], color=c, lw=1.4, label=f"{n} $I_{i + 1}$")
    diag = np.stack([d["J_B"][:, i, i] for i in range(3)], axis=1)
    for i, c in enumerate(("tab:red", "tab:green", "tab:blue")):
        ax.plot(t, diag[:, i], color=c, lw=0.8, ls="--", alpha=0.7,
                label=f"$J_{{{'xyz'[i] * 2}}}$ (body {'xyz'[i]})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"moment of inertia [kg m$^2$]")
    ax.legend(loc="best", fontsize=8, framealpha=0.9, ncol=2)
    finish(fig, ax, os.path.join(out, "inertia.png"),
           "principal moments of J(t) (solid) and body-axis moments (dashed)", d)


def separatrix_circles(J):
    """Great circles on the unit momentum sphere separating the polhode families of J."""
    vals, vecs = np.linalg.eigh(J)
    i1, i2, i3 = vals
    if not (i2 - i1 > 1e-9 * i3 and i3 - i2 > 1e-9 * i3):
        return []
    # x1^2 (1/i1 - 1/i2) = x3^2 (1/i2 - 1/i3) on the unit sphere: two planes through axis 2.
    a = np.sqrt(1 / i1 - 1 / i2)
    b = np.sqrt(1 / i2 - 1 / i3)
    s = np.linspace(0, 2 * np.pi, 400)
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
    if not os.path.isfile(a.trajectory):
        print(f"plot_trajectory: {a.trajectory}: no such file", file=sys.stderr)
        return 1
    out = a.outdir or os.path.splitext(a.trajectory)[0] + "_plots"
    os.makedirs(out, exist_ok=True)
    try:
        d = read(a.trajectory)
    except (OSError, KeyError) as e:
        print(f"plot_trajectory: {a.trajectory}: not a deploysim trajectory file ({e})",
              file=sys.stderr)
        return 1
    for f in (plot_momentum, plot_angular_velocity, plot_spin_axis, plot_inertia, plot_polhode):
        f(d, out)
    print(f"plots written to {out}/ (momentum, angular_velocity, spin_axis, inertia, polhode)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
