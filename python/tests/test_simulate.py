"""simulate() against `deploysim simulate`'s HDF5 file: every shipped profile, every
dataset, bit for bit (the same integrator settings: the profile's own)."""

import json

import h5py
import numpy as np
import pytest

import deploysim
from conftest import PROFILES, SOURCE_DIR

# Result attribute -> HDF5 dataset of the same name (the per-panel ones: geometry mode).
TRAJECTORY = [c["name"] for c in deploysim.trajectory_columns() if c["shape"] != "per-panel"]


def same(a, b):
    a = np.asarray(a)
    b = np.asarray(b)
    if a.dtype.kind in "fc" or b.dtype.kind in "fc":
        return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)
    return a.shape == b.shape and np.array_equal(a, b)


def text(values):
    return [v.decode() if isinstance(v, bytes) else v for v in values]


def test_trajectory_columns_are_the_arrays_and_documented():
    r = deploysim.simulate(deploysim.load_profile(PROFILES[0]))
    doc = deploysim.SimulationResult.__doc__
    for c in deploysim.trajectory_columns():
        assert hasattr(r, c["name"]), c["name"]
        assert len(getattr(r, c["name"])) == len(r.time), c["name"]
        assert f" {c['name']} " in doc, c["name"]
    assert {"time", "H_B", "q_NB", "J_B", "energy_total"} <= set(TRAJECTORY)


@pytest.mark.parametrize("path", PROFILES, ids=[p.stem for p in PROFILES])
def test_simulate_equals_cli_hdf5(path, cli_trajectory):
    out = cli_trajectory(path)
    r = deploysim.simulate(deploysim.load_profile(path))
    with h5py.File(out, "r") as f:
        for name in TRAJECTORY:
            assert same(getattr(r, name), f[name][()]), name
        if "hinge_angles" in f:
            assert same(r.hinge_angles, f["hinge_angles"][()])
            assert same(r.hinge_rates, f["hinge_rates"][()])
            assert text(f["panel_names"][()]) == r.panel_names
        else:
            assert r.hinge_angles.shape == (len(r.time), 0)
        assert same(r.flips, f["events/flip_time"][()])
        assert same(r.predicted_flips, f["events/predicted_flip_time"][()])
        assert same(r.spin_axis_45_times, f["events/spin_axis_45_time"][()])
        assert same(r.danger_windows["t_begin"], f["danger_windows/t_begin"][()])
        assert same(r.danger_windows["t_end"], f["danger_windows/t_end"][()])
        if "hinge_latch_time" in f:
            assert same(r.latch_times, f["hinge_latch_time"][()])
        ev = f["events/hinge"]
        for k in ("time", "angle", "rate_before", "rate_after", "impulse",
                  "energy_dissipated", "panel"):
            assert same(r.events[k], ev[k][()]), k
        for i, c in enumerate("xyz"):
            assert same(r.events[f"w_jump_B_{c}"], ev["w_jump_B"][()][:, i]), c
        assert same(r.events["w_jump_B"], ev["w_jump_B"][()])
        assert text(ev["kind"][()]) == r.events["kind"]
        assert text(ev["panel_name"][()]) == r.events["panel_name"]
        table = r.stage_table
        st = f["stages"]
        rigid = np.array(table["rigid"], dtype=bool)
        for k in ("index", "t_begin", "t_end", "moments_end", "separatrix_distance",
                  "predicted_flip_count", "observed_flip_count", "max_flip_time_difference"):
            assert same(np.array(table[k]), st[k][()]), k
        # Closed-form values of stages that are not rigid are NaN here (the file: 0).
        for k in ("one_minus_k2", "predicted_flip_half_period"):
            v = np.array(table[k], dtype=float)
            assert same(v[rigid], st[k][()][rigid]), k
            assert np.isnan(v[~rigid]).all(), k
        for k in ("rigid", "rigid_body_only"):
            assert same(np.array(table[k], dtype=np.int64), st[k][()]), k
        for k in ("name", "law", "spin_axis_role", "caveat"):
            assert text(st[k][()]) == table[k], k
        # Not applicable: None here, the empty string in the file.
        regimes = text(st["regime"][()])
        assert [x if x is not None else "" for x in table["regime"]] == regimes
        assert all((x is None) == (not g) for x, g in zip(table["regime"], rigid))
        for k in ("from", "to"):
            hinge = r.profile.is_hinge_profile
            assert table[k] == ([None] * len(rigid) if hinge else text(st[k][()])), k
        # The units: those of the file's datasets.
        for name in TRAJECTORY:
            assert r.units[name] == f[name].attrs["units"], name
        for k, u in r.events.units.items():
            if not k.startswith("w_jump_B_"):
                assert u == ev[k].attrs["units"], k
            else:
                assert u == ev["w_jump_B"].attrs["units"], k
        for k in st:
            assert r.stage_units[k] == st[k].attrs["units"], k
        assert r.units["flips"] == f["events/flip_time"].attrs["units"]
        assert f.attrs["termination"] == r.termination
        assert f.attrs["profile_text"] == r.profile.text
        # The body as the run moved it: the file's @body (hinged models only).
        assert r.body == (json.loads(f.attrs["body"]) if "body" in f.attrs else None)


