#!/usr/bin/python3
"""Plots deploysim's deployment-speed study (quasi-rigid coupling vs Simbody) as a PNG.

Usage: /usr/bin/python3 tools/plot_speed_study.py SPEED.csv [-o OUT.png]

SPEED.csv is written by `deploysim crosscheck PROFILE --speed-study --csv SPEED.csv`
(crosscheck::WriteSpeedStudyCsv): '#' comment lines, a header of column names with units
in brackets, one row per deployment duration. The figure (default: SPEED.png next to the
CSV) has two log-log panels against the deployment duration D:
  left   angular-velocity error of the quasi-rigid model during the deployment (falls
         like 1/D while the deployment crosses the danger window quickly) and after it;
  right  attitude error at the end of the deployment (a geometric phase, nearly constant
         in D), the largest attitude error after it, and the exact coupling's attitude
         error (the control, at Simbody's accuracy).
Durations during which the spin axis spends long in the danger window (intermediate axis)
are marked. Needs Debian's python3-matplotlib and python3-numpy.
"""
import argparse
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    comments = []
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f if ln.strip()]
    while lines and lines[0].startswith("#"):
        comments.append(lines.pop(0).lstrip("# "))
    if not lines:
        sys.exit(f"{path}: no header line")
    names = [re.sub(r"\s*\[.*\]$", "", c.strip()) for c in lines[0].split(",")]
    rows = [[float(x) for x in ln.split(",")] for ln in lines[1:]]
    if not rows:
        sys.exit(f"{path}: no data rows")
    data = np.array(rows)
    cols = {n: data[:, i] for i, n in enumerate(names)}
    required = ["duration", "max_w_error_deploying", "attitude_error_at_end",
                "max_attitude_error_after", "max_w_error_after", "exact_max_attitude_error"]
    missing = [c for c in required if c not in cols]
    if missing:
        sys.exit(f"{path}: missing columns {missing}")
    return cols, " ".join(comments)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", help="PNG path (default: next to the CSV)")
    args = ap.parse_args()
    c, title = read(args.csv)
    out = args.output or os.path.splitext(args.csv)[0] + ".png"
    D = c["duration"]
    tiny = 1e-300  # log axes: keep zeros drawable

    fig, (axw, axa) = plt.subplots(1, 2, figsize=(12, 5.2), constrained_layout=True)
    axw.loglog(D, np.maximum(c["max_w_error_deploying"], tiny), "o-", color="C0",
               label="during deployment (max)")
    axw.loglog(D, np.maximum(c["max_w_error_after"], tiny), "s--", color="C1",
               label="after deployment (max)")
    # 1/D reference through the fastest deployment.
    ref = c["max_w_error_deploying"][0] * D[0] / D
    axw.loglog(D, ref, ":", color="0.5", label=r"$\propto 1/D$ (hinge rate)")
    axw.set_xlabel("deployment duration D [s]")
    axw.set_ylabel(r"angular-velocity error $|\Delta\omega_{NB}^B|$ [rad/s]")
    axw.set_title("quasi-rigid vs Simbody: angular velocity")

    axa.loglog(D, np.maximum(c["attitude_error_at_end"], tiny), "o-", color="C2",
               label="at the end of deployment (geometric phase)")
    axa.loglog(D, np.maximum(c["max_attitude_error_after"], tiny), "s--", color="C3",
               label="after deployment (max)")
    axa.loglog(D, np.maximum(c["exact_max_attitude_error"], tiny), "^-.", color="C7",
               label="exact coupling (control)")
    axa.set_xlabel("deployment duration D [s]")
    axa.set_ylabel("attitude error [rad]")
    axa.set_title("quasi-rigid vs Simbody: attitude")

    if "danger_time_deploying" in c:
        # Mark deployments that spend more than 10 s in the danger window.
        slow = c["danger_time_deploying"] > 10.0
        for ax in (axw, axa):
            if slow.any():
                ax.axvspan(D[slow].min() / 1.3, D.max() * 1.3, color="#fbe3e3", zorder=0,
                           lw=0, label="> 10 s in the danger window\n(spin axis intermediate)")
    for ax in (axw, axa):
        ax.grid(True, which="both", lw=0.4, alpha=0.5)
        ax.legend(fontsize=8, loc="best")
    if title:
        fig.suptitle(title, fontsize=9)
    fig.savefig(out, dpi=130)
    print(out)


if __name__ == "__main__":
    main()
