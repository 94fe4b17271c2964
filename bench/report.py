#!/usr/bin/python3
"""Turns mbgen_bench's Google Benchmark JSON into a Markdown table and a PNG bar chart.

    ./build/bench/mbgen_bench --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true \\
        --benchmark_format=json --benchmark_out=bench.json
    bench/report.py bench.json --markdown bench.md --png bench.png

Benchmarks are named <algorithm>/<robot>/<implementation> (bench/README.md). Each row of the
table is one algorithm on one robot, each column one implementation, in ns per call: the median
over the repetitions (Google Benchmark's `median` aggregate when the file has one, else the
median of the repetitions it holds). Ratio columns divide every other implementation's time by
the generated code's: a ratio above 1 means the generated code is that many times faster.
The chart needs gnuplot (bars on a log-scale time axis); without it only the table is written.

Standard library only; run with Debian's /usr/bin/python3.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

REFERENCE = "generated"
# Columns in this order first; other implementations follow in registration order.
PREFERRED_IMPLEMENTATIONS = ["generated", "generic", "kdl"]
NS_PER_UNIT = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


class ReportError(Exception):
    pass


def split_name(run_name):
    """'<algorithm>/<robot>/<implementation>[/<benchmark argument>...]' -> the three parts."""
    parts = run_name.split("/")
    if len(parts) < 3:
        raise ReportError(
            f"benchmark '{run_name}' is not named <algorithm>/<robot>/<implementation> (bench/README.md)")
    return parts[0], parts[1], parts[2]


def read_medians(path, metric):
    """{(algorithm, robot, implementation): median ns} and the file's context, in registration order."""
    try:
        with open(path, encoding="utf-8") as f:
            document = json.load(f)
    except OSError as e:
        raise ReportError(f"{path}: cannot read: {e.strerror}") from e
    except json.JSONDecodeError as e:
        raise ReportError(f"{path}: not JSON (line {e.lineno}): {e.msg}; "
                          "write it with --benchmark_format=json --benchmark_out=FILE") from e
    if not isinstance(document, dict) or not isinstance(document.get("benchmarks"), list):
        raise ReportError(f"{path}: no 'benchmarks' list: not Google Benchmark JSON output")

    repetitions = {}   # key -> [ns, ...]
    aggregates = {}    # key -> ns (the 'median' aggregate)
    order = {}         # key -> registration order (family_index), else order of appearance
    for position, entry in enumerate(document["benchmarks"]):
        if entry.get("error_occurred"):
            print(f"report.py: skipping {entry.get('name')}: {entry.get('error_message', 'error')}", file=sys.stderr)
            continue
        key = split_name(entry.get("run_name", entry["name"]))
        unit = entry.get("time_unit", "ns")
        if unit not in NS_PER_UNIT:
            raise ReportError(f"{path}: {entry['name']}: unknown time_unit '{unit}'")
        if metric not in entry:
            raise ReportError(f"{path}: {entry['name']} has no '{metric}'")
        ns = float(entry[metric]) * NS_PER_UNIT[unit]
        order.setdefault(key, (entry.get("family_index", position), position))
        if entry.get("run_type") == "aggregate":
            if entry.get("aggregate_name") == "median":
                aggregates[key] = ns
        else:
            repetitions.setdefault(key, []).append(ns)

    medians = {}
    for key in sorted(order, key=order.get):
        if key in aggregates:
            medians[key] = aggregates[key]
        elif key in repetitions:
            medians[key] = statistics.median(repetitions[key])
    if not medians:
        raise ReportError(f"{path}: no benchmark results (only aggregates other than the median?)")
    return medians, document.get("context", {})


def table_layout(medians):
    """Rows [(algorithm, robot)] and columns [implementation] in first-registration order."""
    rows, implementations = [], []
    for algorithm, robot, implementation in medians:
        if (algorithm, robot) not in rows:
            rows.append((algorithm, robot))
        if implementation not in implementations:
            implementations.append(implementation)
    columns = [i for i in PREFERRED_IMPLEMENTATIONS if i in implementations]
    columns += [i for i in implementations if i not in columns]
    return rows, columns


