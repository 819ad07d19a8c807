#!/usr/bin/env python3
"""Writes scenes/cornell-box.pbrt from scenes/cornell-box.json: the same numbers in pbrt-v4's
format. `Scale -1 1 1` before `LookAt` makes pbrt's camera frame mirror, which the importer
takes as it is (docs/pbrt-import.md), so both files describe the same world and picture."""
import json
import os

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
scene = json.load(open(os.path.join(root, "scenes", "cornell-box.json")))
cam, render = scene["camera"], scene["render"]
out = ["# The Cornell box of scenes/cornell-box.json in pbrt-v4's format (written by",
       "# scripts/cornell_to_pbrt.py; do not edit by hand). It renders the same bits as the JSON",
       "# scene when both get the same max depth (pbrt's Integrator always sets one).",
       "Scale -1 1 1",
       "LookAt %s  %s  %s" % tuple(" ".join(repr(float(v)) for v in cam[k])
                                  for k in ("position", "look_at", "up")),
       'Camera "perspective" "float fov" %r' % cam["vfov"],
       'Film "rgb" "integer xresolution" %d "integer yresolution" %d'
       % tuple(render["resolution"]),
       'Sampler "paddedsobol" "integer pixelsamples" %d "integer seed" %d' % (render["spp"], render["seed"]),
       'PixelFilter "box"',
       'Integrator "path" "integer maxdepth" 64',
       "WorldBegin"]
for name, m in scene["materials"].items():
    out.append('MakeNamedMaterial "%s" "string type" "diffuse" "rgb reflectance" [%s]'
               % (name, " ".join(repr(float(v)) for v in m["albedo"])))
for s in scene["shapes"]:
    out.append("# " + s["name"])
    out.append("AttributeBegin")
    if "emission" in s:
        out.append('  AreaLightSource "diffuse" "rgb L" [%s]' % " ".join(repr(float(v)) for v in s["emission"]))
    out.append('  NamedMaterial "%s"' % s["material"])
    out.append('  Shape "trianglemesh"')
    out.append('    "point3 P" [%s]' % "  ".join(" ".join(repr(float(v)) for v in p) for p in s["positions"]))
    out.append('    "integer indices" [%s]' % "  ".join(" ".join(str(i) for i in t) for t in s["indices"]))
    out.append("AttributeEnd")
open(os.path.join(root, "scenes", "cornell-box.pbrt"), "w").write("\n".join(out) + "\n")
