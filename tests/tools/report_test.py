#!/usr/bin/python3
"""tools/report.py writes a mission report a reader can trust: every number of the run in
it equals the trajectory file of `deploysim simulate` (read here with h5py, independently
of the tools) at its data-h5 pointer, every number of the coupling comparison equals the
other coupling's `deploysim analyze --json` at its data-json pointer, every stage, flip,
hinge event, latch, 45-degree crossing and danger window appears, the page opens in
headless Chromium without errors and loads nothing from outside, the report runs one
simulation, and bad input leaves no file. Also the tools' one trajectory reader
(tools/deploysim_results.py): a fresh file, a version 2 file from before the free-hinge
outputs, and its errors.

Usage: report_test.py DEPLOYSIM SOURCE_DIR [ARTEFACT_DIR]
ARTEFACT_DIR (default: ./test_artefacts/report) keeps the reports, the trajectory files
they are checked against, full-page screenshots (screen and print media) and the PDF
prints, for a person to look at.
Needs Debian's python3-h5py and python3-numpy (run with /usr/bin/python3), and the
project's tools/headless_chromium.py.
"""

import base64
import html.parser
import json
import math
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import h5py
import numpy as np

HERE = pathlib.Path(__file__).resolve()
sys.path.insert(0, str(HERE.parents[2] / "tools"))
import deploysim_results  # noqa: E402
import headless_chromium  # noqa: E402

DEPLOYSIM = SOURCE = ARTEFACTS = None
PYTHON = "/usr/bin/python3"
DEG = 180.0 / math.pi

# The two reports: the main job (free hinges) and a stage profile (coupling comparison).
CASES = {
    "spring": "deployment_profiles/smallsat_spring_deploy.yaml",
    "three_stage": "deployment_profiles/smallsat_three_stage.yaml",
}
OTHER = "other-coupling"
# Flags (0 or 1) the report shows as words or marks, not as numbers.
FLAGS = {"/stages/rigid", "/stages/rigid_body_only"}
# The wall time of the simulate run, measured by the report (not in the file): only
# checked to be there and positive.
WALL_TIME = "measured by tools/report.py around deploysim simulate"
# Slow-report bound: the report of the main job takes ~3 s on one free core (the plots).
# The most A4 pages each report may print to: 10 each when measured (13 and 12 when every
# section of the inputs started a page and the figures stood a page high each); a bound a
# page above, so that a blank half page more fails, a different font does not.
PRINT_PAGES = {"spring": 11, "three_stage": 11}


def report_cmd(profile, out, *extra, deploysim=None):
    return [PYTHON, str(pathlib.Path(SOURCE) / "tools" / "report.py"), profile, "-o", str(out),
            "--deploysim", deploysim or DEPLOYSIM, *extra]


def simulate(profile, out, *extra):
    """The run of the report, again: its trajectory file (the same bit for bit)."""
    subprocess.run([DEPLOYSIM, "simulate", profile, "-q", "-o", str(out), *extra], cwd=SOURCE,
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=True)
    return out


def analyze_json(profile, *extra):
    p = subprocess.run([DEPLOYSIM, "analyze", profile, "--json", *extra], cwd=SOURCE,
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=True)
    return json.loads(p.stdout)


def fake_deploysim(d, corrupt=False):
    """A deploysim that logs its command lines to d/calls and runs the real one;
    corrupt: its simulate then overwrites the trajectory file with text."""
    fake = pathlib.Path(d, "deploysim")
    fake.write_text(
        f"#!{PYTHON}\nimport subprocess, sys\n"
        f"with open({str(pathlib.Path(d, 'calls'))!r}, 'a') as log:\n"
        "    log.write(' '.join(sys.argv[1:]) + '\\n')\n"
        f"p = subprocess.run([{DEPLOYSIM!r}] + sys.argv[1:])\n"
        f"if {corrupt!r} and sys.argv[1] == 'simulate' and p.returncode == 0:\n"
        "    open(sys.argv[sys.argv.index('-o') + 1], 'w').write('not HDF5\\n')\n"
        "sys.exit(p.returncode)\n")
    fake.chmod(0o755)
    return fake


def get_ptr(doc, pointer):
    cur = doc
    for tok in pointer.split("/")[1:]:
        tok = tok.replace("~1", "/").replace("~0", "~")
        cur = cur[int(tok)] if isinstance(cur, list) else cur[tok]
    return cur


def ptr(*parts):
    return "".join("/" + str(p).replace("~", "~0").replace("/", "~1") for p in parts)


def hp(path, *index):
    """A data-h5 pointer: /path#i,k."""
    return "/" + path + ("#" + ",".join(str(i) for i in index) if index else "")


