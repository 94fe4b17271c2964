#!/usr/bin/env python3
"""What a call from Python costs (docs/python.md, bench/README.md): Lola's generated
forward_dynamics from Python, one state per call and a batch of N states in one call, against the
same C++ function called in a loop by mbgen_bench (`fd/lola/generated`: the demo robot's library,
which the Python module `lola` links, so both run the same machine code).

    PYTHONPATH=build/examples:build/python python3 bench/python_overhead.py [--bench build/bench/mbgen_bench]

The C++ figure is mbgen_bench's median over its repetitions; the Python figures the median of as
many runs, each the mean over its calls. The states: Lola's assembled pose with random
velocities and forces (the C++ pool's are random closed poses; the generated function is
straight-line code, whose time does not depend on the state). Target (issue 56): a batched call
within 1.3x of the C++ loop per state."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import lola
import mbgen

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def cpp_nanoseconds(bench, repetitions):
    """Median ns per call of fd/lola/generated, from mbgen_bench's JSON."""
    with tempfile.TemporaryDirectory() as folder:
        report = os.path.join(folder, "fd_lola.json")  # the benchmarks' own notes go to stdout
        subprocess.run([bench, "--benchmark_filter=^fd/lola/generated$", f"--benchmark_out={report}",
                        "--benchmark_out_format=json", f"--benchmark_repetitions={repetitions}",
                        "--benchmark_report_aggregates_only=true"], check=True, capture_output=True, text=True)
        with open(report) as f:
            benchmarks = json.load(f)["benchmarks"]
    for b in benchmarks:
        if b.get("aggregate_name") == "median":
            return b["real_time"] * {"ns": 1.0, "us": 1e3, "ms": 1e6}[b["time_unit"]]
    sys.exit("python_overhead: mbgen_bench reported no median for fd/lola/generated")


def python_nanoseconds(function, calls, states_per_call, repetitions):
    """Median over repetitions of the mean ns per state of `calls` calls."""
    runs = []
    for _ in range(repetitions):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        runs.append((time.perf_counter() - start) / (calls * states_per_call) * 1e9)
    return statistics.median(runs)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", default=os.path.join(ROOT, "build/bench/mbgen_bench"), help="the mbgen_bench executable")
    parser.add_argument("--states", type=int, default=1000, help="N, the states of a batched call (default 1000)")
    parser.add_argument("--repetitions", type=int, default=7)
    args = parser.parse_args()

    robot = mbgen.load(os.path.join(ROOT, "robots/lola/lola.urdf"), extras=os.path.join(ROOT, "robots/lola/lola.yaml"),
                       base="floating")
    rng = np.random.default_rng(7)
    q, _ = lola.closure_positions(robot.assembled_q)
    Q = np.tile(q, (args.states, 1))
    V = rng.uniform(-1, 1, (args.states, lola.ny))
    TAU = rng.uniform(-10, 10, (args.states, lola.nv))
    vy, tau = V[0], TAU[0]
    single = python_nanoseconds(lambda: lola.forward_dynamics(q, vy, tau), 2000, 1, args.repetitions)
    batched = python_nanoseconds(lambda: lola.forward_dynamics(Q, V, TAU), 5, args.states, args.repetitions)
    cpp = cpp_nanoseconds(args.bench, args.repetitions)
    width = lola.batch_width
    print(f"Lola forward_dynamics (ny {lola.ny}, nv {lola.nv}), ns per state, medians of {args.repetitions}:")
    print("| call | ns per state | / C++ loop |")
    print("|---|---:|---:|")
    print(f"| C++ loop (mbgen_bench fd/lola/generated) | {cpp:.0f} | 1.00 |")
    print(f"| Python, one state per call | {single:.0f} | {single / cpp:.2f} |")
    print(f"| Python, {args.states} states in one call{' (through forward_dynamics_batch, W = %d)' % width if width else ''} "
          f"| {batched:.0f} | {batched / cpp:.2f} |")
    print(f"one call from Python costs {single - cpp:.0f} ns more than the function; a batch pays it once "
          f"(target: batched within 1.3x of the C++ loop: {'met' if batched <= 1.3 * cpp else 'NOT met'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
