#!/usr/bin/env python3
"""Convergence of the radiosity solvers on a scene: runs `penumbra radiosity` once per solver
(and once with the hierarchy), reads the residual (or change) per iteration it prints, and
writes a table and a log-scale SVG plot.

    python3 bench/radiosity/convergence.py [--penumbra build/penumbra] [--scene scenes/cornell-box.json]
        [--svg docs/images/radiosity-convergence.svg]
"""
import argparse
import math
import re
import subprocess
import sys
import tempfile

RUNS = [
    ("Jacobi", "solver=jacobi"),
    ("Gauss-Seidel", "solver=gauss-seidel"),
    ("progressive (shots / n)", "solver=progressive"),
    ("hierarchical (change per gather)", "hierarchy=true"),
]
COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd"]


def run(penumbra, scene, params):
    with tempfile.NamedTemporaryFile(suffix=".ply") as out:
        p = subprocess.run([penumbra, "radiosity", scene, "-o", out.name, "--integrator",
                            "radiosity:tolerance=1e-6," + params],
                           capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    m = re.search(r"(?:residual|change) per iteration:([0-9eE.+\- ]+)", p.stderr)
    return [float(v) for v in m.group(1).split()], p.stderr


def svg(series, path):
    w, h, left, right, top, bottom = 640, 400, 70, 230, 20, 50
    n_max = max(len(s) for _, s in series)
    lo = math.floor(math.log10(min(min(s) for _, s in series)))
    hi = math.ceil(math.log10(max(max(s) for _, s in series)))
    px = lambda i: left + (w - left - right) * i / max(1, n_max - 1)
    py = lambda v: top + (h - top - bottom) * (hi - math.log10(v)) / (hi - lo)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           'font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(lo, hi + 1):
        y = py(10 ** e)
        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{w - right}" y2="{y:.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">1e{e}</text>')
    for i in range(0, n_max, max(1, n_max // 10)):
        out.append(f'<text x="{px(i):.1f}" y="{h - bottom + 16}" text-anchor="middle">{i}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">'
               'iteration</text>')
    out.append(f'<text x="16" y="{(top + h - bottom) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(top + h - bottom) / 2})">relative residual</text>')
    out.append(f'<rect x="{left}" y="{top}" width="{w - left - right}" '
               f'height="{h - top - bottom}" fill="none" stroke="black"/>')
    for k, (name, s) in enumerate(series):
        pts = " ".join(f"{px(i):.1f},{py(v):.1f}" for i, v in enumerate(s))
        out.append(f'<polyline points="{pts}" fill="none" stroke="{COLOURS[k]}" stroke-width="2"/>')
        ly = top + 10 + 18 * k
        out.append(f'<line x1="{w - right + 10}" y1="{ly}" x2="{w - right + 30}" y2="{ly}" '
                   f'stroke="{COLOURS[k]}" stroke-width="2"/>')
        out.append(f'<text x="{w - right + 36}" y="{ly + 4}">{name}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--scene", default="scenes/cornell-box.json")
    ap.add_argument("--svg", default="")
    a = ap.parse_args()
    series = []
    for name, params in RUNS:
        r, log = run(a.penumbra, a.scene, params)
        series.append((name, r))
        print(f"{name:34s} {len(r):3d} iterations: " + " ".join(f"{v:.1e}" for v in r))
        for line in log.splitlines():
            if line.startswith(("form factors", "hierarchy:")):
                print("    " + line)
    if a.svg:
        svg(series, a.svg)
        print("wrote", a.svg)


if __name__ == "__main__":
    main()
