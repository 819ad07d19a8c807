#!/usr/bin/env python3
"""Writes the benchmark terrain of issue #19 as a binary PLY: an N x N-vertex height field over
the unit square with ridges, two triangles per cell (bench/terrain.h is the same function in
C++). Default N = 708: 999,698 triangles (2 (N - 1)^2). Plain Python, no packages.

    bench/make_terrain.py [--n N] OUT.ply
"""
import argparse
import math
import os
import struct
import sys
from array import array


def height(x, z):
    h, amplitude, frequency = 0.0, 1.0, 6.0
    for k in range(6):
        a = 0.7 * k
        s = math.sin(frequency * (x * math.cos(a) + z * math.sin(a)) + 1.3 * k)
        h += amplitude * (1 - abs(s)) * (1 - abs(s))
        amplitude *= 0.5
        frequency *= 2
    return 0.08 * h


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=708, help="vertices per side (default 708)")
    args = ap.parse_args()
    n = args.n
    if n < 2 or n > 5000:
        sys.exit("make_terrain.py: --n must lie in [2, 5000]")
    verts = array("f")
    for j in range(n):
        z = j / (n - 1)
        for i in range(n):
            x = i / (n - 1)
            verts.extend((x, height(x, z), z))
    face = struct.Struct("<Biii")
    faces = bytearray()
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            b, c = a + 1, a + n
            faces += face.pack(3, a, c, b) + face.pack(3, b, c, c + 1)
    if sys.byteorder != "little":
        verts.byteswap()
    triangles = 2 * (n - 1) ** 2
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"comment penumbra benchmark terrain, {n} x {n} vertices (bench/make_terrain.py)\n"
        f"element vertex {n * n}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {triangles}\nproperty list uchar int vertex_indices\nend_header\n")
    tmp = args.out + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header.encode())
        f.write(verts.tobytes())
        f.write(faces)
    os.replace(tmp, args.out)
    print(f"{args.out}: {n * n} vertices, {triangles} triangles")


if __name__ == "__main__":
    main()
