#!/usr/bin/python3
"""The main job from Python: the small satellite's spring-driven wing deployment
(deployment_profiles/smallsat_spring_deploy.yaml, what tools/run.sh runs), simulated with
the deploysim package and plotted with matplotlib.

Usage (after tools/test.sh, or cmake --build --preset release):
    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/main_job.py [-o OUT.png]

Prints the stage table and the deployment timeline (as `deploysim simulate` does) and
writes one figure: the hinge angles with the latches, the body momentum H_B, the angle
between the spin axis and h_N with the flips, and the energies.
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import deploysim  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", default="smallsat_spring_deploy_python.png")
    ap.add_argument("--profile", default=str(ROOT / "deployment_profiles/smallsat_spring_deploy.yaml"))
    args = ap.parse_args()

    profile = deploysim.load_profile(args.profile)
    r = deploysim.simulate(profile)
    first = f" (first at {r.flips[0]:.3f} s)" if len(r.flips) else ""
    print(f"{profile.name}: {len(r.time)} samples, {r.statistics['steps']} steps, "
          f"{r.wall_seconds * 1e3:.1f} ms; {len(r.flips)} flips{first}")
    print(f"{'#':>2}  {'stage':<20} {'t0 [s]':>9} {'t1 [s]':>9}  {'spin axis':<13} {'regime':<14}"
          f" {'flip every [s]':>14}")
    for s in r.stages:
        print(f"{s['index']:>2}  {s['name']:<20} {s['t_begin']:>9.6g} {s['t_end']:>9.6g}  "
              f"{s['spin_axis_role']:<13} {s['regime'] or '-':<14} "
              f"{s['predicted_flip_half_period']:>14.5g}")
    ev = r.events
    print("\ndeployment timeline:")
    for k in range(len(ev["time"])):
        line = f"  {ev['time'][k]:9.4f} s  {ev['panel_name'][k]:<13} {ev['kind'][k]:<8}"
        if ev["kind"][k] != "release":
            line += (f" rate {np.degrees(ev['rate_before'][k]):8.3f} deg/s, "
                     f"hub jump {np.degrees(np.linalg.norm(ev['w_jump_B'][k])):.3f} deg/s")
        print(line)

    fig, ax = plt.subplots(4, 1, figsize=(9, 11))
    for p, name in enumerate(r.panel_names):
        ax[0].plot(r.time, np.degrees(r.hinge_angles[:, p]), label=name)
    for k in range(len(ev["time"])):
        if ev["kind"][k] == "latch":
            ax[0].axvline(ev["time"][k], color="0.6", lw=0.8, ls="--")
    releases = [ev["time"][k] for k in range(len(ev["time"])) if ev["kind"][k] == "release"]
    if releases:  # the deployment takes seconds of the run: show it
        ax[0].set_xlim(releases[0] - 5, max(ev["time"]) + 10)
    ax[0].set_ylabel("hinge angle [deg]")
    ax[0].set_xlabel("time [s] (the deployment; dashed: latches)")
    ax[0].legend()
    for i, c in enumerate("xyz"):
        ax[1].plot(r.time, r.H_B[:, i], label=f"H_B {c}")
    ax[1].set_ylabel("H_B [kg m^2/s]")
    ax[1].legend()
    ax[2].plot(r.time, np.degrees(r.spin_axis_angle))
    for t in r.flips:
        ax[2].axvline(t, color="tab:red", lw=0.8, alpha=0.6)
    ax[2].set_ylabel("spin axis vs h_N [deg]\n(red: flips)")
    ax[3].plot(r.time, r.energy, label="kinetic")
    ax[3].plot(r.time, r.energy_spring, label="spring")
    ax[3].plot(r.time, r.energy_total, label="total")
    ax[3].set_ylabel("energy [J]")
    ax[3].set_xlabel("time [s]")
    ax[3].legend()
    fig.suptitle(f"{profile.name}: spring-driven deployment, then the intermediate-axis spin")
    fig.tight_layout()
    fig.savefig(args.output, dpi=90)
    print(f"\nwrote {args.output}")


if __name__ == "__main__":
    main()
