"""The Simbody cross-check from Python equals `deploysim crosscheck`'s file."""

import h5py
import numpy as np
import pytest

import deploysim
from conftest import SOURCE_DIR

pytestmark = pytest.mark.skipif(not deploysim.HAVE_CROSSCHECK, reason="built without Simbody")


@pytest.mark.parametrize("name,until,accuracy", [("wing_nut", 5.0, 1e-10),
                                                 ("smallsat_spring_deploy", 70.0, 1e-10)])
def test_crosscheck_equals_the_cli(name, until, accuracy, cli, tmp_path):
    path = SOURCE_DIR / "deployment_profiles" / f"{name}.yaml"
    out = tmp_path / "cc.h5"
    cli("crosscheck", path, "--until", until, "--accuracy", accuracy, "-o", out)
    r = deploysim.crosscheck(path, accuracy=accuracy, until=until)
    with h5py.File(out, "r") as f:
        assert np.array_equal(r["time"], f["time"][()])
        for side in ("reduced", "simbody"):
            for k in ("H_B", "h_N", "w_NB_B", "q_NB", "flip_time"):
                assert np.array_equal(r[side][k], f[side][k][()]), (side, k)
        assert np.array_equal(r["difference"]["H_B_relative"],
                              f["difference/H_B_relative"][()])
    assert r["max_H_B_relative"] < 1e-3  # Simbody at 1e-10 near the separatrix: ~1e-5
