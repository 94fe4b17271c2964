#!/usr/bin/env python3
"""`mbgen view`'s options that change what the page holds (generator/cli/view_command.cpp).

On a one-link SDFormat model whose only collision geometry is a TALOS mesh
(tests/data/sdf/one_mesh_link.sdf, also fit-ssv's test):
- by default the page holds the mesh and no SSV (the link has none);
- --fit adds the link's SSV, and it is exactly the compound `mbgen fit-ssv` writes for it;
- --no-meshes leaves the mesh out, with or without --fit;
- --quiet prints nothing on success.

Usage: test_view_command.py MBGEN_BINARY SOURCE_DIR SHARED_ROBOTS WORK_DIR
"""
import json
import os
import re
import subprocess
import sys

MBGEN, SOURCE, ROBOTS, WORK = sys.argv[1:5]
PACKAGE = ["--package-path", "example-robot-data=" + os.path.join(ROBOTS, "talos/meshes/example-robot-data")]
failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


def run(*arguments):
    result = subprocess.run([MBGEN, *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"mbgen {' '.join(arguments)} failed ({result.returncode}): {result.stderr}")
    return result.stdout


def scene(*options):
    page = os.path.join(WORK, "page.html")
    run("view", model, *PACKAGE, "--out", page, "--quiet", *options)
    text = open(page, encoding="utf-8").read()
    return json.loads(re.search(r'id="mbgen-scene">(.*?)</script>', text, re.S).group(1))


os.makedirs(WORK, exist_ok=True)
model = os.path.join(SOURCE, "tests/data/sdf/one_mesh_link.sdf")

plain = scene()
check(len(plain["ssv"]) == 0 and len(plain["meshes"]) == 1, f"default: {len(plain['ssv'])} SSVs, {len(plain['meshes'])} mesh")

fitted = scene("--fit")
check(len(fitted["ssv"]) == 1 and len(fitted["meshes"]) == 1, f"--fit: {len(fitted['ssv'])} SSV, {len(fitted['meshes'])} mesh")
# fit-ssv writes each primitive with six decimals; the page holds the same numbers, rounded to six
# decimals in binary arithmetic (-0.000119 as -0.00011899999999999999): equal to within 1e-15.
extras = os.path.join(WORK, "fitted.yaml")
if os.path.exists(extras):
    os.remove(extras)
run("fit-ssv", model, *PACKAGE, "--out", extras)
line = re.search(r"\{line: \[\[(.*?)\], \[(.*?)\]\], radius: (.*?)\}", open(extras).read())
written = [[float(x) for x in line.group(1).split(",")], [float(x) for x in line.group(2).split(",")]], float(line.group(3))
if fitted["ssv"]:
    ssv = fitted["ssv"][0]
    numbers = [x for p in ssv["points"] for x in p] + [ssv["radius"]]
    expected = [x for p in written[0] for x in p] + [written[1]]
    check(ssv["kind"] == "line" and max(abs(a - b) for a, b in zip(numbers, expected)) <= 1e-15,
          f"--fit's SSV {ssv['kind']} {ssv['points']} r {ssv['radius']} is fit-ssv's {written}")

bare = scene("--no-meshes")
check(len(bare["meshes"]) == 0 and len(bare["ssv"]) == 0, f"--no-meshes: {len(bare['meshes'])} meshes")
both = scene("--fit", "--no-meshes")
check(len(both["meshes"]) == 0 and len(both["ssv"]) == 1, f"--fit --no-meshes: {len(both['ssv'])} SSV, {len(both['meshes'])} meshes")

quiet = subprocess.run([MBGEN, "view", model, *PACKAGE, "--out", os.path.join(WORK, "quiet.html"), "--quiet"], capture_output=True, text=True)
loud = subprocess.run([MBGEN, "view", model, *PACKAGE, "--out", os.path.join(WORK, "loud.html")], capture_output=True, text=True)
check(quiet.returncode == 0 and quiet.stdout == "" and loud.stdout.startswith("mbgen view: m: 1 bodies"),
      f"--quiet prints nothing ('{quiet.stdout}'); without it: '{loud.stdout.strip()}'")

if failures:
    sys.exit(f"{len(failures)} check(s) failed")
print("all checks passed")