def text_of(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def h5_get(f, pointer):
    """The value at a data-h5 pointer of tools/report.py, read with h5py: a root attribute
    (@name, the field key= of a "k=v, k=v" attribute: @name#key, or a member of a JSON
    attribute: @outcome#linear.verdict) as its text or value; a
    dataset's element (/path#i or /path#i,k) or whole dataset (/path) as a number, str or
    list."""
    if pointer.startswith("@"):
        name, _, key = pointer[1:].partition("#")
        v = text_of(f.attrs[name])
        if key and v.startswith("{"):  # a JSON record (@outcome#linear.verdict)
            v = json.loads(v)
            for k in key.split("."):  # list entries by index: @body#appendages.0.name
                v = v[int(k)] if isinstance(v, list) else v[k]
            return v
        if key:
            v = dict(part.strip().split("=", 1) for part in v.split(","))[key]
        return v
    path, _, index = pointer.partition("#")
    v = f[path][()]
    for i in index.split(",") if index else []:
        v = v[int(i)]
    if isinstance(v, np.ndarray):
        return [text_of(x) if isinstance(x, bytes) else x for x in v.tolist()]
    return text_of(v) if isinstance(v, bytes) else v.item() if hasattr(v, "item") else v


def as_number(text):
    """An attribute's text as a number, or None if it is no number."""
    try:
        return float(text)
    except ValueError:
        return None


def same(a, b):
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a)
                      and math.isnan(b))


def evaluate(get, expr):
    """The data-derived grammar of tools/report.py; get(pointer) gives a pointer's value."""
    if expr.startswith("len "):
        return len(get(expr[4:]))
    if expr.startswith("sum "):
        return sum(get(expr[4:]))
    if expr.startswith("norm "):
        return math.sqrt(sum(x * x for x in get(expr[5:])))
    for op in (" - ", " / ", " + "):
        if op in expr:
            a, b = (get(s.strip()) for s in expr.split(op))
            return {" - ": a - b, " / ": a / b, " + ": a + b}[op]
    raise ValueError(f"unknown data-derived expression {expr!r}")


SOURCE_ATTRS = {"data-h5", "data-json", "data-derived", "data-src"}
VOID = {"img", "meta", "br", "hr", "link", "input", "col", "source", "wbr"}


