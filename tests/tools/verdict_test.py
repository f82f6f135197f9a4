#!/usr/bin/python3
"""Every shipped profile's verdict comes from one outcome record: `deploysim analyze
--json`'s "outcome", the trajectory file's `outcome` attribute, the mission report's
verdict sentence (tools/report.py) and the 3D viewer's verdict line (tools/view.py) are
the same record and the same headline.

Usage: verdict_test.py DEPLOYSIM SOURCE_DIR RUNS_DIR
RUNS_DIR: the shipped profiles' runs (simulate -o, analyze --json) that
tools/shipped_runs.py wrote with the same DEPLOYSIM (the ctest fixture Shipped.Runs).
"""
import html
import pathlib
import re
import sys
import unittest

DEPLOYSIM, SRC, RUNS = None, None, None


class OneRecord(unittest.TestCase):
    def test_every_shipped_profile(self):
        sys.path.insert(0, str(SRC / "tools"))
        import report  # noqa: E402
        import view  # noqa: E402
        from deploysim_results import read_trajectory  # noqa: E402
        from deploysim_scene import read_run  # noqa: E402
        from shipped_runs import ShippedRuns, shipped_profiles  # noqa: E402

        runs = ShippedRuns(DEPLOYSIM, RUNS)
        profiles = shipped_profiles()
        self.assertGreaterEqual(len(profiles), 12)
        for p in profiles:
            with self.subTest(profile=p):
                self.assertIsNotNone(runs.get(p), f"{RUNS} holds no run of {p}")
                h5 = runs.get(p)["h5"]
                analyzed = runs.analyzed(p)["outcome"]
                stored = read_trajectory(str(h5)).outcome
                self.assertEqual(stored, analyzed)
                headline = analyzed["headline"]
                self.assertTrue(headline)
                # The report's verdict sentence, its markup taken off.
                h = read_trajectory(str(h5))
                sentence = report.verdict(report.Cells(h), h, {})
                self.assertIn('data-h5="@outcome#headline"', sentence)
                self.assertEqual(html.unescape(re.sub(r"<[^>]+>", "", sentence)), headline)
                # The viewer's page data.
                data = view.build_data(read_run(str(h5)))
                self.assertEqual(data["outcome"]["headline"], headline)
                self.assertEqual(data["outcome"]["name"], analyzed["name"])
                print(f"{pathlib.Path(p).stem}: {headline}", file=sys.stderr)


if __name__ == "__main__":
    DEPLOYSIM = pathlib.Path(sys.argv[1])
    SRC = pathlib.Path(sys.argv[2])
    RUNS = sys.argv[3]
    unittest.main(argv=sys.argv[:1], verbosity=2)
