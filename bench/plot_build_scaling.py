#!/usr/bin/env python3
"""Plots build time per triangle against the number of triangles, one line per structure, from
the JSON that `build_scaling --json FILE` writes (bench/build_scaling.cpp): the O(N log N)
curve of issue #19's report, as an SVG with no library beyond Python's own.

Both axes are logarithmic: x the triangles (10^4 to 10^7), y the build's nanoseconds per
triangle. A build in O(N log N) rises by log2 N from one decade to the next (about 1.25x from
10^5 to 10^6), a linear one stays flat; the dotted grey line shows the slope of log2 N through
the first structure's first point, for comparison. Embree's row (`embree`), when present, is
dashed.

Usage:
  bench/plot_build_scaling.py JSON [JSON ...] [--out FILE.svg] [--title TEXT] [--accel a,b,...]

Several files are merged: a structure measured at several thread counts gets one line per count
("bvh, 2 threads"), and one measured several times at the same size and thread count (repeated
runs of build_scaling, whose builds of a million triangles or more are single) gets the median
of its builds there. `--accel` keeps the structures named (as build_scaling names them, without
the thread count), in that order. Bad input (a file that cannot be read, not
JSON, a row without `accel`, `triangles` or `build_ms`, a value that is not a positive number)
is reported with the file and the row and exits with status 1, writing nothing. The SVG is
written through a temporary file and a rename: no partial file.
"""

import argparse
import json
import math
import os
import statistics
import sys
from xml.sax.saxutils import escape

# Colours that stay apart in print and for the common colour-vision deficiencies (Okabe & Ito).
COLOURS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442",
           "#000000"]
MARKERS = ["circle", "square", "triangle", "diamond"]
WIDTH, HEIGHT = 760, 480
LEFT, RIGHT, TOP, BOTTOM = 70, 200, 40, 50  # margins around the plot area


class InputError(Exception):
    pass


def load_rows(paths, only=None):
    """Every row of every file as (label, triangles, ns per triangle); with `only`, the rows of
    those structures, in that order (then by thread count)."""
    rows = []
    for path in paths:
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise InputError(f"{path}: cannot read: {e.strerror}")
        try:
            data = json.loads(text)
        except json.JSONDecodeError as e:
            raise InputError(f"{path}: line {e.lineno}, column {e.colno}: not JSON: {e.msg}")
        if not isinstance(data, list):
            raise InputError(f"{path}: expected an array of rows, found {type(data).__name__}")
        for i, row in enumerate(data):
            where = f"{path}: row {i}"
            if not isinstance(row, dict):
                raise InputError(f"{where}: expected an object")
            for key in ("accel", "triangles", "build_ms"):
                if key not in row:
                    raise InputError(f"{where}: no '{key}'")
            accel = row["accel"]
            if not isinstance(accel, str) or not accel:
                raise InputError(f"{where}: 'accel' is not a name")
            for key in ("triangles", "build_ms"):
                v = row[key]
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not (
                        math.isfinite(v) and v > 0):
                    raise InputError(f"{where}: '{key}' is {v!r}, not a positive number")
            threads = row.get("threads")
            if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int)
                                        or threads < 1):
                raise InputError(f"{where}: 'threads' is {threads!r}, not a thread count")
            rows.append((accel, threads, float(row["triangles"]),
                         row["build_ms"] * 1e6 / row["triangles"]))
    if not rows:
        raise InputError(f"{', '.join(paths)}: no rows to plot")
    if only:
        present = list(dict.fromkeys(a for a, _, _, _ in rows))
        missing = [a for a in only if a not in present]
        if missing:
            raise InputError(f"--accel: no rows for {', '.join(missing)} "
                             f"(the files hold {', '.join(present)})")
        rows = sorted((r for r in rows if r[0] in only),
                      key=lambda r: (only.index(r[0]), r[1] is None, r[1] or 0))
    # A thread count in the label only where the rows have several.
    counts = {t for _, t, _, _ in rows}
    labelled = []
    for accel, threads, n, ns in rows:
        label = accel
        if len(counts) > 1 and threads is not None:
            label += f", {threads} thread{'s' if threads != 1 else ''}"
        labelled.append((label, n, ns))
    return labelled


def series(rows):
    """Labels in first-seen order, each with its points sorted by triangles; repeated
    measurements of a label at one size reduced to their median."""
    grouped = {}
    for label, n, ns in rows:
        grouped.setdefault(label, {}).setdefault(n, []).append(ns)
    return {label: sorted((n, statistics.median(v)) for n, v in by_n.items())
            for label, by_n in grouped.items()}


def decades(lo, hi):
    """Powers of ten spanning [lo, hi], one beyond each end where needed."""
    a, b = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    if a == b:
        b += 1
    return a, b


def marker(shape, x, y, colour):
    r = 4
    if shape == "circle":
        return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r}" fill="{colour}"/>'
    if shape == "square":
        return (f'<rect x="{x - r:.1f}" y="{y - r:.1f}" width="{2 * r}" height="{2 * r}" '
                f'fill="{colour}"/>')
    if shape == "triangle":
        pts = f"{x:.1f},{y - r - 1:.1f} {x - r - 1:.1f},{y + r:.1f} {x + r + 1:.1f},{y + r:.1f}"
        return f'<polygon points="{pts}" fill="{colour}"/>'
    pts = (f"{x:.1f},{y - r - 1:.1f} {x + r + 1:.1f},{y:.1f} {x:.1f},{y + r + 1:.1f} "
           f"{x - r - 1:.1f},{y:.1f}")
    return f'<polygon points="{pts}" fill="{colour}"/>'


