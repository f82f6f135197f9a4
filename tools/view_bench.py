#!/usr/bin/python3
"""Size and load time of a viewer page (tools/view.py) in Debian's headless Chromium.

Usage: /usr/bin/python3 tools/view_bench.py PAGE.html [--runs 3]
Prints one line: size [MB], load [s] (navigation start to the load event, best of the
runs, a fresh browser each), ready [s] (navigation start to the scene built and drawn,
measured by the page: window.deploysimReadyMs) and the console error count. Exit 1 when the page has console errors or never
gets ready.
"""
import argparse
import os
import pathlib
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import headless_chromium  # noqa: E402


def measure(page_path, width=1280, height=800):
    """(size_bytes, load_seconds, ready_seconds, errors) of one fresh load: load is the
    driver's navigation-to-load-event time (Page.load_seconds), ready the page's own
    navigation-start-to-drawn-scene time (window.deploysimReadyMs); None if never ready."""
    url = pathlib.Path(page_path).resolve().as_uri()
    with headless_chromium.Browser(width, height) as b:
        page = b.open(url, settle=0.0)
        ready = None
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if page.evaluate("window.deploysimReady === true"):
                ready = page.evaluate("window.deploysimReadyMs") / 1000
                break
            time.sleep(0.02)
        return os.path.getsize(page_path), page.load_seconds, ready, page.errors()


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("page")
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args(argv)
    best = None
    for _ in range(max(1, a.runs)):
        r = measure(a.page)
        if best is None or (r[1] < best[1]):
            best = r
    size, load, ready, errs = best
    ready_s = f"{ready:.3f}" if ready is not None else "never"
    print(f"{a.page}: {size / 1e6:.2f} MB, load {load:.3f} s, ready {ready_s} s, "
          f"{len(errs)} console error(s)")
    return 0 if ready is not None and not errs else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
