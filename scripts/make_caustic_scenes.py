#!/usr/bin/env python3
"""Writes the two bundled caustic scenes: scenes/caustic.json (a glass sphere on a diffuse floor
under a small area light) and scenes/cornell-box-caustics.json (the Cornell box of
scenes/cornell-box.json with its blocks replaced by a mirror sphere and a glass sphere, after
Jensen 1996). Run from the repository root."""
import json

def dump(path, scene):
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")

caustic = {
    "description": "A glass sphere (ior 1.5) on a diffuse floor before a diffuse wall, under a small "
                   "square area light: the sphere focuses the light into a caustic in its shadow. "
                   "Written by scripts/make_caustic_scenes.py.",
    "camera": {"type": "pinhole", "position": [0, 3.2, -6.5], "look_at": [0, 0.6, 0.5], "up": [0, 1, 0],
               "vfov": 35},
    "render": {"resolution": [320, 240], "spp": 64, "seed": 0, "integrator": "sppm",
               "sampler": "sobol", "accel": "bvh", "background": [0, 0, 0]},
    "materials": {
        "floor": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
        "wall": {"type": "diffuse", "albedo": [0.5, 0.55, 0.6]},
        "glass": {"type": "dielectric", "ior": 1.5},
        "lamp": {"type": "diffuse", "albedo": 0},
    },
    "shapes": [
        {"type": "quad", "name": "floor", "origin": [-6, 0, -8], "edge1": [0, 0, 12], "edge2": [12, 0, 0],
         "material": "floor"},
        {"type": "quad", "name": "wall", "origin": [-6, 0, 4], "edge1": [12, 0, 0], "edge2": [0, 8, 0],
         "material": "wall"},
        {"type": "sphere", "name": "glass sphere", "center": [0, 1, 0.5], "radius": 1, "material": "glass"},
        {"type": "quad", "name": "light", "origin": [-0.75, 3.5, 2.75], "edge1": [0.5, 0, 0],
         "edge2": [0, 0, 0.5], "material": "lamp", "emission": [60, 60, 60]},
    ],
}

box = json.load(open("scenes/cornell-box.json"))
box["description"] = ("The Cornell box of cornell-box.json with its blocks replaced by a mirror sphere "
                      "(back left) and a glass sphere (front right, ior 1.5), after Jensen 1996: "
                      "caustics under the glass sphere and on the walls. Written by "
                      "scripts/make_caustic_scenes.py.")
box["render"]["integrator"] = "sppm"
box["render"]["spp"] = 256
box["materials"]["mirror"] = {"type": "mirror", "reflectance": [0.95, 0.95, 0.95]}
box["materials"]["glass"] = {"type": "dielectric", "ior": 1.5}
box["shapes"] = [s for s in box["shapes"] if s.get("name") not in ("short_block", "tall_block")]
box["shapes"] += [
    {"type": "sphere", "name": "mirror sphere", "center": [390, 100, 370], "radius": 100, "material": "mirror"},
    {"type": "sphere", "name": "glass sphere", "center": [175, 100, 180], "radius": 100, "material": "glass"},
]

dump("scenes/caustic.json", caustic)
dump("scenes/cornell-box-caustics.json", box)
