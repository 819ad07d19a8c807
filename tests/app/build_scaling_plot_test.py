#!/usr/bin/env python3
"""CTest BuildScaling.PlotsEveryStructure: bench/plot_build_scaling.py draws one line per
structure (and per thread count where the files hold several) through its points, on log-log
axes, with the dearer build higher up; takes the median of repeated runs and keeps the
structures --accel names; and refuses bad input with the file and the row, a non-zero exit and
no SVG.

Usage: build_scaling_plot_test.py SOURCE_DIR
"""

import json
import math
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from script_test import fail, run  # noqa: E402

SVG = "{http://www.w3.org/2000/svg}"


def rows(threads, scale=1.0):
    # bvh linear (a flat line), kdtree in N log N (rising), embree a touch below bvh.
    out = []
    for n in (10_000, 100_000, 1_000_000):
        out.append({"accel": "bvh", "triangles": n, "build_ms": 300e-6 * n * scale,
                    "threads": threads})
        out.append({"accel": "kdtree", "triangles": n,
                    "build_ms": 100e-6 * n * math.log2(n) * scale, "threads": threads})
        out.append({"accel": "embree", "triangles": n, "build_ms": 250e-6 * n * scale,
                    "threads": threads})
    return out


def series(svg_path):
    root = ET.parse(svg_path).getroot()
    out = {}
    for g in root.iter(SVG + "g"):
        if g.get("class") != "series":
            continue
        line = g.find(SVG + "polyline")
        pts = [tuple(map(float, p.split(","))) for p in line.get("points").split()]
        out[g.get("data-label")] = (pts, line.get("stroke-dasharray"))
    return root, out


