#!/usr/bin/python3
"""The package as a user installs it (ctest Python.pip_install, docs/python.md):

    PYTHON -m venv --system-site-packages v
    v/bin/pip install --no-build-isolation SOURCE_COPY

from a copy of the source tree without build/ (the files git tracks plus the untracked
ones it does not ignore: the working tree as it is; without git, everything but build/),
with pip's package index switched off (the build must need nothing from PyPI). Then the
main job (deployment_profiles/smallsat_spring_deploy.yaml) from the environment's Python,
outside the source tree: the run flips, two panels latch, pandas takes the event table,
and the viewer page is written by the command and tools installed with the package.

Prints the wall time of each step. Exit status 0 when everything holds; otherwise the
failing step's output and 1.

Usage: pip_install_check.py --source DIR [--work DIR] [--python /usr/bin/python3] [--keep]

--work: the folder for the copy and the environment (emptied first, removed at the end
unless --keep; default a new temporary folder). ctest passes one in the build tree: at a
fixed place, the one source whose compile command names its own folder
(cli/python_tool.cc: the tools' path) comes from ccache too from the second run on.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

# Runs in the virtual environment, from a folder outside the source copy.
MAIN_JOB = r"""
import json, os, sys
import pandas
import deploysim

source = sys.argv[1]
here = os.path.dirname(os.path.abspath(deploysim.__file__))
assert here.startswith(sys.prefix), (here, sys.prefix)  # the installed copy, not the tree's
r = deploysim.simulate(os.path.join(source, "deployment_profiles/smallsat_spring_deploy.yaml"))
assert r.reached_end, r.termination
kinds = list(r.events["kind"])
assert len(r.flips) > 0, "the main job does not flip"
assert kinds.count("latch") == 2, kinds
df = pandas.DataFrame(r.events)
assert len(df) == len(kinds) and list(df.columns) == list(r.events.units), df.columns
assert r.units["H_B"] == "kg m^2/s" and r.events.units["time"] == "s"
assert deploysim.cli_path().startswith(here), deploysim.cli_path()
deploysim.write_h5(r, "main_job.h5")
deploysim.view("main_job.h5", "main_job.html")
assert os.path.getsize("main_job.html") > 10000
print(json.dumps({"flips": len(r.flips), "latches": kinds.count("latch"),
                  "events": len(df), "first_flip": float(r.flips[0])}))
"""


def copy_source(source, dest):
    """The working tree without build/ (and without what .gitignore ignores)."""
    try:
        listing = subprocess.run(
            ["git", "-C", source, "ls-files", "-z", "--cached", "--others",
             "--exclude-standard"], check=True, stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL).stdout.decode().split("\0")
    except (OSError, subprocess.CalledProcessError):
        shutil.copytree(source, dest, symlinks=True,
                        ignore=lambda d, names: ["build"] if d == source else [])
        return
    for rel in filter(None, listing):
        src = os.path.join(source, rel)
        if not os.path.lexists(src) or rel.split("/")[0] == "build":
            continue  # deleted in the working tree
        os.makedirs(os.path.dirname(os.path.join(dest, rel)), exist_ok=True)
        # copy2: the sources keep their times (ccache's direct mode skips files it sees
        # as just written).
        shutil.copy2(src, os.path.join(dest, rel), follow_symlinks=False)


def step(name, times, cmd, **kw):
    t0 = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    times[name] = time.monotonic() - t0
    print(f"pip_install_check: {name}: {times[name]:.1f} s", flush=True)
    if p.returncode != 0:
        print(p.stdout)
        raise SystemExit(f"pip_install_check: {name} failed (exit {p.returncode}): "
                         f"{' '.join(cmd)}")
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--source", required=True, help="the source tree")
    ap.add_argument("--python", default="/usr/bin/python3",
                    help="the interpreter the environment is made from")
    ap.add_argument("--work", help="folder for the copy and the environment (emptied first)")
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    args = ap.parse_args()

    times = {}
    total = time.monotonic()
    if args.work:
        tmp = os.path.abspath(args.work)
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
    else:
        tmp = tempfile.mkdtemp(prefix="deploysim_pip_")
    try:
        src = os.path.join(tmp, "src")
        t0 = time.monotonic()
        copy_source(os.path.abspath(args.source), src)
        times["copy"] = time.monotonic() - t0
        assert not os.path.exists(os.path.join(src, "build")), "the copy has build/"
        print(f"pip_install_check: copy: {times['copy']:.1f} s", flush=True)

        # Nothing of the caller's Python setup may reach the environment.
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("PYTHON", "PIP_", "VIRTUAL_ENV", "DEPLOYSIM_"))}
        env["PIP_NO_INDEX"] = "1"  # PyPI is not there: a download attempt fails
        env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
        venv = os.path.join(tmp, "v")
        step("venv", times, [args.python, "-m", "venv", "--system-site-packages", venv], env=env)
        step("pip install", times,
             [os.path.join(venv, "bin", "pip"), "install", "--no-build-isolation", src],
             env=env, cwd=tmp)
        run_dir = os.path.join(tmp, "run")
        os.makedirs(run_dir)
        out = step("main job", times, [os.path.join(venv, "bin", "python"), "-c", MAIN_JOB, src],
                   env=env, cwd=run_dir)
        print(out.strip())
    finally:
        if args.keep:
            print(f"pip_install_check: kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    print(f"pip_install_check: total {time.monotonic() - total:.1f} s "
          f"({', '.join(f'{k} {v:.1f} s' for k, v in times.items())})")


if __name__ == "__main__":
    main()
