#!/usr/bin/python3
"""Tests bench/report.py on tests/data/bench_sample.json, a Google Benchmark 1.7 JSON file in the
shape mbgen_bench writes (random interleaving, repetitions, aggregates for one family, an errored
benchmark, a time unit other than ns). The expected medians and ratios are worked out by hand in
the comments below."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPORT = os.path.join(HERE, "..", "bench", "report.py")
SAMPLE = os.path.join(HERE, "data", "bench_sample.json")


def run_report(*args):
    return subprocess.run([sys.executable, REPORT, *args], capture_output=True, text=True)


class BenchReportTest(unittest.TestCase):
    def test_table_has_medians_and_ratios(self):
        result = run_report(SAMPLE)
        self.assertEqual(result.returncode, 0, result.stderr)
        lines = result.stdout.splitlines()
        self.assertEqual(lines[0], "| algorithm | robot | generated (ns) | generic (ns) | kdl (ns) "
                                   "| generic / generated | kdl / generated |")
        # Rows in registration order (family_index), whatever order the interleaved runs came in.
        # aba/iiwa14: the 'median' aggregates (120, 360, 1440), not the repetitions' medians
        #   (125, 360, 1440): 360 / 120 = 3, 1440 / 120 = 12.
        # rnea/iiwa14: no aggregates: median of (50, 40, 60) = 50; of (100, 140, 120, 160) = 130;
        #   kdl in us: median of (0.25, 0.3, 0.2) us = 250 ns. 130 / 50 = 2.6, 250 / 50 = 5.
        # aba/talos: median of (880, 900, 950) = 900, of (2650, 2700, 2800) = 2700; no kdl.
        # crba/hyq: generic only: no ratio. jacobians/iiwa14/kdl errored: no row.
        self.assertEqual(lines[2:6], [
            "| aba | iiwa14 | 120 | 360 | 1440 | 3.00 | 12.00 |",
            "| rnea | iiwa14 | 50.0 | 130 | 250 | 2.60 | 5.00 |",
            "| aba | talos | 900 | 2700 | - | 3.00 | - |",
            "| crba | hyq | - | 512 | - | - | - |",
        ])
        self.assertEqual(lines[6], "")
        self.assertIn("Median CPU time per call", lines[7])
        self.assertIn("skipping jacobians/iiwa14/kdl: KDL chain has no tip frame", result.stderr)

    def test_real_time_on_request(self):
        # The sample's real times are twice its CPU times.
        result = run_report(SAMPLE, "--time", "real")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("| aba | iiwa14 | 240 | 720 | 2880 | 3.00 | 12.00 |", result.stdout)
        self.assertIn("Median wall-clock time per call", result.stdout)

    def test_writes_markdown_file_and_png(self):
        with tempfile.TemporaryDirectory() as tmp:
            markdown, png = os.path.join(tmp, "bench.md"), os.path.join(tmp, "bench.png")
            result = run_report(SAMPLE, "--markdown", markdown, "--png", png)
            self.assertEqual(result.returncode, 0, result.stderr)
            self.assertEqual(result.stdout, "")
            with open(markdown, encoding="utf-8") as f:
                self.assertIn("| rnea | iiwa14 | 50.0 | 130 | 250 | 2.60 | 5.00 |", f.read())
            if not shutil.which("gnuplot"):
                self.skipTest("gnuplot not installed: PNG not checked (scripts/install_deps.sh installs it)")
            with open(png, "rb") as f:
                data = f.read()
            self.assertTrue(data.startswith(b"\x89PNG\r\n\x1a\n"), "not a PNG file")
            self.assertGreater(len(data), 5000)

    def test_bad_inputs_are_reported(self):
        with tempfile.TemporaryDirectory() as tmp:
            not_json = os.path.join(tmp, "console.txt")
            with open(not_json, "w") as f:
                f.write("Benchmark  Time  CPU  Iterations\n")
            result = run_report(not_json)
            self.assertEqual(result.returncode, 1)
            self.assertIn("console.txt: not JSON (line 1)", result.stderr)
            self.assertIn("--benchmark_format=json --benchmark_out=FILE", result.stderr)

            badly_named = os.path.join(tmp, "named.json")
            with open(badly_named, "w") as f:
                f.write('{"benchmarks": [{"name": "BM_aba", "run_type": "iteration", "cpu_time": 1, "real_time": 1}]}')
            result = run_report(badly_named)
            self.assertEqual(result.returncode, 1)
            self.assertIn("benchmark 'BM_aba' is not named <algorithm>/<robot>/<implementation>", result.stderr)

            result = run_report(os.path.join(tmp, "missing.json"))
            self.assertEqual(result.returncode, 1)
            self.assertIn("missing.json: cannot read", result.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