class Elements(html.parser.HTMLParser):
    """Every element with its attributes and text; plus every URL-bearing attribute."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.elements = []
        self.stack = []
        self.urls = []  # (tag, attribute, value)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for k in ("src", "href", "action", "data", "poster", "srcset"):
            if k in a:
                self.urls.append((tag, k, a[k] or ""))
        e = {"tag": tag, "attrs": a, "text": [], "unsourced": []}
        self.elements.append(e)
        if tag not in VOID:
            self.stack.append(e)

    def handle_endtag(self, tag):
        for i in range(len(self.stack) - 1, -1, -1):
            if self.stack[i]["tag"] == tag:
                del self.stack[i:]
                break

    def handle_data(self, data):
        for i, e in enumerate(self.stack):
            e["text"].append(data)
            # text not inside a descendant that names its source
            if not any(SOURCE_ATTRS & set(d["attrs"]) for d in self.stack[i + 1:]):
                e["unsourced"].append(data)


NUMBER = re.compile(r"(-?\d+(?:\.\d+)?)(?:(?:\u00d710|e)([-+]?\d+))?")


def shown_numbers(text):
    """The numbers a reader sees in a cell (U+2212 minus, ×10<sup>n</sup>, 1e-11), each
    with half a unit of its last digit."""
    out = []
    for m in NUMBER.finditer(text.replace("\u2212", "-")):
        mant = m.group(1)
        dec = len(mant.split(".")[1]) if "." in mant else 0
        exp = int(m.group(2)) if m.group(2) else 0
        out.append((float(mant) * 10.0 ** exp, 0.5 * 10.0 ** (exp - dec)))
    return out


def shown_number(text):
    """The first number a reader sees in a cell, or None."""
    numbers = shown_numbers(text)
    return numbers[0] if numbers else None


# How far the page, or a table, figure, code block or the summary box, runs past the
# right edge of its container [px] (a table running off the sheet).
OVERFLOW_JS = """Math.max(
  document.documentElement.scrollWidth - document.documentElement.clientWidth,
  ...Array.from(document.querySelectorAll('table, figure, pre, .summary')).map(e =>
     e.getBoundingClientRect().right - e.parentElement.getBoundingClientRect().right))"""

# The printable width of an A4 sheet with the report's @page margins (210 - 2 x 13 mm) in
# CSS pixels (96 per inch): the print screenshot is laid out this wide.
A4_CONTENT_PX = round((210 - 26) / 25.4 * 96)


def full_page_screenshot(page, path, media="screen"):
    """The whole page as one PNG; media "print": laid out as on an A4 sheet (no page
    breaks). Returns the content size and how far it is wider than the layout [px]."""
    b = page.browser
    b.call("Emulation.setEmulatedMedia", {"media": media}, session=page.session)
    # no scrollbar: the layout gets the whole width, as on paper
    b.call("Emulation.setScrollbarsHidden", {"hidden": True}, session=page.session)
    width = A4_CONTENT_PX if media == "print" else b.width
    b.call("Emulation.setDeviceMetricsOverride",
           {"width": width, "height": b.height, "deviceScaleFactor": 1, "mobile": False},
           session=page.session)
    over = page.evaluate(OVERFLOW_JS)
    m = b.call("Page.getLayoutMetrics", session=page.session)
    size = m.get("cssContentSize") or m["contentSize"]
    data = b.call("Page.captureScreenshot",
                  {"format": "png", "captureBeyondViewport": True,
                   "clip": {"x": 0, "y": 0, "width": size["width"], "height": size["height"],
                            "scale": 1}}, session=page.session)["data"]
    pathlib.Path(path).write_bytes(base64.b64decode(data))
    b.call("Emulation.setEmulatedMedia", {"media": ""}, session=page.session)
    b.call("Emulation.setDeviceMetricsOverride",
           {"width": b.width, "height": b.height, "deviceScaleFactor": 1, "mobile": False},
           session=page.session)
    return size, over


class ReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.art = pathlib.Path(ARTEFACTS)
        cls.art.mkdir(parents=True, exist_ok=True)
        cls.reports, cls.h5, cls.seconds, cls.calls = {}, {}, {}, {}
        # The reports run a deploysim that logs its command lines (the real one behind it),
        # so that test_one_simulation_per_report reads how often these reports ran it.
        cls.calls_dir = tempfile.mkdtemp()
        for name, profile in CASES.items():
            out = cls.art / f"{name}_report.html"
            if out.exists():
                out.unlink()
            log_dir = pathlib.Path(cls.calls_dir, name)
            log_dir.mkdir()
            fake = fake_deploysim(log_dir)
            t0 = time.monotonic()
            p = subprocess.run(report_cmd(profile, out, deploysim=str(fake)), cwd=SOURCE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            cls.seconds[name] = time.monotonic() - t0
            cls.calls[name] = (log_dir / "calls").read_text().splitlines()
            if p.returncode != 0:
                raise AssertionError(f"report of {profile} failed ({p.returncode}): {p.stderr}")
            print(f"report of {profile}: {cls.seconds[name]:.2f} s, "
                  f"{out.stat().st_size / 1024:.0f} kB -> {out}", file=sys.stderr)
            cls.reports[name] = out
            cls.h5[name] = simulate(profile, cls.art / f"{name}.h5")
        cls.other = analyze_json(CASES["three_stage"], "--coupling", "quasi-rigid")
        cls.browser = headless_chromium.Browser(900, 1200)

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()
        shutil.rmtree(cls.calls_dir, ignore_errors=True)

    def parse(self, name):
        p = Elements()
        p.feed(self.reports[name].read_text(encoding="utf-8"))
        return p

    # --- the numbers ---------------------------------------------------------------
    def check_h5_cell(self, f, where, pointer, value_attr, text):
        """A data-h5 element: its data-value is the file's value at the pointer, and what
        it shows is that value (or in degrees) to the digits shown."""
        v = h5_get(f, pointer)
        base = pointer.partition("#")[0]
        if isinstance(v, str) and as_number(v) is None:
            self.assertEqual(value_attr, v, where)
            return
        if isinstance(v, str):
            v = as_number(v)
        if isinstance(v, list):
            self.assertEqual(json.loads(value_attr), v, where)
            shown = shown_numbers(text)
            self.assertEqual(len(shown), len(v), f"{where}: shows {text!r}")
        else:
            self.assertTrue(same(float(value_attr), float(v)), f"{where}: {value_attr} vs {v!r}")
            if base in FLAGS:
                self.assertIn(v, (0, 1), where)
                return
            if not math.isfinite(v):
                self.assertIsNone(shown_number(text), f"{where}: shows {text!r} for {v!r}")
                return
            shown = [shown_number(text)]
            self.assertIsNotNone(shown[0], f"{where}: shows no number: {text!r}")
            v = [v]
        for (x, tol), y in zip(shown, v):
            self.assertTrue(abs(x - y) <= tol * 1.01 or abs(x - y * DEG) <= tol * 1.01,
                            f"{where}: shows {text!r} for {y!r}")

    def check_json_cell(self, doc, where, pointer, value_attr, text):
        """A data-json element (the other coupling's analyze --json)."""
        v = get_ptr(doc, pointer)
        if isinstance(v, str):
            self.assertEqual(value_attr, v, where)
            return
        self.assertEqual(json.loads(value_attr), v, where)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            sn = shown_number(text)
            self.assertIsNotNone(sn, f"{where}: shows no number: {text!r}")
            x, tol = sn
            self.assertTrue(abs(x - v) <= tol * 1.01 or abs(x - v * DEG) <= tol * 1.01,
                            f"{where}: shows {text!r} for {v!r}")

    def check_numbers(self, name, other=None):
        """Every number of the page against the trajectory file (data-h5), the other
        coupling's JSON (data-json) or the expression it was computed by (data-derived);
        every table cell with a digit names its source."""
        p = self.parse(name)
        seen = set()
        n_checked = 0
        with h5py.File(self.h5[name], "r") as f:
            def get(pointer):
                return h5_get(f, pointer)
            for e in p.elements:
                a = e["attrs"]
                text = "".join(e["text"]).strip()
                if SOURCE_ATTRS & set(a):
                    self.assertIn("data-value", a, f"{name}: {e['tag']} {a}")
                if "data-h5" in a:
                    where = f"{name}: <{e['tag']} data-h5={a['data-h5']!r}>"
                    self.check_h5_cell(f, where, a["data-h5"], a["data-value"], text)
                    seen.add((None, a["data-h5"]))
                    n_checked += 1
                if "data-json" in a:
                    self.assertEqual(a.get("data-doc"), OTHER, f"{name}: {a}")
                    self.assertIsNotNone(other, f"{name}: data-json without its document")
                    where = f"{name}: <{e['tag']} data-json={a['data-json']!r}>"
                    self.check_json_cell(other, where, a["data-json"], a["data-value"], text)
                    seen.add((OTHER, a["data-json"]))
                    n_checked += 1
                if "data-derived" in a:
                    doc = a.get("data-doc")
                    where = f"{name}: data-derived={a['data-derived']!r}"
                    v = evaluate((lambda q: get_ptr(other, q)) if doc == OTHER else get,
                                 a["data-derived"])
                    got = json.loads(a["data-value"])
                    self.assertTrue(got == v or abs(got - v) <= 1e-12 * abs(v),
                                    f"{where}: {got} vs {v}")
                    seen.add(("derived", a["data-derived"]))
                    n_checked += 1
                if "data-src" in a:
                    seen.add(("src", a["data-src"]))
                    if a["data-src"] == WALL_TIME:
                        self.assertGreater(float(a["data-value"]), 0.0, name)
                # every table cell that shows a number says where the number comes from
                # (itself, or each number in an element inside it that does)
                if e["tag"] == "td" and re.search(r"\d", text) and not SOURCE_ATTRS & set(a):
                    self.assertNotRegex("".join(e["unsourced"]), r"\d",
                                        f"{name}: number cell without a source: {text!r}")
        print(f"{name}: {n_checked} machine-readable numbers checked against the trajectory "
              "file (and the other coupling's analyze --json)", file=sys.stderr)
        return seen

    def check_coverage(self, name, seen, other=None, grouped=()):
        """Every stage, flip, event, latch, crossing and danger window is in the page; but
        the panels `grouped` (an appendage's bending hinges): their releases at the run's
        start and their latch times are not (the page names each appendage once)."""
        def need(pointer, doc=None):
            self.assertTrue((doc, pointer) in seen, f"{name}: {pointer} "
                            f"({doc or 'trajectory file'}) not in the report")
        for key in ("@integrator", "@termination", "@statistics#steps",
                    "@statistics#evaluations", "@max_h_N_drift", "@mode", "@coupling"):
            need(key)
        self.assertIn(("src", WALL_TIME), seen, f"{name}: no wall time")
        with h5py.File(self.h5[name], "r") as f:
            st = f["stages"]
            for i in range(len(st["t_begin"])):
                for k in ("index", "name", "law", "t_begin", "t_end", "spin_axis_role",
                          "separatrix_distance", "caveat", "rigid_body_only",
                          "predicted_flip_half_period", "rigid", "observed_flip_count"):
                    need(hp("stages/" + k, i))
                if st["observed_flip_count"][i] or st["predicted_flip_count"][i]:
                    need(hp("stages/max_flip_time_difference", i))
                for k in range(3):
                    need(hp("stages/moments_end", i, k))
                if st["rigid"][i]:
                    for k in ("regime", "one_minus_k2", "predicted_flip_count"):
                        need(hp("stages/" + k, i))
            panels = [text_of(x) for x in f["panel_names"][()]] if "panel_names" in f else []
            for path in ("events/flip_time", "events/predicted_flip_time",
                         "danger_windows/t_begin", "danger_windows/t_end",
                         "events/spin_axis_45_time", "hinge_latch_time"):
                for k in range(len(f[path])):
                    if path == "hinge_latch_time" and panels[k] in grouped:
                        self.assertNotIn((None, hp(path, k)), seen, f"{name}: {panels[k]}")
                        continue
                    need(hp(path, k))
            ev = f["events/hinge"]
            for e in range(len(ev["time"])):
                if (text_of(ev["panel_name"][e]) in grouped and text_of(ev["kind"][e]) == "release"
                        and ev["time"][e] <= f["time"][0]):
                    self.assertNotIn((None, hp("events/hinge/time", e)), seen, f"{name}: {e}")
                    continue
                for k in ("time", "panel_name", "kind", "angle"):
                    need(hp("events/hinge/" + k, e))
                if text_of(ev["kind"][e]) != "release":
                    for k in ("rate_before", "rate_after", "impulse", "energy_dissipated"):
                        need(hp("events/hinge/" + k, e))
                    self.assertIn(("derived", f"norm {hp('events/hinge/w_jump_B', e)}"), seen,
                                  f"{name}: hub w jump of event {e} not in the report")
        if other is not None:
            for k in other.get("coupling_comparison", {}):
                if k != "w_scale":
                    need(ptr("coupling_comparison", k), OTHER)
            for k in range(len(other["flip_times"])):
                need(ptr("flip_times", k), OTHER)

    def check_self_contained(self, name):
        p = self.parse(name)
        raw = self.reports[name].read_text(encoding="utf-8")
        for tag, attr, v in p.urls:
            if attr == "href":
                self.assertTrue(v.startswith("#"), f"{name}: <{tag} href={v[:60]!r}>")
            else:
                self.assertTrue(v.startswith("data:"), f"{name}: <{tag} {attr}={v[:60]!r}>")
        self.assertNotRegex(raw, r"(?i)https?:", f"{name}: a network address")
        self.assertNotRegex(raw, r"(?i)url\((?!\s*['\"]?data:)", f"{name}: a CSS url()")
        self.assertNotIn("@import", raw)
        self.assertNotIn("<script", raw.lower())
        self.assertNotIn("<link", raw.lower())

    def check_in_browser(self, name):
        page = self.browser.open(self.reports[name].resolve().as_uri())
        self.assertEqual(page.errors(), [], name)
        n_img = page.evaluate("document.images.length")
        broken = page.evaluate("Array.from(document.images).filter(i => !i.complete || "
                               "i.naturalWidth === 0).length")
        self.assertGreater(n_img, 5, name)
        self.assertEqual(broken, 0, f"{name}: images that did not decode")
        size, over = full_page_screenshot(page, self.art / f"{name}_screen.png")
        self.assertLessEqual(over, 0.5, f"{name}: something is {over} px too wide")
        _, over_a4 = full_page_screenshot(page, self.art / f"{name}_print.png", media="print")
        self.assertLessEqual(over_a4, 0.5, f"{name}: printed, the page is {over_a4} px wider "
                                         "than an A4 sheet")
        pdf = self.browser.call("Page.printToPDF", {"paperWidth": 8.27, "paperHeight": 11.69,
                                                     "printBackground": False},
                                session=page.session)["data"]
        pdf = base64.b64decode(pdf)
        (self.art / f"{name}.pdf").write_bytes(pdf)
        pages = len(re.findall(rb"/Type\s*/Page[^s]", pdf))
        print(f"{name}: page {size['width']:.0f} x {size['height']:.0f} px, loaded in "
              f"{page.load_seconds:.2f} s, {n_img} images, A4 print {pages} pages; "
              f"screenshots {self.art / (name + '_screen.png')}, "
              f"{self.art / (name + '_print.png')}", file=sys.stderr)
        self.assertGreater(pages, 2)
        self.assertLessEqual(pages, PRINT_PAGES[name], f"{name}: the A4 print has {pages} "
                             f"pages, more than {PRINT_PAGES[name]}: blank page ends?")
        return page

    # --- the tests -----------------------------------------------------------------
    def test_main_job_report(self):
        seen = self.check_numbers("spring")
        self.check_coverage("spring", seen)
        self.check_self_contained("spring")
        page = self.check_in_browser("spring")
        verdict = page.evaluate("document.querySelector('.summary .verdict').textContent")
        verdict = verdict.replace("\u00a0", " ")
        print(f"spring verdict: {verdict}", file=sys.stderr)
        self.assertEqual(verdict, self.headline("spring"))
        self.assertRegex(verdict, r"Flips every 129\.6 s about \+y \(intermediate axis\), "
                                  r"4 flips from 71\.08 s")
        body = self.reports["spring"].read_text(encoding="utf-8")
        self.assertIn("coupled exactly", body)
        self.assertIn("holds only for a perfectly rigid body", body.replace("\n", " "))

    def headline(self, name):
        """The headline of the run's outcome record in its trajectory file."""
        with h5py.File(self.h5[name], "r") as f:
            return json.loads(text_of(f.attrs["outcome"]))["headline"]

    def test_stage_profile_report(self):
        seen = self.check_numbers("three_stage", self.other)
        self.check_coverage("three_stage", seen, self.other)
        self.check_self_contained("three_stage")
        page = self.check_in_browser("three_stage")
        verdict = page.evaluate("document.querySelector('.summary .verdict').textContent")
        verdict = verdict.replace("\u00a0", " ")
        print(f"three_stage verdict: {verdict}", file=sys.stderr)
        self.assertEqual(verdict, self.headline("three_stage"))
        self.assertRegex(verdict, r"Flips every 72\.76 s about \+y \(intermediate axis\), "
                                  r"6 flips from 160 s")

    def test_other_kinds_of_profile(self):
        # A tensor model (no panels), an energy sink with no flip and a panel that never
        # locks, a spinning rotor (prescribed) with a free damper: every number still
        # equals the trajectory file and the page stays self-contained.
        for name, profile in (("seed_satellite", "deployment_profiles/seed_satellite.yaml"),
                              ("flat_spin", "deployment_profiles/minor_axis_flat_spin.yaml"),
                              ("dual_spin", "deployment_profiles/dual_spin_rotor.yaml")):
            with self.subTest(profile):
                out = self.art / f"{name}_report.html"
                t0 = time.monotonic()
                subprocess.run(report_cmd(profile, out, "-q"), cwd=SOURCE, check=True)
                print(f"report of {profile}: {time.monotonic() - t0:.2f} s", file=sys.stderr)
                self.reports[name] = out
                self.h5[name] = simulate(profile, self.art / f"{name}.h5")
                self.check_coverage(name, self.check_numbers(name))
                self.check_self_contained(name)

    def test_appendages(self):
        # Flexible booms (tests/tools/data/soft_boom_swing.yaml): the Appendages table has
        # a row per beam and bending plane, every number of it equals the file's @body
        # (and the ledger's and the outcome's), the bending hinges are named once per
        # beam (stage names, timeline), and the rest of the page still covers the run.
        name, profile = "booms", "tests/tools/data/soft_boom_swing.yaml"
        out = self.art / f"{name}_report.html"
        subprocess.run(report_cmd(profile, out, "-q"), cwd=SOURCE, check=True)
        self.reports[name] = out
        self.h5[name] = simulate(profile, self.art / f"{name}.h5")
        seen = self.check_numbers(name)
        with h5py.File(self.h5[name], "r") as f:
            body = json.loads(text_of(f.attrs["body"]))
            n = len(f["time"]) - 1
        grouped = {body["panels"][k]["name"] for a in body["appendages"] for k in a["hinges"]}
        self.assertEqual(len(grouped), 12 + 6)
        self.check_coverage(name, seen, grouped=grouped)
        self.check_self_contained(name)
        for i, planes in ((0, 2), (1, 1)):
            for p in range(planes):
                for key in ("kind", "segments", f"chain_frequencies.{p}.0",
                            f"beam_frequencies.{p}.0", f"chain_frequencies.{p}.1",
                            f"damping_ratio.{p}", f"damping.{p}"):
                    self.assertIn((None, f"@body#appendages.{i}.{key}"), seen, key)
        for pointer in (hp("work_damper", n), "@outcome#linear.growth_rate",
                        "@outcome#linear.quasi_rigid_rate"):
            self.assertIn((None, pointer), seen, pointer)
        page = out.read_text(encoding="utf-8")
        self.assertIn(">free: boom_px (12), boom_mx (6)<", page)
        self.assertNotIn(">boom_px_1a<", page)
        self.assertIn("The 18 hinges the appendages generated are free from the start", page)

    def test_stability_columns_say_which_axis(self):
        # The spin axis' role and the axis the polhode circulates about are two axes: an
        # intermediate spin axis beside a "minor" regime is no contradiction, and the table
        # says so under it.
        for name in CASES:
            with self.subTest(name):
                body = self.reports[name].read_text(encoding="utf-8")
                self.assertIn("polhode circulates about the \u2026 axis</th>", body)
                self.assertIn("spin axis at t<sub>1</sub> is the \u2026 axis</th>", body)
                self.assertIn("<b>Two different axes.</b>", body)
                self.assertNotIn(">minor-axis<", body)  # shown as "minor", not the file's word
        with h5py.File(self.h5["three_stage"], "r") as f:
            roles = [text_of(x) for x in f["stages/spin_axis_role"][()]]
            regimes = [text_of(x) for x in f["stages/regime"][()]]
        # the row that looked contradictory is in the checked report
        self.assertIn(("intermediate", "minor-axis"), list(zip(roles, regimes)))

    def test_print_styles_compact(self):
        # No forced page breaks; a figure keeps its caption.
        body = self.reports["spring"].read_text(encoding="utf-8")
        css = body[body.index("<style>"):body.index("</style>")]
        self.assertNotRegex(css, r"break-before:\s*(page|always)")
        self.assertRegex(css, r"figure \{[^}]*break-inside: avoid")

    def test_geometry_figures_or_a_note(self):
        body = self.reports["spring"].read_text(encoding="utf-8")
        if (pathlib.Path(SOURCE) / "tools" / "plot_geometry.py").exists():
            self.assertIn('alt="geometry_ellipsoid.png"', body)
            self.assertIn('alt="geometry_projections.png"', body)
        else:
            self.assertIn("Geometry figures not available", body)

    def test_inputs_and_provenance(self):
        body = self.reports["spring"].read_text(encoding="utf-8")
        for piece in ("release: {after_latch: wing_plus_x, delay: 2.0}",  # profile text
                      "hinge_point: [0.3, 0, 0.4]",  # model text
                      "deploysim version", "report generated"):
            self.assertIn(piece, body)

    def test_bad_input_leaves_nothing(self):
        with tempfile.TemporaryDirectory() as d:
            d = pathlib.Path(d)
            model = pathlib.Path(SOURCE, "models", "smallsat.yaml").resolve()
            good = pathlib.Path(SOURCE, CASES["three_stage"]).read_text()
            good = good.replace("../models/smallsat.yaml", str(model))
            (d / "bad_key.yaml").write_text(good.replace("until: 600", "untill: 600"))
            (d / "bad_yaml.yaml").write_text("name: x\n  bad: [\n")
            (d / "good.yaml").write_text(good)
            before = (d / "good.yaml").read_bytes()
            cases = [
                ("missing profile", [str(d / "nope.yaml"), d / "r.html"], "nope.yaml"),
                ("invalid YAML", [str(d / "bad_yaml.yaml"), d / "r.html"], "YAML"),
                ("unknown key", [str(d / "bad_key.yaml"), d / "r.html"], "untill"),
                ("-o is the profile", [str(d / "good.yaml"), d / "good.yaml"], "input"),
                ("-o is the model", [str(d / "good.yaml"), model], "input"),
                ("-o in a missing folder", [str(d / "good.yaml"), d / "no" / "r.html"],
                 "does not exist"),
                ("bad method", [str(d / "good.yaml"), d / "r.html", "--method", "nosuch"],
                 "nosuch"),
                ("bad rtol", [str(d / "good.yaml"), d / "r.html", "--rtol", "2"], "rtol"),
                ("no deploysim", [str(d / "good.yaml"), d / "r.html", "--deploysim",
                                  str(d / "none")], "deploysim"),
            ]
            for what, args, word in cases:
                with self.subTest(what):
                    profile, out, *extra = args
                    cmd = report_cmd(profile, out, *extra)
                    if "--deploysim" in extra:
                        cmd = cmd[:cmd.index("--deploysim")] + extra
                    p = subprocess.run(cmd, cwd=SOURCE, stdout=subprocess.PIPE,
                                       stderr=subprocess.PIPE, text=True)
                    self.assertNotEqual(p.returncode, 0, what)
                    lines = p.stderr.splitlines()
                    self.assertEqual(len(lines), 1, f"{what}: {p.stderr!r}")
                    self.assertIn(word, lines[0], what)
                    self.assertFalse((d / "r.html").exists(), what)
                    self.assertEqual(sorted(x.name for x in d.iterdir()),
                                     ["bad_key.yaml", "bad_yaml.yaml", "good.yaml"], what)
                    print(f"  {what}: exit {p.returncode}: {lines[0]}", file=sys.stderr)
            self.assertEqual((d / "good.yaml").read_bytes(), before)
            self.assertTrue(model.exists())

    def test_one_simulation_per_report(self):
        # The run's numbers come from one simulate; analyze runs only for the comparison
        # with the other coupling (a geometry-mode stage profile), never for this run.
        for name, want in (("spring", ["simulate"]), ("three_stage", ["simulate", "analyze"])):
            with self.subTest(name):
                calls = self.calls[name]
                runs = [c for c in calls if c.split()[0] in ("simulate", "analyze")]
                self.assertEqual([c.split()[0] for c in runs], want, calls)
                if len(runs) > 1:
                    self.assertIn("--coupling quasi-rigid", runs[1])

    def test_unreadable_trajectory_fails_loudly(self):
        # A deploysim whose simulate writes no HDF5 file: exit 5, one line, nothing written.
        with tempfile.TemporaryDirectory() as d:
            fake = fake_deploysim(d, corrupt=True)
            out = pathlib.Path(d, "r.html")
            p = subprocess.run(report_cmd(CASES["spring"], out, deploysim=str(fake)),
                               cwd=SOURCE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
            self.assertEqual(p.returncode, 5, p.stderr)
            lines = p.stderr.splitlines()
            self.assertEqual(len(lines), 1, p.stderr)
            self.assertIn("the trajectory file: not an HDF5 file", lines[0])
            self.assertFalse(out.exists())
            self.assertEqual(sorted(os.listdir(d)), ["calls", "deploysim"])

    def test_help(self):
        p = subprocess.run([PYTHON, str(pathlib.Path(SOURCE) / "tools" / "report.py"), "--help"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.assertEqual(p.returncode, 0)
        self.assertIn("Examples:", p.stdout)
        self.assertIn("Exit codes", p.stdout)


class ResultsReaderTest(unittest.TestCase):
    """tools/deploysim_results.py, the tools' one trajectory reader: a fresh file read as
    h5py reads it, a version 2 file from before the free-hinge outputs with its stand-ins,
    and one clear error (file and dataset named) for each kind of bad file."""

    OLD = "tests/io/data/trajectory_v2_before_issue9.h5"
    # The datasets added to version 2 with the free hinges (docs/file_formats.md) that the
    # reader fills in for an older file; /hinge_rates has no stand-in.
    ADDITIONS = {"energy_spring", "energy_total", "panel_names", "hinge_latch_time",
                 "events/spin_axis_45_time", "stages/caveat", "stages/rigid_body_only"} | {
        "events/hinge/" + k for k in ("time", "panel", "panel_name", "kind", "angle",
                                      "rate_before", "rate_after", "impulse", "w_jump_B",
                                      "energy_dissipated", "drive_work")}

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        cls.fresh = simulate(CASES["spring"], cls.dir / "spring.h5")
        cls.old = pathlib.Path(SOURCE, cls.OLD)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def assert_as_h5py_reads(self, path, run):
        """Every dataset and root attribute of the file, as h5py reads it; the per-sample
        datasets (those filled in aside) found without a list of names."""
        with h5py.File(path, "r") as f:
            names = []
            f.visititems(lambda k, o: names.append(k) if isinstance(o, h5py.Dataset) else None)
            for k in names:
                raw = f[k][()]
                if raw.dtype.kind == "O":
                    self.assertEqual(run[k], [text_of(x) for x in raw], k)
                else:
                    self.assertTrue(np.array_equal(run[k], raw, equal_nan=True), k)
            self.assertEqual(run.attrs, {k: text_of(v) for k, v in f.attrs.items()})
            n = len(f["time"])
            per_sample = {k for k in f if isinstance(f[k], h5py.Dataset) and f[k].ndim
                          and f[k].shape[0] == n and k not in ("panel_names", "hinge_latch_time")}
        self.assertEqual(set(run.samples) - set(run.filled), per_sample)
        return names

    def test_fresh_file(self):
        run = deploysim_results.read_trajectory(str(self.fresh))
        names = self.assert_as_h5py_reads(self.fresh, run)
        self.assertEqual(run.filled, [])
        self.assertTrue(run.has_hinge_outputs)
        self.assertTrue(self.ADDITIONS <= set(names))
        self.assertEqual(run.panel_names, ["wing_plus_x", "wing_minus_x"])
        self.assertEqual(list(run.latch_times), run.panel_names)
        self.assertTrue(all(isinstance(v, str) for v in run.attrs.values()))
        self.assertEqual(run.attr_fields("statistics")["steps"],
                         run.attrs["statistics"].split(",")[0].split("=")[1])
        stages = run.stages
        self.assertEqual([s["name"] for s in stages], run["stages/name"])
        self.assertEqual(sum(len(s["flip_rows"]) for s in stages), len(run.flip_time))
        for s in stages:
            self.assertEqual(len(s["flip_rows"]), s["observed_flip_count"])
            self.assertEqual(len(s["predicted_flip_rows"]), s["predicted_flip_count"])
        ev = run.hinge_events
        self.assertEqual([e["kind"] for e in ev], run["events/hinge/kind"])
        self.assertEqual(len(ev), 4)
        self.assertEqual(len(run.danger_windows), len(run["danger_windows/t_begin"]))

    def test_file_from_before_the_free_hinge_outputs(self):
        run = deploysim_results.read_trajectory(str(self.old))
        names = self.assert_as_h5py_reads(self.old, run)
        self.assertFalse(self.ADDITIONS & set(names))
        self.assertEqual(set(run.filled), self.ADDITIONS)
        self.assertFalse(run.has_hinge_outputs)
        n = len(run.time)
        self.assertTrue(np.array_equal(run["energy_spring"], np.zeros(n)))
        self.assertTrue(np.array_equal(run["energy_total"], run["energy"]))
        self.assertIn("energy_total", run.samples)
        self.assertEqual(run.panel_names, ["panel 0", "panel 1"])
        self.assertEqual((run.hinge_events, run.latch_times), ([], {}))
        self.assertEqual(run["events/hinge/w_jump_B"].shape, (0, 3))
        self.assertEqual(len(run.spin_axis_45_time), 0)
        self.assertEqual([s["caveat"] for s in run.stages], [""] * 5)
        self.assertEqual([s["rigid_body_only"] for s in run.stages], [0] * 5)
        self.assertIsNone(run.get("hinge_rates"))
        with self.assertRaises(deploysim_results.TrajectoryError) as e:
            run["hinge_rates"]
        self.assertEqual(str(e.exception),
                         f"{self.old}: not a deploysim trajectory (no dataset /hinge_rates)")

    def assert_error(self, path, words):
        with self.assertRaises(deploysim_results.TrajectoryError) as e:
            deploysim_results.read_trajectory(str(path))
        msg = str(e.exception)
        self.assertTrue(msg.startswith(f"{path}: "), msg)
        self.assertIn(words, msg)
        self.assertEqual(len(msg.splitlines()), 1, msg)

    def test_errors_name_the_file_and_what_is_wrong(self):
        self.assert_error(self.dir / "nope.h5", "no such file")
        text = self.dir / "notes.h5"
        text.write_text("not HDF5\n")
        self.assert_error(text, "not an HDF5 file")
        v3 = self.dir / "v3.h5"
        shutil.copy(self.fresh, v3)
        with h5py.File(v3, "r+") as f:
            f.attrs["schema_version"] = "3"
        self.assert_error(v3, "schema_version 3: this reader reads version 2 only")
        foreign = self.dir / "foreign.h5"
        with h5py.File(foreign, "w") as f:
            f["time"] = np.zeros(3)
        self.assert_error(foreign, "not a deploysim trajectory (no schema_version attribute)")
        no_q = self.dir / "no_q.h5"
        shutil.copy(self.fresh, no_q)
        with h5py.File(no_q, "r+") as f:
            del f["q_NB"]
        run = deploysim_results.read_trajectory(str(no_q))
        with self.assertRaises(deploysim_results.TrajectoryError) as e:
            run["q_NB"]
        self.assertEqual(str(e.exception),
                         f"{no_q}: not a deploysim trajectory (no dataset /q_NB)")
        with self.assertRaises(deploysim_results.TrajectoryError) as e:
            run.attr("no_such_attribute")
        self.assertIn("@no_such_attribute", str(e.exception))


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    DEPLOYSIM = os.path.abspath(sys.argv[1])
    SOURCE = os.path.abspath(sys.argv[2])
    ARTEFACTS = os.path.abspath(sys.argv[3] if len(sys.argv) > 3
                                else os.path.join("test_artefacts", "report"))
    if not shutil.which(DEPLOYSIM):
        sys.exit(f"report_test: {DEPLOYSIM}: not an executable")
    t0 = time.monotonic()
    prog = unittest.main(argv=[sys.argv[0], "-v"], exit=False)
    print(f"report_test: {time.monotonic() - t0:.1f} s", file=sys.stderr)
    sys.exit(0 if prog.result.wasSuccessful() else 1)
