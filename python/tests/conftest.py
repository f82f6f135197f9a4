"""Shared fixtures of the deploysim Python tests (run by ctest: Python.pytest).

Environment (set by python/CMakeLists.txt): PYTHONPATH=<build>/python (the package),
DEPLOYSIM_SOURCE_DIR (the source tree), DEPLOYSIM_CLI (the deploysim executable, where
it is built; the tests that compare with the CLI are skipped without it),
DEPLOYSIM_SHIPPED_RUNS (optional: the shipped profiles' CLI runs that tools/shipped_runs.py
wrote with that executable, the ctest fixture Shipped.Runs; without it the CLI runs here).
"""

import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("DEPLOYSIM_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("DEPLOYSIM_CLI", str(SOURCE_DIR / "build/release/bin/deploysim"))
PROFILES = sorted((SOURCE_DIR / "deployment_profiles").glob("*.yaml"))


@pytest.fixture
def cli():
    """Runs the deploysim CLI: cli(args...) -> CompletedProcess (text)."""
    if not os.access(CLI, os.X_OK):
        pytest.skip(f"no deploysim executable at {CLI}")

    def run(*args, check=True):
        r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"deploysim {' '.join(map(str, args))}: {r.stderr}")
        return r

    return run


@pytest.fixture
def cli_trajectory(cli, tmp_path):
    """The trajectory file of `deploysim simulate PROFILE` (a shipped profile's from the
    fixture's runs where they are given): cli_trajectory(profile) -> path."""
    runs = None
    if os.environ.get("DEPLOYSIM_SHIPPED_RUNS"):
        sys.path.insert(0, str(SOURCE_DIR / "tools"))
        from shipped_runs import ShippedRuns
        runs = ShippedRuns(CLI, os.environ["DEPLOYSIM_SHIPPED_RUNS"])

    def trajectory(profile):
        files = runs.get(str(profile)) if runs else None
        if files:
            return pathlib.Path(files["h5"])
        out = tmp_path / "run.h5"
        cli("simulate", profile, "-o", out, "-q")
        return out

    return trajectory
