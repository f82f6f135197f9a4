#!/usr/bin/python3
"""The long runs that the sanitizer and qemu steps leave out (tests/long_runs.txt) each
name short tests that run their code paths there: every listed long run and every named
short test is a test of this build (ctest -N), and no short test is itself left out.

Usage: long_runs_test.py SOURCE_DIR BUILD_DIR
Exit status 0 when the list holds; 1, naming each broken line, when not.
"""
import re
import subprocess
import sys


def read_list(path):
    """[(line number, long-run regex, [short tests], reason)] of tests/long_runs.txt."""
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            fields = line.split(None, 2)
            if len(fields) < 3:
                rows.append((n, fields[0], [], ""))
                continue
            rows.append((n, fields[0], fields[1].split(","), fields[2].strip()))
    return rows


def main():
    source, build = sys.argv[1], sys.argv[2]
    listed = subprocess.run(["ctest", "--test-dir", build, "-N"], capture_output=True, text=True,
                            check=True).stdout
    # ctest -N: "Test #12: Name" (a parameterized test adds "  # GetParam() = ..."); the
    # short tests are named without that comment, the long runs' expressions match either.
    tests = set(re.findall(r"^\s*Test\s+#\d+: (.+?)\s*$", listed, re.M))
    bare = {t.split("  # ")[0] for t in tests}
    rows = read_list(f"{source}/tests/long_runs.txt")
    long_patterns = [re.compile(f"^({r})$") for _, r, _, _ in rows]
    problems = []
    for n, regex, short, reason in rows:
        where = f"tests/long_runs.txt:{n}"
        matched = sorted(t for t in tests if re.fullmatch(regex, t))
        if not matched:
            problems.append(f"{where}: '{regex}' is no test of this build")
        if not short or not reason:
            problems.append(f"{where}: needs a long run, its short tests and a reason")
        for s in short:
            if s not in bare:
                problems.append(f"{where}: short test '{s}' is no test of this build")
            elif any(p.match(s) for p in long_patterns):
                problems.append(f"{where}: short test '{s}' is itself left out")
        print(f"{regex}: {len(matched)} test(s), covered by {', '.join(short)}")
    for p in problems:
        print(p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