def format_ns(ns):
    return f"{ns:.1f}" if ns < 100 else f"{ns:.0f}"


def markdown_table(medians, context, metric):
    rows, columns = table_layout(medians)
    ratio_columns = [c for c in columns if c != REFERENCE] if REFERENCE in columns else []
    header = ["algorithm", "robot"] + [f"{c} (ns)" for c in columns] + [f"{c} / {REFERENCE}" for c in ratio_columns]
    lines = ["| " + " | ".join(header) + " |",
             "|" + "|".join(["---"] * 2 + ["---:"] * (len(header) - 2)) + "|"]
    for algorithm, robot in rows:
        cells = [algorithm, robot]
        for c in columns:
            ns = medians.get((algorithm, robot, c))
            cells.append(format_ns(ns) if ns is not None else "-")
        reference = medians.get((algorithm, robot, REFERENCE))
        for c in ratio_columns:
            ns = medians.get((algorithm, robot, c))
            cells.append(f"{ns / reference:.2f}" if ns is not None and reference else "-")
        lines.append("| " + " | ".join(cells) + " |")

    what = "CPU time" if metric == "cpu_time" else "wall-clock time"
    source = " on ".join(x for x in [os.path.basename(context.get("executable", "")), context.get("date", "")] if x)
    notes = [f"Median {what} per call, ns" + (f" ({source}, {context['num_cpus']} CPUs)." if source and "num_cpus" in context
                                                else f" ({source})." if source else ".")]
    if ratio_columns:
        notes.append(f"`<implementation> / {REFERENCE}`: how many times faster the generated code is (above 1: faster).")
    return "\n".join(lines) + "\n\n" + " ".join(notes) + "\n"


def gnuplot_quote(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def write_chart(medians, png_path, metric):
    """Clustered bars, one cluster per algorithm/robot, log-scale time axis. False without gnuplot."""
    gnuplot = shutil.which("gnuplot")
    if gnuplot is None:
        print("report.py: gnuplot not found (apt-get install gnuplot-nox): no chart written", file=sys.stderr)
        return False
    rows, columns = table_layout(medians)
    with tempfile.TemporaryDirectory() as tmp:
        data_path = os.path.join(tmp, "medians.dat")
        with open(data_path, "w", encoding="utf-8") as f:
            for algorithm, robot in rows:
                values = [medians.get((algorithm, robot, c)) for c in columns]
                f.write(" ".join([gnuplot_quote(f"{algorithm}/{robot}")] +
                                 [repr(v) if v is not None else "?" for v in values]) + "\n")
        plots = [f"{gnuplot_quote(data_path) if i == 0 else chr(39) * 2} using {i + 2}"
                 f"{':xtic(1)' if i == 0 else ''} title {gnuplot_quote(c)}" for i, c in enumerate(columns)]
        what = "CPU time" if metric == "cpu_time" else "wall-clock time"
        script = "\n".join([
            f"set terminal pngcairo size {max(640, 110 * len(rows) + 200)},480 noenhanced",
            f"set output {gnuplot_quote(png_path)}",
            'set datafile missing "?"',
            "set style data histograms",
            "set style histogram clustered gap 1",
            "set style fill solid 0.85 border -1",
            "set logscale y",
            f'set ylabel "median {what} per call (ns, log scale)"',
            "set grid ytics mytics",
            "set xtics rotate by -30 nomirror",
            "set key outside right top",
            "set yrange [*:*]",
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
    parser.add_argument("--markdown", help="write the table here (default: standard output)")
    parser.add_argument("--png", help="write the bar chart here (needs gnuplot)")
    parser.add_argument("--time", choices=["cpu", "real"], default="cpu",
                        help="which time to report (default: cpu; a shared machine's wall-clock time includes waiting)")
    args = parser.parse_args(argv)
    metric = f"{args.time}_time"
    try:
        medians, context = read_medians(args.json, metric)
        table = markdown_table(medians, context, metric)
        if args.markdown:
            with open(args.markdown, "w", encoding="utf-8") as f:
                f.write(table)
        else:
            sys.stdout.write(table)
        if args.png:
            write_chart(medians, args.png, metric)
    except ReportError as e:
        print(f"report.py: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
