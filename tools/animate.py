#!/usr/bin/python3
"""Renders a deploysim run to MP4 (and GIF) for slides and reports: the viewer's scene
(tools/view.py) drawn offline with matplotlib and encoded by ffmpeg.

Usage: /usr/bin/python3 tools/animate.py RESULT.h5 -o OUT.mp4 [--gif] [--fps 30]
           [--seconds 20] [--t0 T] [--t1 T] [--size 1280x720] [--model MODEL.yaml]

RESULT.h5 is a trajectory or a cross-check file (then both models side by side). The
video shows the run from --t0 to --t1 (default: all of it) in --seconds at --fps: the
body (hub and panels at their hinge angles, or the equivalent box of a tensors model)
with its axes (x red, y green, z blue), the fixed h_N (gold, pointing up), the spin axis
and its trail (magenta: the last minute, or two flip intervals), flips (white dots),
hinge releases (green) and latches (orange) and, beside it, H_B / |H| and the angle
between the spin axis and h_N with a moving marker, and the stage timeline (danger window
shaded). --gif also writes OUT.gif (same frames, 256-colour palette).

Exit status: 0 written; 1 bad input or ffmpeg failure (one line on stderr, no output
file); 2 bad usage.
Needs Debian's python3-matplotlib, python3-h5py, python3-yaml and ffmpeg.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import deploysim_scene as scene  # noqa: E402

# Box faces as corner indices; corners are (+-1/2, +-1/2, +-1/2) in bit order x, y, z.
CORNERS = np.array([[(i >> 0 & 1) - .5, (i >> 1 & 1) - .5, (i >> 2 & 1) - .5] for i in range(8)])
FACES = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
# Per part kind (deploysim_scene.SHAPE_KINDS): beam segments light grey, a slosh bob blue;
# a massless link ("link") is not drawn.
COLORS = {"hub": np.array([0.72, 0.63, 0.44]), "panel": np.array([0.16, 0.31, 0.63]),
          "beam": np.array([0.82, 0.82, 0.86]), "bob": np.array([0.25, 0.63, 0.88])}
COLORS_2 = {"hub": np.array([0.60, 0.60, 0.66]), "panel": np.array([0.48, 0.23, 0.54]),
            "beam": np.array([0.70, 0.60, 0.74]), "bob": np.array([0.55, 0.35, 0.70])}
LIGHT = np.array([0.4, -0.5, 0.77])
ROLE_COLORS = {"minor": "#33aa66", "intermediate": "#cc4444", "major": "#4477cc",
               "degenerate": "#888888"}


def view_basis(h):
    """Rows: the plot's x, y, z in N; z along h_N (right-handed)."""
    z = h / np.linalg.norm(h)
    x = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = x - z * (x @ z)
    x /= np.linalg.norm(x)
    return np.array([x, np.cross(z, x), z])


def interp_run(run, t):
    """Per side: R_NB at time t (slerp between samples), the sample index below t."""
    ts = run["time"]
    k = int(np.clip(np.searchsorted(ts, t, side="right") - 1, 0, len(ts) - 2))
    f = (t - ts[k]) / (ts[k + 1] - ts[k])
    out = []
    for s in run["sides"]:
        q0, q1 = s["q"][k], s["q"][k + 1]
        if q0 @ q1 < 0:
            q1 = -q1
        om = np.arccos(np.clip(q0 @ q1 / np.linalg.norm(q0) / np.linalg.norm(q1), -1, 1))
        if om < 1e-9:
            q = q0 + f * (q1 - q0)
        else:
            q = (np.sin((1 - f) * om) * q0 + np.sin(f * om) * q1) / np.sin(om)
        out.append(scene.quat_to_matrix(q))
    return out, k, f


def poses_interp(run, k, f, scale):
    """Boxes between samples k and k+1 (hinge angles or J_B interpolated)."""
    if run["geometry"] is not None:
        ang = (1 - f) * run["hinge"][k] + f * run["hinge"][k + 1]
        return run["geometry"].poses(ang)
    J = (1 - f) * run["J"][k] + f * run["J"][k + 1]
    return scene.tensor_poses(J, scale)[0]


