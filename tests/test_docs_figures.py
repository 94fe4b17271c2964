#!/usr/bin/python3
"""The figures the docs quote from a program, against the program's own output: the operation
counts in Lola's committed generated header (generated/lola/lola.hpp, the generator's `Cost:`
lines, which ctest's generated.up_to_date keeps current) against docs/control.md, and the
model-reductions table that mbgen_study writes (docs/study/study.md) against the header's forward
dynamics. A figure copied by hand goes stale when the generator improves; this fails then."""

import math
import os
import re
import unittest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def read(relative):
    with open(os.path.join(ROOT, relative), encoding="utf-8") as f:
        return f.read()


def header_costs(relative):
    """function name -> operation count, from the `Cost: N operations` line above each declaration."""
    costs, cost = {}, None
    for line in read(relative).splitlines():
        m = re.match(r"/// Cost: (\d+) operations", line)
        if m:
            cost = int(m.group(1))
        m = re.match(r"void (\w+)\(const double\*", line)
        if m and cost is not None:
            costs.setdefault(m.group(1), cost)
            cost = None
    return costs


def number(text):
    return int(text.replace(",", ""))


class DocsFigures(unittest.TestCase):
    def setUp(self):
        self.lola = header_costs("generated/lola/lola.hpp")

    def test_control_quotes_the_task_kinematics_counts(self):
        m = re.search(r"Lola: ([\d,]+) operations against ([\d,]+) for the four functions apart", read("docs/control.md"))
        self.assertIsNotNone(m, "docs/control.md no longer quotes task_kinematics' count")
        four = sum(self.lola[f] for f in ("frame_poses", "frame_jacobians", "center_of_mass", "centroidal_momentum_matrix"))
        self.assertEqual(number(m.group(1)), self.lola["task_kinematics"])
        self.assertEqual(number(m.group(2)), four)

    def test_study_reductions_whole_model_is_the_generated_forward_dynamics(self):
        m = re.search(r"^\| whole model \| (\d+) \| (\d+) \|", read("docs/study/study.md"), re.MULTILINE)
        self.assertIsNotNone(m, "docs/study/study.md has no model-reductions row for the whole model")
        self.assertEqual(int(m.group(1)), 46)  # Lola's nv
        self.assertEqual(int(m.group(2)), self.lola["forward_dynamics"])

    def test_derivatives_quotes_the_accuracy_study(self):
        """docs/derivatives.md's analytic error and best central difference on talos_reduced, against
        the CSV scripts/derivatives_chart.sh wrote beside its charts."""
        rows = [line.split(",") for line in read("docs/derivatives/accuracy.csv").splitlines()[1:]]
        analytic = [float(r[3]) for r in rows if r[0] == "talos" and r[1] == "analytic"]
        central = [float(r[3]) for r in rows if r[0] == "talos" and r[1] == "central"]
        doc = read("docs/derivatives.md")
        self.assertIn(f"exact to {analytic[0]:.1e} (talos", doc)
        order = round(math.log10(min(central)))  # the doc quotes the order of magnitude
        self.assertIn(f"with 1e{order} (talos)", doc)


if __name__ == "__main__":
    unittest.main()
