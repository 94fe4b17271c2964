#!/usr/bin/env python3
"""The pages of `mbgen view` in a real browser (Debian's Chromium, headless, software WebGL).

Each page must load without an error (its data-status and #mbgen-errors, which catch window
errors, rejected promises and console.error) and draw the robot: a screenshot's coloured pixels
form a figure in the middle of the image. Near pairs are drawn warm (red at contact to orange at
the threshold), far ones cool: Lola at its assembled pose has warm pixels with a 3 cm threshold
and none with 0.1 mm; a scripted frame with the legs swung into each other has them at 0.1 mm.
A trajectory whose columns are not the robot's is refused, naming the column; the same input gives
the same bytes; a file mbgen view did not write is never overwritten.

Usage: test_view_page.py MBGEN_BINARY SOURCE_DIR WORK_DIR
"""
import json
import os
import re
import subprocess
import sys

import matplotlib.image

MBGEN, SOURCE, WORK = sys.argv[1:4]
LOLA = [os.path.join(SOURCE, "robots/lola/lola.urdf"), "--extras", os.path.join(SOURCE, "robots/lola/lola.yaml"), "--floating"]
CHROMIUM = ["chromium", "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
            "--window-size=800,600", "--virtual-time-budget=10000"]
failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


def view(name, *arguments):
    page = os.path.join(WORK, name + ".html")
    result = subprocess.run([MBGEN, "view", *LOLA, "--out", page, *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"mbgen view {name} failed ({result.returncode}): {result.stderr}")
    return page


def scene_of(page):
    text = open(page, encoding="utf-8").read()
    return json.loads(re.search(r'id="mbgen-scene">(.*?)</script>', text, re.S).group(1))


def loads_cleanly(page):
    dom = subprocess.run(CHROMIUM + ["--dump-dom", "file://" + page], capture_output=True, text=True, timeout=120).stdout
    status = re.search(r'<body[^>]*data-status="([a-z]*)"', dom)
    errors = re.search(r'<pre id="mbgen-errors">(.*?)</pre>', dom, re.S)
    return (status.group(1) if status else "none"), (errors.group(1).strip() if errors else "no error element")


def pixels(page, frame=0):
    png = os.path.join(WORK, os.path.basename(page) + f".{frame}.png")
    subprocess.run(CHROMIUM + [f"--screenshot={png}", f"file://{page}#frame={frame}"], capture_output=True, timeout=120, check=True)
    image = matplotlib.image.imread(png)[:, :, :3]
    image = image[100:]  # below the control panel
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    warm = (r - b > 0.15) & (r > 0.6)
    cool = (b - r > 0.06)
    return image, warm, cool


def figure_extent(mask):
    rows = mask.any(axis=1).nonzero()[0]
    cols = mask.any(axis=0).nonzero()[0]
    return (rows.min(), rows.max(), cols.min(), cols.max()) if len(rows) else None


os.makedirs(WORK, exist_ok=True)

# The assembled pose with the default 3 cm threshold.
page = view("lola", "--near", "0.03")
status, errors = loads_cleanly(page)
check(status == "ready" and errors == "", f"Lola's page loads: status {status}, errors '{errors}'")
image, warm, cool = pixels(page)
extent = figure_extent(warm | cool)
height, width = warm.shape
check(extent is not None and extent[1] - extent[0] > 0.5 * height and extent[2] > 0.2 * width and extent[3] < 0.8 * width,
      f"the robot fills the middle of the image: rows and columns {extent} of {height} x {width}")
check(cool.sum() > 5000, f"far bodies are drawn cool: {cool.sum()} pixels")
check(warm.sum() > 1000, f"near pairs (3 cm) are drawn warm: {warm.sum()} pixels")
near = scene_of(page)["frames"]["near"][0]
check(len(near) > 0, f"the scene lists {len(near)} pairs within 3 cm")

# 0.1 mm: no pair is that near at the assembled pose; a frame with the left leg rolled into the
# right one has its shanks in contact, and only there is the page warm.
inspected = json.loads(subprocess.run([MBGEN, "inspect", *LOLA, "--json"], capture_output=True, text=True, check=True).stdout)
q_names = [""] * inspected["nq"]
for j in inspected["joints"]:
    width = 7 if j["type"] == "floating" else 1
    for k in range(width):
        q_names[j["idx_q"] + k] = f"{j['name']}[{k}]" if width > 1 else j["name"]
nominal = inspected["assembly"]["q"]
rolled = list(nominal)
rolled[q_names.index("hip_roll_l")] = -0.12
trajectory = os.path.join(WORK, "rolled.csv")
with open(trajectory, "w") as f:
    f.write(",".join(["t"] + q_names) + "\n")
    for t, q in ((0.0, nominal), (0.5, rolled)):
        f.write(",".join([repr(t)] + [repr(x) for x in q]) + "\n")
page = view("lola_rolled", "--near", "0.0001", "--trajectory", trajectory, "--fps", "0")
scene = scene_of(page)
check(len(scene["frames"]["t"]) == 2, f"two rows, two frames: {len(scene['frames']['t'])}")
check(scene["frames"]["near"][0] == [], "no pair within 0.1 mm at the assembled pose")
contact = [n[1] for n in scene["frames"]["near"][1]]
check(len(contact) > 0 and min(contact) < 0, f"the rolled frame has pairs in contact: {sorted(contact)[:3]}")
status, errors = loads_cleanly(page)
check(status == "ready" and errors == "", f"the trajectory's page loads: status {status}, errors '{errors}'")
_, warm0, cool0 = pixels(page, 0)
_, warm1, cool1 = pixels(page, 1)
check(warm0.sum() < 50 and cool0.sum() > 5000, f"assembled pose at 0.1 mm: {warm0.sum()} warm pixels, {cool0.sum()} cool")
check(warm1.sum() > 1000, f"legs in contact: {warm1.sum()} warm pixels")

# A trajectory of another robot is refused, naming the column.
wrong = os.path.join(WORK, "wrong.csv")
with open(wrong, "w") as f:
    f.write(",".join(["t"] + q_names[:8] + ["elbow"] + q_names[9:]) + "\n")
    f.write(",".join(["0"] + [repr(x) for x in nominal]) + "\n")
result = subprocess.run([MBGEN, "view", *LOLA, "--trajectory", wrong, "--out", os.path.join(WORK, "wrong.html")],
                        capture_output=True, text=True)
check(result.returncode == 1 and "column 10 ('elbow')" in result.stderr and f"named '{q_names[8]}'" in result.stderr,
      f"a wrong column is refused (exit {result.returncode}): {result.stderr.strip()[:200]}")
check(not os.path.exists(os.path.join(WORK, "wrong.html")), "and nothing is written")

# The same input gives the same bytes; a file mbgen view did not write is left alone (exit 3).
again = view("lola_again", "--near", "0.03")
check(open(again, "rb").read() == open(os.path.join(WORK, "lola.html"), "rb").read(), "the same input gives a byte-identical page")
foreign = os.path.join(WORK, "foreign.html")
with open(foreign, "w") as f:
    f.write("<html>someone's page</html>\n")
result = subprocess.run([MBGEN, "view", *LOLA, "--out", foreign], capture_output=True, text=True)
check(result.returncode == 3 and "was not written by mbgen view" in result.stderr and open(foreign).read() == "<html>someone's page</html>\n",
      f"a page mbgen view did not write is refused (exit {result.returncode}) and kept")

if failures:
    sys.exit(f"{len(failures)} check(s) failed")
print("all checks passed")
