"""Shared fixtures of the deploysim Python tests (run by ctest: Python.pytest).

Environment (set by python/CMakeLists.txt): PYTHONPATH=<build>/python (the package),
DEPLOYSIM_SOURCE_DIR (the source tree), DEPLOYSIM_CLI (the deploysim executable, where
it is built; the tests that compare with the CLI are skipped without it).
"""

import os
import pathlib
import subprocess

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
