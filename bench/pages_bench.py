#!/usr/bin/python3
"""The pages deploysim writes, measured on the main job.

For the 3D viewer (`deploysim view`) and the mission report (`deploysim report`) of
deployment_profiles/smallsat_spring_deploy.yaml: the file size, the time to write the page
(what the user waits for at the command line: the whole deploysim command, simulation
included for the report; the viewer's input HDF5 is written once, untimed), and the time the
page takes to open in Debian's headless Chromium (from the navigation command to the load
event, and for the viewer on to its scene built and first drawn: `window.deploysimReady`). Each timing is the median of several cold repetitions (a new
browser per opening; a new process per write). Targets: viewer under 5 MB and open in under 2 s.

Usage: bench/pages_bench.py DEPLOYSIM [--quick] [--markdown FILE]
"""

import argparse
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import headless_chromium  # noqa: E402

PROFILE = ROOT / "deployment_profiles" / "smallsat_spring_deploy.yaml"
VIEWER_MAX_BYTES = 5e6
VIEWER_MAX_OPEN_S = 2.0


def timed_run(cmd):
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return time.perf_counter() - t0


def open_times(html, viewer, reps):
    """Median load-event time and median ready time [s], a fresh browser per opening, both
    from the navigation command (headless_chromium's Page.load_seconds). Ready: for the
    viewer, the load event plus the wait until the page's flag window.deploysimReady (scene
    built and first drawn) is seen, polled every 10 ms; for the report, the load event."""
    loads, readies = [], []
    for _ in range(reps):
        with headless_chromium.Browser(1280, 800) as b:
            page = b.open(html.as_uri(), settle=0.0)
            t_loaded = time.perf_counter()
            if viewer:
                deadline = time.monotonic() + 30
                while not page.evaluate("window.deploysimReady === true"):
                    if time.monotonic() > deadline:
                        raise RuntimeError(f"{html.name}: the scene never became ready")
                    time.sleep(0.01)
            ready = page.load_seconds + (time.perf_counter() - t_loaded)
            errs = page.errors()
            if errs:
                raise RuntimeError(f"{html.name}: console errors: {errs}")
            loads.append(page.load_seconds)
            readies.append(ready)
    return statistics.median(loads), statistics.median(readies)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("deploysim")
    ap.add_argument("--quick", action="store_true", help="3 repetitions instead of 7")
    ap.add_argument("--markdown", help="also write the table as markdown to this file")
    a = ap.parse_args(argv)
    reps = 3 if a.quick else 7
    cli = a.deploysim
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        h5 = tmp / "main.h5"
        subprocess.run([cli, "simulate", str(PROFILE), "-q", "-o", str(h5)], check=True)
        view, report = tmp / "main_view.html", tmp / "main_report.html"
        write_view = statistics.median(
            timed_run([cli, "view", str(h5), "-o", str(view)]) for _ in range(reps))
        write_report = statistics.median(
            timed_run([cli, "report", str(PROFILE), "-o", str(report)])
            for _ in range(max(1, reps // 2)))
        v_load, v_ready = open_times(view, True, reps)
        r_load, _ = open_times(report, False, reps)
        v_size, r_size = view.stat().st_size, report.stat().st_size

    ok_size = "met" if v_size < VIEWER_MAX_BYTES else "MISSED"
    ok_open = "met" if v_ready < VIEWER_MAX_OPEN_S else "MISSED"
    rows = [
        ("3D viewer (`deploysim view`)", v_size, write_view, v_load, v_ready,
         f"< 5 MB: {ok_size}; open < 2 s: {ok_open}"),
        ("mission report (`deploysim report`)", r_size, write_report, r_load, r_load,
         "the simulation and the plots included in the write time"),
    ]
    lines = [
        "### 7. Pages of the main job (smallsat_spring_deploy): viewer and report",
        "",
        "| page | size | write [s] | open: load event [s] | open: ready [s] | note |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for name, size, w, load, ready, note in rows:
        lines.append(f"| {name} | {size / 1e6:.2f} MB | {w:.2f} | {load:.3f} | {ready:.3f} | "
                     f"{note} |")
    lines += [
        "",
        f"Median of {reps} cold repetitions for the viewer's write and every opening "
        f"({max(1, reps // 2)} for the report's write: a new `deploysim` process each). Write: "
        "the whole command as a user runs it (the viewer reads an HDF5 written once, untimed; "
        "the report runs the simulation and the plots). Open: Debian's headless "
        "Chromium (software rendering, no GPU) on a local file, a new browser each time; "
        "both times count from the navigation command; "
        "'ready' adds the wait until the viewer's scene is built and first drawn (its "
        "`window.deploysimReady` flag, polled every 10 ms); for the report it is the load event. `bench/pages_bench.py`.",
    ]
    text = "\n".join(lines)
    print(text)
    if a.markdown:
        pathlib.Path(a.markdown).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
