"""The result's tables as pandas takes them, their units, the values that do not apply
(None / NaN, where `deploysim analyze --json` writes null), and the files written from
Python: the trajectory file, the 3D viewer and the mission report."""

import json
import math
import os

import h5py
import numpy as np
import pandas
import pytest

import deploysim
from conftest import SOURCE_DIR

MAIN_JOB = SOURCE_DIR / "deployment_profiles/smallsat_spring_deploy.yaml"
STAGE_PROFILE = SOURCE_DIR / "deployment_profiles/wing_nut.yaml"


@pytest.fixture(scope="module")
def main_job():
    return deploysim.simulate(MAIN_JOB)


# ---- tables for pandas ----

def test_events_are_one_dimensional_columns_for_pandas(main_job):
    ev = main_job.events
    df = pandas.DataFrame(ev)
    assert len(df) == len(ev["time"]) == 4
    assert list(df.columns) == list(ev)
    for k, v in ev.items():
        assert np.ndim(v) == 1 and len(v) == len(df), k
    assert list(df["kind"]).count("latch") == 2
    assert df["time"].is_monotonic_increasing
    # The jump's three columns are the (E, 3) array's, which stays available by name.
    assert ev["w_jump_B"].shape == (4, 3)
    assert np.array_equal(ev["w_jump_B"][:, 1], df["w_jump_B_y"].to_numpy())
    assert "w_jump_B" not in ev
    with pytest.raises(KeyError):
        ev["no_such_column"]


def test_a_stage_profile_has_an_empty_event_table_with_the_same_columns():
    r = deploysim.simulate(STAGE_PROFILE, dt=0.5)
    df = pandas.DataFrame(r.events)
    assert len(df) == 0
    assert list(df.columns) == list(deploysim.EVENT_UNITS)
    assert r.events["w_jump_B"].shape == (0, 3)
    assert len(pandas.DataFrame(r.stage_table)) == len(r.stages)
    assert len(pandas.DataFrame(r.danger_windows)) == len(r.danger_windows["t_begin"])


# ---- missing values ----

def test_free_hinge_stages_have_no_regime_and_no_one_minus_k2(main_job, cli):
    """The main job's free-hinge phases are not rigid: regime None and 1 - k^2 NaN, where
    `deploysim analyze --json` writes null; the rigid ones have both."""
    stages = main_job.stages
    assert [s["rigid"] for s in stages] == [True, False, True, False, True]
    for s in stages:
        if s["rigid"]:
            assert isinstance(s["regime"], str) and s["regime"]
            assert math.isfinite(s["one_minus_k2"]) and 0.0 <= s["one_minus_k2"] <= 1.0
        else:
            assert s["regime"] is None
            assert math.isnan(s["one_minus_k2"])
            assert math.isnan(s["predicted_flip_half_period"])
        assert s["from"] is None and s["to"] is None  # phases of a hinge profile
    analyzed = json.loads(cli("analyze", MAIN_JOB, "--json").stdout)["stages"]
    assert len(analyzed) == len(stages)
    for a, s in zip(analyzed, stages):
        assert (a["regime"] is None) == (s["regime"] is None), s["index"]
        assert (a["one_minus_k2"] is None) == math.isnan(s["one_minus_k2"]), s["index"]
        if a["regime"] is not None:
            assert a["regime"] == s["regime"]
            assert a["one_minus_k2"] == pytest.approx(s["one_minus_k2"], rel=1e-15)


def test_stage_profiles_keep_their_configurations():
    r = deploysim.simulate(SOURCE_DIR / "deployment_profiles/smallsat_three_stage.yaml")
    assert all(isinstance(s["from"], str) and isinstance(s["to"], str) for s in r.stages)
    df = pandas.DataFrame(r.stage_table)
    assert df["regime"].isna().tolist() == [not x for x in df["rigid"]]
    assert df["one_minus_k2"].isna().tolist() == [not x for x in df["rigid"]]


# ---- units ----

def test_every_column_has_its_unit(main_job):
    r = main_job
    for c in deploysim.trajectory_columns():
        assert r.units[c["name"]] == c["units"], c["name"]
    assert r.units["time"] == "s" and r.units["H_B"] == "kg m^2/s"
    assert r.units["w_NB_B"] == "rad/s" and r.units["energy"] == "J"
    arrays = [k for k, v in vars(r).items() if isinstance(v, np.ndarray)]
    assert arrays and set(arrays) <= set(r.units), set(arrays) - set(r.units)
    assert set(r.events.units) == set(r.events)
    assert r.events.units["angle"] == "rad" and r.events.units["impulse"] == "N m s"
    assert set(r.stage_table.units) == set(r.stage_table) == set(r.stage_units)
    assert r.danger_windows.units == {"t_begin": "s", "t_end": "s"}
    assert all(isinstance(u, str) and u for u in r.units.values())


# ---- files ----