def main():
    src = sys.argv[1]
    script = os.path.join(src, "bench", "plot_build_scaling.py")
    with tempfile.TemporaryDirectory() as tmp:
        one = os.path.join(tmp, "one.json")
        json.dump(rows(1), open(one, "w"))
        out = os.path.join(tmp, "plot.svg")
        p = run(script, one, "--out", out, "--title", "terrain & co")
        if p.returncode != 0:
            fail(f"exit {p.returncode}: {p.stderr}")
        umask = os.umask(0)
        os.umask(umask)
        if os.stat(out).st_mode & 0o777 != 0o666 & ~umask:
            fail(f"mode {oct(os.stat(out).st_mode & 0o777)}, not a new file's usual one")
        root, lines = series(out)
        if sorted(lines) != ["bvh", "embree", "kdtree"]:
            fail(f"lines {sorted(lines)}")
        for label, (pts, _) in lines.items():
            if len(pts) != 3:
                fail(f"{label}: {len(pts)} points, expected 3")
            xs = [x for x, _ in pts]
            if not xs[0] < xs[1] < xs[2]:
                fail(f"{label}: x not increasing with the triangles: {xs}")
            # Log axis: the decades are equally spaced.
            if abs((xs[1] - xs[0]) - (xs[2] - xs[1])) > 0.2:
                fail(f"{label}: decades unequally spaced: {xs}")
        bvh, kd = lines["bvh"][0], lines["kdtree"][0]
        if max(y for _, y in bvh) - min(y for _, y in bvh) > 0.2:
            fail(f"bvh's constant ns per triangle is not flat: {bvh}")
        if not kd[0][1] > kd[1][1] > kd[2][1]:
            fail(f"kdtree's rising ns per triangle does not rise (SVG y falls): {kd}")
        if not all(k[1] < b[1] for k, b in zip(kd, bvh)):
            fail("the dearer build (kdtree) is not drawn above the cheaper one (bvh)")
        if not lines["embree"][1] or lines["bvh"][1]:
            fail("embree's line should be dashed and only it")
        text = "".join(root.itertext())
        if "terrain & co" not in text or "log2 N" not in text:
            fail(f"title or reference missing from the text: {text!r}")
        if len(list(root.iter(SVG + "polyline"))) != 4:  # three lines and the log2 N reference
            fail("expected three lines and the reference slope")

        # Two thread counts: one line per structure and count.
        two = os.path.join(tmp, "two.json")
        json.dump(rows(2, 0.6), open(two, "w"))
        p = run(script, one, two, "--out", out)
        if p.returncode != 0:
            fail(f"two files: exit {p.returncode}: {p.stderr}")
        _, lines = series(out)
        if "bvh, 1 thread" not in lines or "kdtree, 2 threads" not in lines or len(lines) != 6:
            fail(f"two thread counts: lines {sorted(lines)}")
        p = run(script, two, one, "--out", out, "--accel", "kdtree,embree")
        _, lines = series(out)
        order = ["kdtree, 1 thread", "kdtree, 2 threads", "embree, 1 thread", "embree, 2 threads"]
        if list(lines) != order:
            fail(f"--accel kdtree,embree over two thread counts: lines {list(lines)}")

        # Repeated runs: the median of each size; --accel keeps the named ones, in its order.
        runs = []
        for k, scale in enumerate((1.0, 3.0, 1.2)):
            path = os.path.join(tmp, f"run{k}.json")
            json.dump(rows(1, scale), open(path, "w"))
            runs.append(path)
        p = run(script, *runs, "--out", out, "--accel", "kdtree,bvh")
        if p.returncode != 0:
            fail(f"repeated runs: exit {p.returncode}: {p.stderr}")
        _, merged = series(out)
        if list(merged) != ["kdtree", "bvh"]:
            fail(f"--accel kdtree,bvh: lines {list(merged)}")
        p = run(script, runs[2], "--out", out, "--accel", "kdtree,bvh")
        _, middle = series(out)
        if merged != middle:
            fail("three runs at 1.0, 3.0 and 1.2 times should plot as the 1.2 one (the median)")
        p = run(script, one, "--out", os.path.join(tmp, "x.svg"), "--accel", "bvh,grid")
        if p.returncode != 1 or "no rows for grid" not in p.stderr:
            fail(f"--accel with a missing structure: exit {p.returncode}, {p.stderr!r}")

        # Bad input: the file and the row named, status 1, nothing written.
        bad = os.path.join(tmp, "bad.json")
        cases = [
            ("[{\"accel\": \"bvh\",\n  \"triangles\": }]", "line 2"),
            (json.dumps([{"accel": "bvh", "triangles": 10}]), "row 0: no 'build_ms'"),
            (json.dumps(rows(1) + [{"accel": "bvh", "triangles": 0, "build_ms": 1}]),
             "row 9: 'triangles' is 0"),
            (json.dumps([{"accel": "bvh", "triangles": 10, "build_ms": "fast"}]),
             "'build_ms' is 'fast'"),
            (json.dumps({"accel": "bvh"}), "expected an array"),
            (json.dumps([{"accel": "bvh", "triangles": 10, "build_ms": 1, "threads": "two"}]),
             "row 0: 'threads' is 'two'"),
            (json.dumps([]), "no rows"),
        ]
        for text, expected in cases:
            open(bad, "w").write(text)
            target = os.path.join(tmp, "bad.svg")
            p = run(script, bad, "--out", target)
            if p.returncode != 1:
                fail(f"{expected}: exit {p.returncode}, expected 1")
            if expected not in p.stderr or bad not in p.stderr:
                fail(f"expected '{expected}' and the file in the error: {p.stderr!r}")
            if os.path.exists(target):
                fail(f"{expected}: an SVG was written")
        p = run(script, os.path.join(tmp, "missing.json"), "--out", os.path.join(tmp, "m.svg"))
        if p.returncode != 1 or "missing.json: cannot read" not in p.stderr:
            fail(f"missing file: exit {p.returncode}, {p.stderr!r}")
        if [f for f in os.listdir(tmp) if f.endswith(".tmp")]:
            fail("a temporary file was left behind")
    print("ok")


if __name__ == "__main__":
    main()