def svg(lines, title):
    ns_all = [ns for pts in lines.values() for _, ns in pts]
    n_all = [n for pts in lines.values() for n, _ in pts]
    x0, x1 = decades(min(n_all), max(n_all))
    y0, y1 = decades(min(ns_all), max(ns_all))
    pw, ph = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM

    def px(n):
        return LEFT + (math.log10(n) - x0) / (x1 - x0) * pw

    def py(ns):
        return TOP + ph - (math.log10(ns) - y0) / (y1 - y0) * ph

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
           f'viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="12">',
           f'<rect width="{WIDTH}" height="{HEIGHT}" fill="white"/>',
           f'<text x="{LEFT + pw / 2:.1f}" y="{TOP - 16}" text-anchor="middle" '
           f'font-size="14">{escape(title)}</text>']
    # Grid and ticks: decades, with 2 and 5 between on the y axis.
    for e in range(x0, x1 + 1):
        x = px(10.0 ** e)
        out.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{TOP + ph}" stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{TOP + ph + 18}" text-anchor="middle">10'
                   f'<tspan dy="-6" font-size="9">{e}</tspan></text>')
    for e in range(y0, y1 + 1):
        for m in (1, 2, 5):
            v = m * 10.0 ** e
            if v > 10.0 ** y1:
                break
            y = py(v)
            out.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{LEFT + pw}" y2="{y:.1f}" '
                       f'stroke="{"#ddd" if m == 1 else "#f0f0f0"}"/>')
            out.append(f'<text x="{LEFT - 6}" y="{y + 4:.1f}" text-anchor="end">'
                       f'{v:g}</text>')
    out.append(f'<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" '
               f'stroke="#444"/>')
    out.append(f'<text x="{LEFT + pw / 2:.1f}" y="{HEIGHT - 12}" text-anchor="middle">'
               f'triangles</text>')
    out.append(f'<text transform="translate(18 {TOP + ph / 2:.1f}) rotate(-90)" '
               f'text-anchor="middle">build ns per triangle</text>')
    # The slope of log2 N, through the first line's first point.
    first = next(iter(lines.values()))
    n_a, ns_a = first[0]
    ref = [(n, ns_a * math.log2(n) / math.log2(n_a))
           for n in (10.0 ** (x0 + k * (x1 - x0) / 32) for k in range(33)) if n >= n_a]
    ref = [(n, v) for n, v in ref if 10.0 ** y0 <= v <= 10.0 ** y1]
    if len(ref) > 1:
        pts = " ".join(f"{px(n):.1f},{py(v):.1f}" for n, v in ref)
        out.append(f'<polyline class="reference" points="{pts}" fill="none" stroke="#888" '
                   f'stroke-dasharray="2 3"/>')
    # One line per structure, with its legend entry. Past eight lines the colours repeat, with
    # the next marker shape.
    lx = LEFT + pw + 16  # the legend's left edge
    for k, (label, pts) in enumerate(lines.items()):
        colour = COLOURS[k % len(COLOURS)]
        shape = MARKERS[(k // len(COLOURS) + k) % len(MARKERS)]
        dash = ' stroke-dasharray="6 4"' if label.startswith("embree") else ""
        coords = " ".join(f"{px(n):.1f},{py(ns):.1f}" for n, ns in pts)
        out.append(f'<g class="series" data-label="{escape(label)}">')
        out.append(f'<polyline points="{coords}" fill="none" stroke="{colour}" '
                   f'stroke-width="2"{dash}/>')
        out.extend(marker(shape, px(n), py(ns), colour) for n, ns in pts)
        ly = TOP + 10 + 20 * k
        out.append(f'<line x1="{lx}" y1="{ly}" x2="{lx + 24}" y2="{ly}" stroke="{colour}" '
                   f'stroke-width="2"{dash}/>')
        out.append(marker(shape, lx + 12, ly, colour))
        out.append(f'<text x="{lx + 32}" y="{ly + 4}">{escape(label)}</text>')
        out.append("</g>")
    ly = TOP + 10 + 20 * len(lines)
    if len(ref) > 1:
        out.append(f'<line x1="{lx}" y1="{ly}" x2="{lx + 24}" y2="{ly}" stroke="#888" '
                   f'stroke-dasharray="2 3"/>')
        out.append(f'<text x="{lx + 32}" y="{ly + 4}">∝ log2 N</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def write_atomically(path, text):
    """`text` to `path` through PATH.tmp and a rename, as issue19.py and ab_accel.py write."""
    tmp = path + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("json", nargs="+", help="build_scaling --json output(s)")
    p.add_argument("--out", default="build-scaling.svg", help="SVG to write")
    p.add_argument("--title", default="Build time per triangle (terrain)", help="plot title")
    p.add_argument("--accel", default="", help="the structures to draw, comma-separated")
    args = p.parse_args(argv)
    try:
        only = [a for a in args.accel.split(",") if a]
        lines = series(load_rows(args.json, only))
        text = svg(lines, args.title)
        write_atomically(args.out, text)
    except InputError as e:
        print(f"plot_build_scaling: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"plot_build_scaling: {args.out}: cannot write: {e.strerror}", file=sys.stderr)
        return 1
    print(f"wrote {args.out}: {len(lines)} line(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
