#!/usr/bin/python3
"""Time per call against problem size from mbgen_bench's JSON: the closed-loop scaling series.

    ./build/bench/mbgen_bench --benchmark_filter='^fd_chain/' --benchmark_repetitions=3 \\
        --benchmark_format=json --benchmark_out=scaling.json
    bench/scaling_chart.py scaling.json --png scaling.png

Benchmarks named <algorithm>/<k>/<implementation> (default algorithm fd_chain: a chain of k loop
modules, bench/loop_chain.hpp) give one line per implementation, median time per call against k
on log-log axes. The table also gives each implementation's growth exponent: the slope of
log(time) against log(k) fitted over k >= --fit-from (1 for O(n), 3 for O(n^3) once the
constant costs no longer dominate).

Standard library only (and gnuplot for the chart); run with Debian's /usr/bin/python3.
"""

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report import ReportError, gnuplot_quote, read_medians  # noqa: E402


def series(medians, algorithm):
    """{implementation: [(k, ns), ...] sorted by k}."""
    out = {}
    for (alg, size, implementation), ns in medians.items():
        if alg != algorithm:
            continue
        try:
            k = int(size)
        except ValueError as e:
            raise ReportError(f"{algorithm}/{size}/{implementation}: the size '{size}' is not an integer") from e
        out.setdefault(implementation, []).append((k, ns))
    if not out:
        raise ReportError(f"no '{algorithm}/<k>/<implementation>' benchmarks in the file")
    return {impl: sorted(points) for impl, points in out.items()}


def growth_exponent(points, fit_from):
    """Least-squares slope of log(ns) against log(k) over the points with k >= fit_from."""
    xs = [math.log(k) for k, _ in points if k >= fit_from]
    ys = [math.log(ns) for k, ns in points if k >= fit_from]
    if len(xs) < 2:
        return None
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else None


def markdown(curves, fit_from):
    implementations = list(curves)
    sizes = sorted({k for points in curves.values() for k, _ in points})
    lines = ["| k | " + " | ".join(f"{i} (ns)" for i in implementations) + " |",
             "|---:|" + "---:|" * len(implementations)]
    for k in sizes:
        cells = []
        for i in implementations:
            ns = dict(curves[i]).get(k)
            cells.append(f"{ns:.0f}" if ns is not None else "-")
        lines.append(f"| {k} | " + " | ".join(cells) + " |")
    exponents = []
    for i in implementations:
        e = growth_exponent(curves[i], fit_from)
        exponents.append(f"{i} {e:.2f}" if e is not None else f"{i} -")
    return "\n".join(lines) + f"\n\nGrowth exponent (slope of log time against log k, k >= {fit_from}): " + \
        ", ".join(exponents) + ".\n"


def write_chart(curves, png_path, algorithm):
    gnuplot = shutil.which("gnuplot")
    if gnuplot is None:
        print("scaling_chart.py: gnuplot not found (apt-get install gnuplot-nox): no chart written", file=sys.stderr)
        return False
    with tempfile.TemporaryDirectory() as tmp:
        plots = []
        for n, (implementation, points) in enumerate(curves.items()):
            path = os.path.join(tmp, f"{n}.dat")
            with open(path, "w", encoding="utf-8") as f:
                f.writelines(f"{k} {ns!r}\n" for k, ns in points)
            plots.append(f"{gnuplot_quote(path)} using 1:2 with linespoints title {gnuplot_quote(implementation)}")
        script = "\n".join([
            "set terminal pngcairo size 720,480 noenhanced",
            f"set output {gnuplot_quote(png_path)}",
            "set logscale xy",
            f'set xlabel "k (loop modules, {algorithm})"',
            'set ylabel "median CPU time per call (ns)"',
            "set grid xtics ytics mytics",
            "set key top left",
            "plot " + ", ".join(plots),
        ]) + "\n"
        result = subprocess.run([gnuplot], input=script, text=True, capture_output=True)
        if result.returncode != 0:
            raise ReportError(f"gnuplot failed: {result.stderr.strip()}")
    return True


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("json", help="Google Benchmark JSON (--benchmark_format=json --benchmark_out=FILE)")
    parser.add_argument("--algorithm", default="fd_chain", help="benchmark family <algorithm>/<k>/<impl> (default fd_chain)")
    parser.add_argument("--fit-from", type=int, default=4, help="fit the growth exponent over k >= this (default 4)")
    parser.add_argument("--markdown", help="write the table here (default: standard output)")
    parser.add_argument("--png", help="write the chart here (needs gnuplot)")
    args = parser.parse_args(argv)
    try:
        medians, _ = read_medians(args.json, "cpu_time")
        curves = series(medians, args.algorithm)
        table = markdown(curves, args.fit_from)
        if args.markdown:
            with open(args.markdown, "w", encoding="utf-8") as f:
                f.write(table)
        else:
            sys.stdout.write(table)
        if args.png:
            write_chart(curves, args.png, args.algorithm)
    except ReportError as e:
        print(f"scaling_chart.py: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