# A hub with a two-plane and a one-plane beam (docs/file_formats.md, "The body").
BOOMS_MODEL = """name: booms
kind: hinged
hub: {mass: 50.0, box: [0.8, 0.8, 0.6]}
appendages:
  - {name: boom_px, kind: beam, root: [0.4, 0, 0], direction: [1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20},
     {axis: [0, 0, 1], EI: 20}], damping_ratio: 0.01, segments: 4}
  - {name: boom_mx, kind: beam, root: [-0.4, 0, 0], direction: [-1, 0, 0], length: 2.0,
     mass_per_length: 0.2, radius: 0.01, bending: [{axis: [0, 1, 0], EI: 20}],
     damping_ratio: 0.01, segments: 3}
configurations:
  straight: {hinge_angles_deg: [0, 0]}
"""
BOOMS_PROFILE = """name: booms
model: booms.yaml
initial: {configuration: straight, spin: {axis: z, rate_rpm: 10, nutation_deg: 5}}
until: 1
hinges: {}
"""


def test_result_body_has_the_appendages_as_the_file(cli, tmp_path):
    (tmp_path / "booms.yaml").write_text(BOOMS_MODEL)
    profile = tmp_path / "p.yaml"
    profile.write_text(BOOMS_PROFILE)
    r = deploysim.simulate(deploysim.load_profile(profile))
    # stubs, 4 x (link, segment), 3 segments
    assert len(r.body["panels"]) == r.hinge_angles.shape[1] == 2 + 2 * 4 + 3
    assert [p["name"] for p in r.body["panels"]] == r.panel_names
    assert [(a["name"], a["kind"], a["segments"], a["planes"], len(a["hinges"]))
            for a in r.appendages] == [("boom_px", "beam", 4, 2, 8), ("boom_mx", "beam", 3, 1, 3)]
    shapes = [p["drawn"]["shape"] for p in r.body["panels"]]
    assert shapes.count("none") == 4 and shapes.count("rod") == 2 + 4 + 3
    assert r.appendages[0]["damping_ratio"] == pytest.approx([0.01, 0.01], rel=1e-12)
    out = tmp_path / "run.h5"
    cli("simulate", profile, "-o", out, "-q")
    with h5py.File(out, "r") as f:
        assert json.loads(f.attrs["body"]) == r.body


