#!/usr/bin/python3
"""The shipped profiles' runs, made once and read by every check that needs them.

Runs, for every deployment_profiles/*.yaml, `deploysim simulate PROFILE -o DIR/NAME.h5`
(its standard output kept in DIR/NAME.txt) and `deploysim analyze PROFILE --json`
(DIR/NAME.json), two processes at a time, and writes DIR/index.json last: the binary
(its path, size and modification time) and, per profile (its path relative to the source
tree), the three files. The checks that read them (tools/published.py --runs,
tools/work_table.py --runs, tests/tools/verdict_test.py) take a run from here only when
the index names the same binary, so a stale folder is never read as today's.

In the test suite this is the ctest fixture `Shipped.Runs` (tests/CMakeLists.txt): the
consumers require it, so ctest makes the runs once, before them.

Usage: /usr/bin/python3 tools/shipped_runs.py DEPLOYSIM DIR
Exit status: 0 written; 1 a run failed (its command and message on stderr; no index).
"""
import concurrent.futures
import glob
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INDEX = "index.json"


def shipped_profiles():
    """The shipped profiles, relative to the source tree (sorted)."""
    return sorted(os.path.relpath(p, ROOT)
                  for p in glob.glob(os.path.join(ROOT, "deployment_profiles", "*.yaml")))


def binary_identity(binary):
    st = os.stat(binary)
    return {"path": os.path.abspath(binary), "size": st.st_size, "mtime_ns": st.st_mtime_ns}


def _run(args, stdout_path):
    r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: exit {r.returncode}: {r.stderr.strip()}")
    with open(stdout_path, "w", encoding="utf-8") as f:
        f.write(r.stdout)


def make(binary, out_dir, jobs=2):
    """Runs every shipped profile (simulate and analyze --json) into out_dir."""
    binary = os.path.abspath(binary)
    os.makedirs(out_dir, exist_ok=True)
    index_path = os.path.join(out_dir, INDEX)
    if os.path.exists(index_path):
        os.remove(index_path)   # no index while the files are being rewritten
    runs, tasks = {}, []
    for rel in shipped_profiles():
        stem = os.path.join(os.path.abspath(out_dir), os.path.splitext(os.path.basename(rel))[0])
        files = {"h5": stem + ".h5", "stdout": stem + ".txt", "json": stem + ".json"}
        runs[rel] = files
        tasks.append(([binary, "simulate", rel, "-o", files["h5"]], files["stdout"]))
        tasks.append(([binary, "analyze", rel, "--json"], files["json"]))
    # The slowest (the slosh stack's, 10 s; the others take 1 s at most) first, so that
    # the two workers end together.
    tasks.sort(key=lambda t: "spin_stabilized_tank" not in t[0][2])
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        for f in [pool.submit(_run, *t) for t in tasks]:
            f.result()
    with open(index_path, "w", encoding="utf-8") as f:
        json.dump({"binary": binary_identity(binary), "runs": runs}, f, indent=1)


class ShippedRuns:
    """The runs of a folder make() wrote, for this binary; get(profile) gives a profile's
    files (h5, stdout, json) or None when the folder does not hold it."""

    def __init__(self, binary, out_dir):
        path = os.path.join(out_dir, INDEX)
        try:
            with open(path, encoding="utf-8") as f:
                index = json.load(f)
        except OSError as e:
            raise RuntimeError(f"{path}: cannot read ({e.strerror}); "
                               f"write it with tools/shipped_runs.py") from e
        if index.get("binary") != binary_identity(binary):
            raise RuntimeError(f"{path}: made by another build of deploysim "
                               f"({index.get('binary')}); run tools/shipped_runs.py again")
        self.runs = index["runs"]

    def get(self, profile):
        """profile: a path relative to the source tree (or absolute)."""
        return self.runs.get(os.path.relpath(os.path.join(ROOT, profile), ROOT))

    def stdout(self, profile):
        with open(self.get(profile)["stdout"], encoding="utf-8") as f:
            return f.read()

    def analyzed(self, profile):
        with open(self.get(profile)["json"], encoding="utf-8") as f:
            return json.load(f)


def main():
    if len(sys.argv) != 3 or sys.argv[1] in ("-h", "--help"):
        print(__doc__, file=sys.stderr if len(sys.argv) != 2 else sys.stdout)
        return 0 if len(sys.argv) == 2 else 2
    try:
        make(sys.argv[1], sys.argv[2])
    except (RuntimeError, OSError) as e:
        print(f"shipped_runs: error: {e}", file=sys.stderr)
        return 1
    print(f"shipped_runs: {len(shipped_profiles())} profiles simulated and analyzed "
          f"into {sys.argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
