#!/usr/bin/env python3
"""Writes the hand-made seeds of fuzz/corpus/ (PLY, OBJ, PFM, PNG, 2D text, JSON): small files
that reach each branch of the readers. The EXR seeds come from make_exr_seeds.cpp."""
import os
import shutil
import struct
import sys
import zlib

root = os.path.dirname(os.path.abspath(__file__))
repo = os.path.dirname(root)


def put(target, name, data):
    d = os.path.join(root, "corpus", target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def copy(target, path):
    with open(os.path.join(repo, path), "rb") as f:
        put(target, "seed-" + os.path.basename(path), f.read())


# PLY: ascii with normals and uvs, binary little and big endian, extra elements, quads.
verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
head = "ply\nformat {}\ncomment seed\nelement vertex 4\nproperty float x\nproperty float y\n" \
       "property float z\n{}element face 2\nproperty list uchar int vertex_indices\n{}end_header\n"
put("ply", "ascii-uv-normal.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0 1\n3 0 1 2\n")
put("ply", "ascii-quad-extra.ply",
    "ply\nformat ascii 1.0\nobj_info x\nelement vertex 4\nproperty double x\nproperty double y\n"
    "property double z\nproperty list uchar float extra\nelement face 1\nproperty uchar flags\n"
    "property list ushort uint vertex_index\nelement edge 1\nproperty int a\nproperty int b\n"
    "end_header\n0 0 0 0\n1 0 0 1 7\n1 1 0 0\n0 1 0 0\n0 4 0 1 2 3\n0 1\n")
for fmt, endian in (("binary_little_endian 1.0", "<"), ("binary_big_endian 1.0", ">")):
    body = b"".join(struct.pack(endian + "fff", *v) for v in verts)
    body += struct.pack(endian + "Biii", 3, 0, 1, 2) + struct.pack(endian + "Biii", 3, 0, 2, 3)
    put("ply", fmt.split()[0] + ".ply", (head.format(fmt, "", "")).encode() + body)
    body = b"".join(struct.pack(endian + "hhhbB", *v, -1, 2) for v in verts)
    body += struct.pack(endian + "HIIII", 4, 0, 1, 2, 3) + struct.pack(endian + "HIII", 3, 0, 1, 2)
    put("ply", fmt.split()[0] + "-types.ply",
        ("ply\nformat " + fmt + "\nelement vertex 4\nproperty int16 x\nproperty int16 y\n"
         "property int16 z\nproperty int8 s\nproperty uint8 t\nelement face 2\n"
         "property list uint16 uint32 vertex_indices\nend_header\n").encode() + body)

# OBJ: positions only, uvs and normals, negative indices, ignored statements.
put("obj", "quad-attributes.obj",
    "# seed\nmtllib a.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvt 1 0\n"
    "vt 1 1\nvt 0 1\nvn 0 0 1\ng g1\nusemtl m\ns off\nf 1/1/1 2/2/1 3/3/1 4/4/1\n")
put("obj", "negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nvn 0 0 1\nf 1//1 2//1 3//1\r\n"
    "l 1 2\np 1\nvp 0.5\n")
# OBJ polygons: concave (ear clipping), with a hole cut open, not planar, crossing, no area.
put("obj", "polygons.obj",
    "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 4 5 6 1 2 3\n"
    "v 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 3 0\nv 3 3 0\nv 3 1 0\nf 1 7 8 9 1 4 10 11 12 4\n"
    "v 1 1 0.3\nf 1 2 13 6\nf 1 8 2 10\nf 1 4 8 4\n")

# 2D laboratory text.
for f in ("scenes/lab2d/lecture.txt", "scenes/lab2d/objects.txt"):
    copy("scene2d", f)
put("scene2d", "small.txt", "# two segments, a square and a ray\n0 0 1 0\n"
    "0 1 1 2 # comment\r\npoly 3 3 4 3 4 4 3 4\nray -1 0.5 1 0\n")

# PFM: colour and grey, both byte orders.
def pfm(magic, w, h, scale, values, endian):
    return f"{magic}\n{w} {h}\n{scale}\n".encode() + struct.pack(endian + f"{len(values)}f", *values)
put("pfm", "colour-le.pfm", pfm("PF", 2, 2, -1.0, [0.5] * 12, "<"))
put("pfm", "colour-be.pfm", pfm("PF", 2, 1, 1.0, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0], ">"))
put("pfm", "grey-le.pfm", pfm("Pf", 3, 1, -2.0, [0.1, 0.2, 0.3], "<"))

# PNG: each colour type, bit depths 1 to 16, a palette with tRNS, interlacing.
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
def png(w, h, depth, ctype, rows, extra=b"", interlace=0):
    ihdr = struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0, interlace)
    raw = b"".join(b"\x00" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
put("png", "rgb8.png", png(2, 2, 8, 2, [bytes([255, 0, 0, 0, 255, 0]), bytes([0, 0, 255, 9, 9, 9])],
                           chunk(b"sRGB", b"\x00")))
put("png", "grey1.png", png(8, 1, 1, 0, [b"\xa5"]))
put("png", "palette.png", png(2, 1, 8, 3, [b"\x00\x01"],
                              chunk(b"PLTE", b"\xff\x00\x00\x00\xff\x00") + chunk(b"tRNS", b"\x80")))
put("png", "rgba16.png", png(1, 1, 16, 6, [b"\x12\x34\x56\x78\x9a\xbc\xde\xf0"]))
put("png", "greyalpha-interlaced.png", png(3, 3, 8, 4, [b"\x10\x20" * 3] * 3, interlace=1))

# JSON scenes: the repository's small scenes and an inline mesh.
for f in ("scenes/antialiasing.json", "scenes/zone-plate.json", "scenes/caustic.json",
          "scenes/environment.json", "scenes/motion-blur.json", "scenes/glossy.json",
          "tests/data/scenes/file_meshes.json"):
    copy("scene_json", f)
put("scene_json", "inline-mesh.json",
    '{"camera": {"type": "pinhole", "position": [0, 0, -5], "look_at": [0, 0, 0]},'
    ' "render": {"resolution": [4, 4], "spp": 1, "max_depth": 3, "seed": 7, "integrator": "path",'
    ' "accel": "grid", "sampler": "sobol", "filter": "gaussian", "background": [0.1, 0.1, 0.1]},'
    ' "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},'
    ' "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 1},'
    ' {"type": "environment", "map": "sky.pfm"}],'
    ' "shapes": [{"type": "mesh", "positions": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2],'
    ' "material": "m", "transform": [{"rotate": {"axis": [0, 1, 0], "angle": 30}},'
    ' {"scale": 2}, {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}],'
    ' "transform_end": [{"translate": [0, 1, 0]}]},'
    ' {"type": "quad", "origin": [0, 0, 0], "u": [1, 0, 0], "v": [0, 0, 1], "material": "m",'
    ' "emission": [1, 1, 1], "two_sided": true},'
    ' {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "name": "ball"}]}')