def test_result_arrays_have_the_documented_shapes():
    r = deploysim.simulate(SOURCE_DIR / "deployment_profiles/wing_nut.yaml", dt=0.5)
    n = len(r.time)
    assert n == 81
    assert r.H_B.shape == (n, 3) and r.q_NB.shape == (n, 4) and r.J_B.shape == (n, 3, 3)
    assert r.energy.shape == (n,) and r.hinge_angles.shape == (n, 0)
    assert r.reached_end
    assert len(r.flips) == 11  # docs/design.md 6: 11 flips in 40 s
    assert np.allclose(r.flips[0], 1.7338627960581041, atol=1e-6)
    # Arrays own their memory beyond the result's lifetime.
    H = r.H_B
    del r
    assert np.isfinite(H).all()


def test_overrides_are_validated_like_the_cli():
    p = deploysim.load_profile(SOURCE_DIR / "deployment_profiles/wing_nut.yaml")
    with pytest.raises(ValueError, match="unknown integrator"):
        deploysim.simulate(p, method="rk5")
    q = p.with_overrides(method="rk4", step=1e-3)
    assert q.method == "rk4" and q.step == 1e-3 and p.method != "rk4"


def test_progress_is_called_up_to_one():
    seen = []
    deploysim.simulate(SOURCE_DIR / "deployment_profiles/wing_nut.yaml", progress=seen.append)
    assert seen and seen[-1] == 1.0


def test_an_exception_in_progress_stops_the_run():
    def fail(_):
        raise ZeroDivisionError("stop")

    with pytest.raises(ZeroDivisionError):
        deploysim.simulate(SOURCE_DIR / "deployment_profiles/wing_nut.yaml", progress=fail)


CTRL_C = """
import sys, deploysim
d = {{"name": "long", "model": {model!r},
     "initial": {{"angular_momentum": [1.0e-8, 2.1252e-5, 1.0e-8]}},
     "stages": [{{"name": "free spin", "hold": "default", "until": 1000}}],
     "integrator": {{"method": "thesis-euler", "step": 2e-5}},
     "output": {{"dt": 1.0}}}}
p = deploysim.profile_from_dict(d)
running = []
def progress(fraction):
    if not running:
        running.append(fraction)
        print("running", flush=True)
try:
    deploysim.simulate(p, progress=progress)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(5)
print("finished", flush=True)
"""


def test_ctrl_c_interrupts_simulate(tmp_path):
    """The seed's Euler for 1000 s (5e7 steps, ~10 s): Ctrl-C once the run reports its
    first progress (a handshake, not a delay), and the run ends by KeyboardInterrupt,
    long before it could have finished."""
    import os
    import signal
    import subprocess
    import sys
    script = CTRL_C.format(model=str(SOURCE_DIR / "models/wing_nut.yaml"))
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=os.environ, cwd=tmp_path)
    assert p.stdout.readline().strip() == "running"
    p.send_signal(signal.SIGINT)
    # A guard against a hang only: the run stops at its next progress poll.
    stdout, stderr = p.communicate(timeout=600)
    assert p.returncode == 5, (stdout, stderr)
    assert stdout.split() == ["interrupted"]


def test_simulate_releases_the_gil():
    """While simulate runs in a thread, the main thread runs Python code between the
    progress callbacks (it could not if the run held the GIL). Not timed."""
    import threading
    d = {"name": "gil", "model": str(SOURCE_DIR / "models/wing_nut.yaml"),
         "initial": {"angular_momentum": [1.0e-8, 2.1252e-5, 1.0e-8]},
         "stages": [{"name": "free spin", "hold": "default", "until": 100}],
         "integrator": {"method": "thesis-euler", "step": 2e-5}, "output": {"dt": 1.0}}
    p = deploysim.profile_from_dict(d)
    fractions = []
    seen_inside = []
    worker = threading.Thread(target=deploysim.simulate, args=(p,),
                              kwargs={"progress": fractions.append})
    worker.start()
    while worker.is_alive():
        if fractions and 0.0 < fractions[-1] < 1.0:
            seen_inside.append(fractions[-1])
    worker.join()
    assert fractions[-1] == 1.0
    assert seen_inside, "the main thread never ran while simulate was running"