def render(run, out, fps, seconds, t0, t1, size, dpi=100):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    w, h = size
    nfr = int(round(fps * seconds))
    if nfr < 2:
        raise scene.SceneError(f"--fps {fps} x --seconds {seconds}: fewer than 2 frames")
    times = np.linspace(t0, t1, nfr)
    idx = scene.decimate(run)
    scale = scene.tensor_scale(run)
    L = scene.extent(run, idx, scale) or 1.0
    nS = len(run["sides"])
    P = view_basis(run["sides"][0]["h_N"][0])
    spacing = 2.6 * L if nS > 1 else 0.0
    offsets = [np.array([0, (si - (nS - 1) / 2) * spacing, 0]) for si in range(nS)]
    _, kinds = scene.part_names(run)
    sB = run["spin_axis_B"]
    # Releases and latches are marked; stop impacts come in bursts and are not.
    events = [e for e in run["events"] if e["kind"] != "stop"]
    trail = scene.trail_seconds(run)
    ts = run["time"]

    fig = plt.figure(figsize=(w / dpi, h / dpi), dpi=dpi, facecolor="#10141c")
    gs = fig.add_gridspec(3, 2, width_ratios=[1.9, 1], left=0.0, right=0.97, top=0.93,
                          bottom=0.08, hspace=0.55, wspace=0.12)
    small = max(5.0, 7.0 * h / 480)
    ax = fig.add_subplot(gs[:, 0], projection="3d", facecolor="#10141c")
    ax.set_axis_off()
    half = L * 1.15 + spacing / 2
    ax.set_xlim(-half, half)
    ax.set_ylim(-half, half)
    ax.set_zlim(-half, half)
    try:
        ax.set_box_aspect((1, 1, 1), zoom=1.35)
    except (AttributeError, TypeError):
        pass
    ax.view_init(elev=18, azim=-60 if nS == 1 else -90)
    fig.suptitle(f"{run['profile_name']} ({'reduced model | Simbody' if nS > 1 else run['model_name']})",
                 color="#dde", fontsize=small * 1.3)

    polys = Poly3DCollection([], edgecolor="k", linewidths=0.3)
    ax.add_collection3d(polys)
    axis_lines, spin_lines, trails, flip_pts, event_pts = [], [], [], [], []
    for si in range(nS):
        o = offsets[si]
        hN = P @ (run["sides"][si]["h_N"][0] / np.linalg.norm(run["sides"][si]["h_N"][0]))
        ax.plot(*np.array([o, o + 1.6 * L * hN]).T, color="#ffd030", lw=2)
        axis_lines.append([ax.plot([], [], [], color=c, lw=1.6)[0]
                           for c in ("#ff5050", "#50e050", "#5090ff")])
        spin_lines.append(ax.plot([], [], [], color="#ff60ff", lw=2)[0])
        trails.append(ax.plot([], [], [], color="#ff60ff", lw=0.8)[0])
        flip_pts.append(ax.plot([], [], [], "o", color="white", ms=4)[0])
        event_pts.append({kind: ax.plot([], [], [], "o", color=c, ms=3)[0]
                          for kind, c in (("release", "#33cc99"), ("latch", "#ff9933"))})
        # The spin-axis tip over the whole run (plot frame), for the trail.
        R_all = scene.quat_to_matrix(run["sides"][si]["q"])
        run["sides"][si]["_tip"] = o + 1.25 * L * (R_all @ sB) @ P.T
    if nS > 1:
        for si, s in enumerate(run["sides"]):
            ax.text2D(0.25 + 0.5 * si, 0.95, s["label"], transform=ax.transAxes, color="#dde",
                      ha="center", fontsize=small * 1.1)
    hud = ax.text2D(0.02, 0.02, "", transform=ax.transAxes, color="#dde", fontsize=small)
    banner = ax.text2D(0.5, 0.08, "", transform=ax.transAxes, color="white", ha="center",
                       fontsize=small * 1.2, weight="bold")

    def chart(pos, title):
        c = fig.add_subplot(pos, facecolor="#0e121a")
        c.set_title(title, color="#bbc", fontsize=small)
        c.tick_params(colors="#889", labelsize=small * 0.85)
        for sp in c.spines.values():
            sp.set_color("#334")
        c.set_xlim(ts[0], ts[-1])
        for e in events:
            c.axvline(e["t"], color="#33cc99" if e["kind"] == "release" else "#ff9933", lw=0.6)
        for s in run["sides"]:
            for tf in s["flips"]:
                c.axvline(tf, color="white", lw=0.5, ls=":")
        return c, c.axvline(t0, color="white", lw=1.2)

    cH, mH = chart(gs[0, 1], "H_B / |H| (x red, y green, z blue)")
    for si, s in enumerate(run["sides"]):
        Hn = s["H"] / np.linalg.norm(s["H"][0])
        for c, col in enumerate(("#ff5050", "#50e050", "#5090ff")):
            cH.plot(ts[idx], Hn[idx, c], color=col, lw=0.8, ls="--" if si else "-")
    cH.set_ylim(-1.05, 1.05)
    cA, mA = chart(gs[1, 1], "spin axis to h_N [deg]")
    for si, s in enumerate(run["sides"]):
        cA.plot(ts[idx], np.degrees(s["angle"][idx]), color="#ff60ff", lw=0.9,
                ls="--" if si else "-")
    cA.set_ylim(0, 180)
    cA.set_yticks([0, 90, 180])
    cS, mS = chart(gs[2, 1], "stages (spin axis role), danger window")
    for a, b in run["danger"]:
        cS.axvspan(a, b, color="#ff3c3c", alpha=0.25, lw=0)
    for st in run["stages"]:
        cS.barh(0.7, st["t1"] - st["t0"], left=st["t0"], height=0.35,
                color=ROLE_COLORS.get(st["role"], "#555555"))
    cS.set_ylim(0, 1)
    cS.set_yticks([])
    cS.set_xlabel("t [s]", color="#889", fontsize=small * 0.85)
    markers = (mH, mA, mS)

    win = max(2.0, 0.02 * (ts[-1] - ts[0]))

    def draw(t):
        Rs, k, f = interp_run(run, t)
        boxes = poses_interp(run, k, f, scale)
        verts, cols = [], []
        for si in range(nS):
            o = offsets[si]
            M = P @ Rs[si]  # B components -> plot frame
            palette = COLORS if si == 0 else COLORS_2
            for (c, R, d), kind in zip(boxes, kinds):
                if kind == "link":
                    continue
                pts = o + (c + (CORNERS * d) @ R.T) @ M.T
                for face in FACES:
                    quad = pts[list(face)]
                    n = np.cross(quad[1] - quad[0], quad[2] - quad[0])
                    nn = np.linalg.norm(n)
                    shade = 0.45 + 0.55 * max(0.0, (n / nn) @ LIGHT) if nn > 0 else 0.45
                    verts.append(quad)
                    cols.append(np.append(palette.get(kind, COLORS["hub"]) * shade, 1.0))
            for j, line in enumerate(axis_lines[si]):
                e = M[:, j] * 0.95 * L
                line.set_data_3d(*np.array([o, o + e]).T)
            s_tip = o + 1.25 * L * (M @ sB)
            spin_lines[si].set_data_3d(*np.array([o, s_tip]).T)
            # The trail: the last trail seconds of the tip's path.
            k0 = min(int(np.searchsorted(ts, t - trail)), k)
            tip = run["sides"][si]["_tip"][k0: k + 1]
            trails[si].set_data_3d(tip[:, 0], tip[:, 1], tip[:, 2])
            fl = [tf for tf in run["sides"][si]["flips"] if tf <= t]
            if fl:
                fk = np.clip(np.searchsorted(ts, fl), 0, len(ts) - 1)
                fp = run["sides"][si]["_tip"][fk]
                flip_pts[si].set_data_3d(fp[:, 0], fp[:, 1], fp[:, 2])
            else:
                flip_pts[si].set_data_3d([], [], [])
            for kind, pts_line in event_pts[si].items():
                te = [e["t"] for e in events if e["t"] <= t and
                      (e["kind"] == "release") == (kind == "release")]
                ek = np.clip(np.searchsorted(ts, te), 0, len(ts) - 1).astype(int)
                ep = run["sides"][si]["_tip"][ek] if len(te) else np.zeros((0, 3))
                pts_line.set_data_3d(ep[:, 0], ep[:, 1], ep[:, 2])
        polys.set_verts(verts)
        polys.set_facecolor(cols)
        lines = [f"t = {t:.2f} s"]
        for st in run["stages"]:
            if st["t0"] <= t < st["t1"]:
                lines.append(f"{st['name']} (spin axis {st['role']})")
        for s in run["sides"]:
            nf = int(np.sum(np.asarray(s["flips"]) <= t))
            lines.append((s["label"] + ": " if nS > 1 else "") + f"flips {nf}/{len(s['flips'])}")
        hud.set_text("\n".join(lines))
        msg = ""
        for e in events:
            if e["t"] <= t < e["t"] + win:
                msg = f"{e['kind'].upper()} {e['panel']}"
        for s in run["sides"]:
            for tf in s["flips"]:
                if tf <= t < tf + win:
                    msg = f"FLIP at {tf:.2f} s"
        banner.set_text(msg)
        for m in markers:
            m.set_xdata([t, t])

    writer = FFMpegWriter(fps=fps, codec="libx264",
                          extra_args=["-pix_fmt", "yuv420p", "-preset", "veryfast", "-crf", "23"])
    with writer.saving(fig, out, dpi):
        for t in times:
            draw(t)
            writer.grab_frame(facecolor=fig.get_facecolor())
    plt.close(fig)