def test_simulate_writes_the_cli_file_in_the_same_run(main_job, tmp_path, cli):
    ours = tmp_path / "py.h5"
    theirs = tmp_path / "cli.h5"
    r = deploysim.simulate(MAIN_JOB, output=ours, csv=True)
    cli("simulate", MAIN_JOB, "-o", theirs, "--csv", "-q")
    assert (tmp_path / "py.h5.csv").read_text() == (tmp_path / "cli.h5.csv").read_text()
    with h5py.File(ours, "r") as a, h5py.File(theirs, "r") as b:
        for name in ("time", "H_B", "q_NB", "J_B", "hinge_angles", "events/flip_time",
                     "events/hinge/time", "events/hinge/w_jump_B", "stages/one_minus_k2"):
            assert np.array_equal(a[name][()], b[name][()]), name
        assert np.array_equal(a["H_B"][()], r.H_B)
        assert a.attrs["profile_text"] == b.attrs["profile_text"]


def test_write_h5_of_a_result_holds_its_arrays(main_job, tmp_path):
    path = tmp_path / "again.h5"
    assert deploysim.write_h5(main_job, path) == path
    with h5py.File(path, "r") as f:
        for c in deploysim.trajectory_columns():
            assert np.array_equal(f[c["name"]][()], getattr(main_job, c["name"])), c["name"]
        assert np.array_equal(f["events/flip_time"][()], main_job.flips)


def test_write_h5_keeps_the_overrides_a_result_ran_with(tmp_path):
    r = deploysim.simulate(STAGE_PROFILE, dt=0.5)
    deploysim.write_h5(r, tmp_path / "coarse.h5")
    with h5py.File(tmp_path / "coarse.h5", "r") as f:
        assert len(f["time"]) == len(r.time) == 81


def test_write_h5_refuses_to_overwrite_an_input(tmp_path):
    profile = tmp_path / "p.yaml"
    profile.write_text(STAGE_PROFILE.read_text().replace(
        "../models/", str(SOURCE_DIR / "models") + "/"))
    before = profile.read_text()
    with pytest.raises(ValueError, match="input"):
        deploysim.write_h5(str(profile), profile)
    assert profile.read_text() == before


def test_a_failed_file_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        deploysim.write_h5(STAGE_PROFILE, tmp_path / "no_such_folder" / "x.h5")
    assert not (tmp_path / "no_such_folder").exists()


def test_view_writes_the_viewer_page(tmp_path):
    if not os.path.isdir("/usr/share/javascript/three"):
        pytest.skip("libjs-three is not installed (tools/install_deps.sh)")
    h5 = deploysim.write_h5(MAIN_JOB, tmp_path / "run.h5")
    html = tmp_path / "run.html"
    assert deploysim.view(h5, html, title="main job") == html
    page = html.read_text()
    assert "main job" in page and "deploysimReady" in page


def test_view_passes_the_tools_message_on(tmp_path):
    bad = tmp_path / "not.h5"
    bad.write_text("not HDF5")
    with pytest.raises(RuntimeError, match="deploysim view: .*not.h5"):
        deploysim.view(bad, tmp_path / "x.html")
    assert not (tmp_path / "x.html").exists()


def test_report_writes_the_mission_report(tmp_path):
    html = tmp_path / "report.html"
    assert deploysim.report(STAGE_PROFILE, html, dt=0.5) == html
    page = html.read_text()
    assert "wing_nut" in page and "<table" in page


def test_report_takes_a_path_only(tmp_path):
    with pytest.raises(TypeError, match="path"):
        deploysim.report(deploysim.load_profile(STAGE_PROFILE), tmp_path / "r.html")


def test_no_command_is_a_clear_error(monkeypatch, tmp_path):
    monkeypatch.delenv("DEPLOYSIM_BIN", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.setattr(deploysim, "__file__", str(tmp_path / "pkg" / "__init__.py"))
    with pytest.raises(RuntimeError, match="pip install"):
        deploysim.cli_path()
    with pytest.raises(RuntimeError, match="no deploysim command"):
        deploysim.view(tmp_path / "x.h5", tmp_path / "x.html")


def test_outcome_and_warnings_are_the_clis(cli, tmp_path):
    """The verdict record and the input warnings, as `analyze --json` gives them."""
    profile = MAIN_JOB
    r = deploysim.simulate(str(profile))
    ref = json.loads(cli("analyze", profile, "--json").stdout)
    assert r.outcome == ref["outcome"]
    assert r.outcome["headline"].startswith("Flips every 129.6 s about +y")
    assert r.warnings == ref["warnings"] == []
    late = tmp_path / "late.yaml"
    late.write_text(profile.read_text().replace("release: {at: 60}", "release: {at: 900}")
                    .replace("model: ../models/", f"model: {SOURCE_DIR}/models/"))
    short = deploysim.simulate(str(late), until=100)
    assert short.time[-1] == 100.0
    w = short.warnings
    assert len(w) == 2 and "hinges.wing_plus_x.free.release.at = 900" in w[0], w
    assert "(until = 100 s)" in w[0]
