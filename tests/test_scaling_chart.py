#!/usr/bin/python3
"""Tests bench/scaling_chart.py on a synthetic Google Benchmark JSON file written here: a
'generic' series growing as 100 k and a 'reference' series as 10 k^3 (k = 1, 2, ..., 64), so the
fitted growth exponents must come out 1.00 and 3.00, and the table must list every k."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "bench", "scaling_chart.py")


def sample(path):
    benchmarks = []
    for k in (1, 2, 4, 8, 16, 32, 64):
        for impl, ns in (("generic", 100.0 * k), ("reference", 10.0 * k ** 3)):
            benchmarks.append({"name": f"fd_chain/{k}/{impl}", "run_name": f"fd_chain/{k}/{impl}", "run_type": "iteration",
                               "cpu_time": ns, "real_time": ns, "time_unit": "ns", "family_index": len(benchmarks)})
    benchmarks.append({"name": "aba/iiwa14/generic", "run_name": "aba/iiwa14/generic", "run_type": "iteration",
                       "cpu_time": 5.0, "real_time": 5.0, "time_unit": "ns"})  # another family: ignored
    with open(path, "w", encoding="utf-8") as f:
        json.dump({"context": {}, "benchmarks": benchmarks}, f)


class ScalingChartTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.json = os.path.join(self.tmp, "scaling.json")
        sample(self.json)

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def run_script(self, *args):
        return subprocess.run([sys.executable, SCRIPT, self.json, *args], capture_output=True, text=True)

    def test_table_and_exponents(self):
        result = self.run_script()
        self.assertEqual(result.returncode, 0, result.stderr)
        lines = result.stdout.splitlines()
        self.assertEqual(lines[0], "| k | generic (ns) | reference (ns) |")
        self.assertEqual(lines[2], "| 1 | 100 | 10 |")
        self.assertEqual(lines[8], "| 64 | 6400 | 2621440 |")
        self.assertIn("generic 1.00, reference 3.00", result.stdout)

    def test_chart(self):
        if shutil.which("gnuplot") is None:
            self.skipTest("gnuplot not installed")
        png = os.path.join(self.tmp, "scaling.png")
        result = self.run_script("--png", png)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_missing_family_is_an_error(self):
        result = self.run_script("--algorithm", "nothing")
        self.assertEqual(result.returncode, 1)
        self.assertIn("no 'nothing/<k>/<implementation>' benchmarks", result.stderr)


if __name__ == "__main__":
    unittest.main()