def make_gif(mp4, gif, fps):
    vf = f"fps={fps},split[a][b];[a]palettegen=max_colors=256[p];[b][p]paletteuse=dither=bayer"
    r = subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", mp4, "-vf", vf, "-loop", "0", gif],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise scene.SceneError(f"ffmpeg (GIF): {(r.stderr.strip().splitlines() or ['failed'])[-1]}")


def parse_size(text):
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected WIDTHxHEIGHT, e.g. 1280x720")
    if w < 64 or h < 64:
        raise argparse.ArgumentTypeError(f"{text!r}: at least 64x64")
    return (w + w % 2, h + h % 2)  # even, for yuv420p


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("result", help="trajectory or cross-check file (HDF5) written by deploysim")
    ap.add_argument("-o", "--output", required=True, help="MP4 file to write")
    ap.add_argument("--gif", action="store_true", help="also write the .gif beside it")
    ap.add_argument("--fps", type=float, default=30.0, help="frames per second (default 30)")
    ap.add_argument("--seconds", type=float, default=20.0, help="video length [s] (default 20)")
    ap.add_argument("--t0", type=float, help="first simulated time shown [s] (default: start)")
    ap.add_argument("--t1", type=float, help="last simulated time shown [s] (default: end)")
    ap.add_argument("--size", type=parse_size, default=(1280, 720), help="WIDTHxHEIGHT pixels")
    ap.add_argument("--model", help="model YAML (default: from the file, as tools/view.py)")
    a = ap.parse_args(argv)
    if not (a.fps > 0 and a.seconds > 0):
        ap.error("--fps and --seconds must be positive")
    if shutil.which("ffmpeg") is None:
        print("animate: ffmpeg not found (Debian package ffmpeg)", file=sys.stderr)
        return 1
    d = os.path.dirname(os.path.abspath(a.output))
    fd, tmp = tempfile.mkstemp(prefix=".animate-", suffix=".mp4", dir=d)
    os.close(fd)
    tmp_gif = tmp[:-4] + ".gif"
    try:
        run = scene.read_run(a.result, a.model)
        ts = run["time"]
        t0 = ts[0] if a.t0 is None else a.t0
        t1 = ts[-1] if a.t1 is None else a.t1
        if not ts[0] <= t0 < t1 <= ts[-1]:
            raise scene.SceneError(f"--t0 {t0:g} / --t1 {t1:g}: not within the run "
                                   f"[{ts[0]:g}, {ts[-1]:g}] s with t0 < t1")
        render(run, tmp, a.fps, a.seconds, t0, t1, a.size)
        if a.gif:
            make_gif(tmp, tmp_gif, a.fps)
            scene.publish(tmp_gif, os.path.splitext(a.output)[0] + ".gif")
        scene.publish(tmp, a.output)
    except scene.SceneError as e:
        print(f"animate: {e}", file=sys.stderr)
        return 1
    except (OSError, KeyError, ValueError, TypeError, subprocess.CalledProcessError) as e:
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        print(f"animate: {a.result}: {msg}", file=sys.stderr)
        return 1
    finally:
        for p in (tmp, tmp_gif):
            if os.path.exists(p):
                os.unlink(p)
    print(f"wrote {a.output}" + (f" and {os.path.splitext(a.output)[0]}.gif" if a.gif else "")
          + f" ({int(round(a.fps * a.seconds))} frames, {a.fps:g} fps)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
