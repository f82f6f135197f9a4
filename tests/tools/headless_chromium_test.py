#!/usr/bin/python3
"""tools/headless_chromium.py finds what the page tests rely on it to find: console errors,
uncaught exceptions and failed resource loads, none on a clean page; it evaluates
JavaScript and writes a PNG screenshot."""

import pathlib
import sys
import tempfile
import unittest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import headless_chromium  # noqa: E402

BAD = """<!doctype html><html><body><p>x</p>
<script>console.log("a log line is not an error"); console.error("boom");
undefinedFunction();</script><img src="missing.png"></body></html>"""
GOOD = """<!doctype html><html><head><title>clean</title></head>
<body style="background:#fff"><p id="p">clean</p><script>console.log("fine");
document.getElementById("p").dataset.n = 6 * 7;</script></body></html>"""


class HeadlessChromiumTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.dir = pathlib.Path(cls.tmp.name)
        (cls.dir / "bad.html").write_text(BAD)
        (cls.dir / "good.html").write_text(GOOD)
        cls.browser = headless_chromium.Browser(640, 480)

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()
        cls.tmp.cleanup()

    def test_reports_every_kind_of_error(self):
        errs = self.browser.open((self.dir / "bad.html").as_uri()).errors()
        self.assertEqual(len(errs), 3, errs)
        joined = "\n".join(errs)
        self.assertIn("console.error: boom", joined)
        self.assertIn("undefinedFunction is not defined", joined)
        self.assertIn("missing.png", joined)
        self.assertNotIn("a log line", joined)

    def test_clean_page_evaluate_and_screenshot(self):
        page = self.browser.open((self.dir / "good.html").as_uri())
        self.assertEqual(page.errors(), [])
        self.assertEqual(page.evaluate("document.title"), "clean")
        self.assertEqual(page.evaluate("document.getElementById('p').dataset.n"), "42")
        png = self.dir / "shot.png"
        page.screenshot(png)
        self.assertEqual(png.read_bytes()[:8], b"\x89PNG\r\n\x1a\n")
        with self.assertRaises(headless_chromium.ChromiumError):
            page.evaluate("noSuchName + 1")


if __name__ == "__main__":
    unittest.main()
