"""run_sweep: the CLI's results table as numpy columns, bit for bit; pandas; progress;
Ctrl-C."""

import os
import signal
import subprocess
import sys
import textwrap

import h5py
import numpy as np
import pytest

import deploysim
from conftest import SOURCE_DIR

BASE = SOURCE_DIR / "deployment_profiles/smallsat_three_stage.yaml"


def small_sweep(samples=8):
    return {
        "name": "py_sweep",
        "base": str(BASE),
        "integrator": {"method": "exact", "rtol": 1e-9, "atol": 1e-11},
        "grid": [{"parameter": "spin_rate_rpm", "values": [1.0, 3.0, 5.0]}],
        "monte_carlo": {"samples": samples, "seed": 7,
                        "parameters": [{"parameter": "nutation_deg",
                                        "uniform": [0.0, 5.0]}]},
        "outcome": {"tumble_angle_deg": 20},
    }


def test_sweep_equals_the_cli_results_file(cli, tmp_path):
    spec_file = tmp_path / "s.yaml"
    spec_file.write_text(deploysim._to_yaml(small_sweep()) + "\n")
    cli("sweep", spec_file, "-o", tmp_path / "cli.h5", "-q", "--threads", "2")
    cols = deploysim.run_sweep(spec_file, threads=2)
    from_dict = deploysim.run_sweep(small_sweep(), threads=1)
    with h5py.File(tmp_path / "cli.h5", "r") as f:
        names = f.attrs["columns"].split(",")
        assert list(cols.keys()) == names
        for name in names:
            ref = f["cases"][name][()]
            if ref.dtype.kind in "OS":
                assert [x.decode() if isinstance(x, bytes) else x for x in ref] == list(cols[name])
            else:
                assert np.array_equal(cols[name], ref, equal_nan=True), name
                assert np.array_equal(from_dict[name], ref, equal_nan=True), name
            assert cols.units[name] == f["cases"][name].attrs["units"]


def test_pandas_takes_it_as_it_is():
    pandas = pytest.importorskip("pandas")
    cols = deploysim.run_sweep(small_sweep(2), threads=2)
    df = pandas.DataFrame(cols)
    assert len(df) == 6 and list(df.columns) == list(cols.keys())
    assert df["case_index"].tolist() == list(range(6))


def test_progress_and_output(tmp_path):
    seen = []
    out = tmp_path / "r.h5"
    deploysim.run_sweep(small_sweep(), threads=2, progress=lambda d, n: seen.append((d, n)),
                        output=out, csv=True)
    assert seen[-1] == (24, 24)
    assert all(n == 24 for _, n in seen)
    assert out.exists() and (tmp_path / "r.h5.csv").exists()


def test_errors_of_dict_sweeps_are_the_files():
    d = small_sweep()
    d["grid"][0]["values"] = [1.0, -3.0]
    with pytest.raises(ValueError, match=r"^<dict>: grid\[0\]\.values\[1\] = -3.0: "):
        deploysim.run_sweep(d)


CTRL_C = textwrap.dedent("""
    import sys, deploysim
    spec = deploysim.sweep_from_dict({sweep!r})
    running = []
    def progress(done, total):
        if not running:
            running.append(done)
            print("running", flush=True)
    try:
        deploysim.run_sweep(spec, threads=2, progress=progress, output=sys.argv[1])
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        sys.exit(5)
    print("finished", flush=True)
""")


def test_ctrl_c_raises_keyboard_interrupt_and_writes_nothing(tmp_path):
    out = tmp_path / "big.h5"
    script = CTRL_C.format(sweep=small_sweep(20000))
    p = subprocess.Popen([sys.executable, "-c", script, str(out)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=os.environ)
    # Ctrl-C once the sweep reports progress from inside the run (a handshake, not a
    # delay); the workers then stop after the cases at hand, long before the 20000 cases.
    assert p.stdout.readline().strip() == "running"
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=600)  # a guard against a hang only
    assert p.returncode == 5, stderr
    assert stdout.split() == ["interrupted"]
    assert list(tmp_path.iterdir()) == []
