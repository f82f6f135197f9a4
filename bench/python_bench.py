#!/usr/bin/python3
"""The Python package's overhead, table 8.

Rows:
  1. a 1,000-case sweep (the small satellite's three-stage deployment, 50 deployment
     durations x 20 spin rates, exact flow at rtol 1e-9, 2 threads): `deploysim sweep` as
     a process (load, run, write the results file) against run_sweep(file, output=...) in
     a running interpreter (the same load, cases and file), each the median of several
     runs; the interpreter's start with `import deploysim` is timed on its own row. Target: Python within 1.2x of the CLI.
  2. one simulate call on the main job (deployment_profiles/smallsat_spring_deploy.yaml):
     the whole deploysim.simulate(profile) call against the run inside it
     (MissionResult::wall_seconds, analysis::RunMission); overhead = the difference
     (taking the GIL back, numpy arrays and dicts, the result object; the previous
     result is freed outside the timed call). Target: under 5 % of the run.
  3. GIL: two Python threads each running simulate on the main job (5 calls each),
     against the same 10 calls one after the other. Target: about half the time on 2
     cores (ratio <= 0.6).

Usage: PYTHONPATH=build/release/python bench/python_bench.py DEPLOYSIM [--quick]
       [--markdown FILE]
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
MAIN_JOB = ROOT / "deployment_profiles" / "smallsat_spring_deploy.yaml"
BASE = ROOT / "deployment_profiles" / "smallsat_three_stage.yaml"

SWEEP = """name: bench_1000
base: {base}
integrator: {{method: exact, rtol: 1.0e-9, atol: 1.0e-11}}
grid:
  - {{parameter: deploy_duration_scale, logspace: [0.1, 3, 50]}}
  - {{parameter: spin_rate_rpm, logspace: [0.2, 8, 20]}}
outcome: {{tumble_angle_deg: 20}}
"""


def median_time(f, reps):
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("deploysim")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--markdown")
    args = ap.parse_args()
    try:
        import deploysim
    except ImportError as e:
        print(f"python_bench: the deploysim package is not importable ({e}): skipped")
        if args.markdown:
            pathlib.Path(args.markdown).write_text("")
        return 0
    reps = 3 if args.quick else 7
    rows = []

    with tempfile.TemporaryDirectory() as tmp:
        spec = pathlib.Path(tmp) / "bench_1000.yaml"
        spec.write_text(SWEEP.format(base=BASE))
        out = pathlib.Path(tmp) / "cli.h5"

        def cli():
            subprocess.run([args.deploysim, "sweep", str(spec), "-o", str(out), "--threads",
                            "2", "-q"], check=True)
            out.unlink()

        out_py = pathlib.Path(tmp) / "py.h5"

        def py():
            cols = deploysim.run_sweep(str(spec), threads=2, output=str(out_py))
            assert len(cols["case_index"]) == 1000
            out_py.unlink()

        py()  # warm the page cache
        t_cli, t_py = [], []
        for _ in range(reps):  # interleaved
            t_cli.append(median_time(cli, 1))
            t_py.append(median_time(py, 1))
        c, p = statistics.median(t_cli), statistics.median(t_py)
        rows.append(("1,000-case sweep, 2 threads: run_sweep(file, output=...) vs `deploysim sweep`",
                     f"{p:.3f} s", f"{c:.3f} s", f"{p / c:.2f}x", "<= 1.2x",
                     "met" if p / c <= 1.2 else "missed"))

    imports = []
    for _ in range(reps):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import deploysim"], check=True)
        imports.append(time.perf_counter() - t0)
    bare = []
    for _ in range(reps):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], check=True)
        bare.append(time.perf_counter() - t0)
    rows.append(("once per session: start /usr/bin/python3 and `import deploysim` (numpy)",
                 f"{statistics.median(imports):.3f} s",
                 f"{statistics.median(bare):.3f} s", "", "", "(reference: a bare interpreter)"))

    profile = deploysim.load_profile(MAIN_JOB)
    deploysim.simulate(profile)
    overheads, runs = [], []
    for _ in range(5 * reps):
        t0 = time.perf_counter()
        r = deploysim.simulate(profile)
        total = time.perf_counter() - t0
        overheads.append(total - r.wall_seconds)
        runs.append(r.wall_seconds)
        del r  # freeing the previous result is the caller's business, not the call's
    o, w = statistics.median(overheads), statistics.median(runs)
    rows.append(("simulate, main job: Python overhead vs the run (RunMission)",
                 f"{o * 1e3:.3f} ms", f"{w * 1e3:.2f} ms", f"{100 * o / w:.1f} %", "< 5 %",
                 "met" if o / w < 0.05 else "missed"))

    calls = 20

    def work():
        for _ in range(calls):
            deploysim.simulate(profile)

    def serial():
        # In one worker thread, as the two of threaded() run: the main thread's allocator
        # returns freed memory to the system between calls (page faults on every call),
        # which would make the serial side slower for a reason other than parallelism.
        t = threading.Thread(target=lambda: (work(), work()))
        t.start()
        t.join()

    def threaded():
        ts = [threading.Thread(target=work) for _ in range(2)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    t_serial, t_threads = [], []
    work()  # warm the allocator with this call pattern
    for i in range(reps):  # interleaved, the order alternating
        if i % 2:
            t_threads.append(median_time(threaded, 1))
            t_serial.append(median_time(serial, 1))
        else:
            t_serial.append(median_time(serial, 1))
            t_threads.append(median_time(threaded, 1))
    s, t = statistics.median(t_serial), statistics.median(t_threads)
    rows.append((f"GIL: 2 threads x {calls} simulate (main job) vs the {2 * calls} calls in turn (one thread)",
                 f"{t:.3f} s", f"{s:.3f} s", f"{t / s:.2f}", "about 0.5 (<= 0.6)",
                 "met" if t / s <= 0.6 else "missed"))

    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    lines = [
        "### 8. The Python package",
        "",
        "`bench/python_bench.py` (`PYTHONPATH=build/release/python`, Debian's /usr/bin/python3):",
        "the package against the CLI and against its own C++ run.",
        "",
        "| measurement | Python | reference | ratio | target | |",
        "|---|---:|---:|---:|---|---|",
    ]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    lines += [
        "",
        f"- Sweep: {reps} runs per side, interleaved, median; `deploysim sweep` timed as a "
        "process (start-up, load and validation of the 1,000 cases, the run with its journal "
        "and the results file); Python: run_sweep(file, threads=2, output=results file) in a "
        "running interpreter (the same load, validation, cases and file; the interpreter's "
        "start and `import deploysim`, paid once per session, are the next row).",
        f"- simulate: median of {5 * reps} calls; the reference is MissionResult::wall_seconds "
        "measured inside the C++ run; the overhead is the rest of the call.",
        f"- GIL: {reps} rounds, median, the two sides interleaved in alternating order after a "
        f"warm-up; each thread calls simulate {calls} times.",
        f"- Load average before: {load}; {os.cpu_count()} hardware threads.",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.markdown:
        pathlib.Path(args.markdown).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
