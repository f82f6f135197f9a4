#!/usr/bin/python3
"""The work estimate against the steps taken, for every shipped profile and trap family.

Runs `deploysim analyze` on deployment_profiles/*.yaml and examples/traps/*.yaml, reads
the line "work estimate before the run: estimated N steps ..." and the integrator's step
count, and prints a Markdown table of both and their ratio. --update FILE writes the table
between the markers <!-- work-table:begin --> and <!-- work-table:end --> of FILE (the
table in docs/design.md is written so); --check exits 1 when a ratio lies outside
[1/3, 3], the estimate's stated accuracy.

--runs DIR reads the shipped profiles' output from the runs tools/shipped_runs.py wrote
there (`simulate` prints the same two lines) instead of running them again.
Usage: tools/work_table.py DEPLOYSIM_BINARY [--update docs/design.md] [--check] [--runs DIR]
"""

import argparse
import glob
import os
import re
import subprocess
import sys

from shipped_runs import ShippedRuns

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BEGIN, END = "<!-- work-table:begin -->", "<!-- work-table:end -->"
FACTOR = 3.0


def measure(binary, path, shipped=None):
    """(estimated steps, estimated s, measured steps, measured s) of one profile."""
    if shipped is not None and shipped.get(path):
        text = shipped.stdout(path)
    else:
        run = subprocess.run([binary, "analyze", path], capture_output=True, text=True,
                             check=False)
        if run.returncode != 0:
            raise RuntimeError(f"{path}: deploysim analyze failed: {run.stderr.strip()}")
        text = run.stdout
    steps = re.search(r"^integrator \S+: (\d+) steps, .*?, ([0-9.e+-]+) s wall", text, re.M)
    est = re.search(r"^work estimate before the run: estimated ([0-9.e+-]+) steps.*?about "
                    r"([0-9.e+-]+) s on one core", text, re.M)
    if not steps or not est:
        raise RuntimeError(f"{path}: no step count or work estimate in the output")
    return float(est.group(1)), float(est.group(2)), int(steps.group(1)), float(steps.group(2))


def table(binary, shipped=None):
    paths = sorted(glob.glob(os.path.join(ROOT, "deployment_profiles", "*.yaml")))
    paths += sorted(glob.glob(os.path.join(ROOT, "examples", "traps", "*.yaml")))
    rows, worst = [], 1.0
    for path in paths:
        est, est_s, steps, wall = measure(binary, path, shipped)
        ratio = steps / est
        worst = max(worst, ratio, 1.0 / ratio)
        rows.append(f"| `{os.path.relpath(path, ROOT)}` | {est:.3g} | {steps} | {ratio:.2f} | "
                    f"{est_s:.2g} | {wall:.2g} |")
    head = ("| profile | estimated steps | steps taken | taken / estimated | estimated s | "
            "wall s |\n|---|---:|---:|---:|---:|---:|")
    note = (f"\nLargest factor between the estimate and the steps taken: {worst:.2f} "
            f"(written by `tools/work_table.py`; wall times on the machine that wrote it).")
    return head + "\n" + "\n".join(rows) + "\n" + note, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("--update", metavar="FILE")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--runs", metavar="DIR")
    a = ap.parse_args()
    try:
        text, worst = table(a.binary, ShippedRuns(a.binary, a.runs) if a.runs else None)
    except RuntimeError as e:
        print(f"work_table: {e}", file=sys.stderr)
        return 1
    print(text)
    if a.update:
        doc = open(a.update, encoding="utf-8").read()
        if BEGIN not in doc or END not in doc:
            print(f"work_table: {a.update}: no {BEGIN} ... {END} markers", file=sys.stderr)
            return 1
        head, rest = doc.split(BEGIN, 1)
        tail = rest.split(END, 1)[1]
        tmp = a.update + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(head + BEGIN + "\n" + text + "\n" + END + tail)
        os.replace(tmp, a.update)
    if a.check and worst > FACTOR:
        print(f"work_table: a ratio is {worst:.2f} times off (rule: within {FACTOR:g})",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
