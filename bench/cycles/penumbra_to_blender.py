"""Builds a penumbra JSON scene in Blender and renders it with Cycles (run inside Blender 3.4).

    blender -b --factory-startup --python-exit-code 1 \
        --python bench/cycles/penumbra_to_blender.py -- \
        --scene scenes/cornell-box.json --output out.exr [--pfm out.pfm] [--png out.png] \
        [--spp 16] [--threads 2] [--seed 0] [--resolution 256x256] [--max-depth 64] \
        [--sampling-pattern SOBOL] [--save-blend out.blend] [--timings out.json] \
        [--launched-at EPOCH_SECONDS]

Without --output it only builds the scene (and saves it with --save-blend). The geometry is read
by scene_geometry.py (axes, units and what is converted are described there); this file maps it
onto Blender objects, Cycles shaders and render settings chosen so that Cycles estimates the same
quantity as penumbra: radiance averaged over each pixel square, no bias from clamping, denoising,
adaptive sampling, light thresholds or bounce limits. docs/cycles-comparison.md lists the choices.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Matrix

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import image_io  # noqa: E402
import scene_geometry  # noqa: E402

SCRIPT_START = time.time()


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="penumbra_to_blender.py")
    p.add_argument("--scene", required=True)
    p.add_argument("--output", help="OpenEXR (32-bit float, linear) to render to")
    p.add_argument("--pfm", help="also write the render as PFM (read back from the EXR)")
    p.add_argument("--png", help="also write an 8-bit sRGB preview")
    p.add_argument("--save-blend", help="save the built scene as a .blend file")
    p.add_argument("--timings", help="write startup, build and render times as JSON")
    p.add_argument("--launched-at", type=float, help="epoch seconds when blender was started")
    p.add_argument("--spp", type=int, default=16)
    p.add_argument("--threads", type=int, default=0, help="0: all cores (threads_mode AUTO)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--resolution", help="WxH (default: the scene's)")
    p.add_argument("--max-depth", type=int, default=64, help="Cycles total and per-type bounces")
    p.add_argument("--sampling-pattern", default="PROGRESSIVE_MULTI_JITTER",
                   choices=["PROGRESSIVE_MULTI_JITTER", "SOBOL"])
    p.add_argument("--scale", type=float, default=0.001, help="scene units -> metres")
    p.add_argument("--sphere-detail", type=int, default=64, help="rings of a tessellated sphere")
    return p.parse_args(argv)


# --- shaders ---------------------------------------------------------------------------------

def bsdf_node(nodes, record):
    """The Cycles BSDF of a penumbra material."""
    rgba = (*record["color"], 1.0)
    if record["kind"] == "diffuse":
        node = nodes.new("ShaderNodeBsdfDiffuse")  # roughness 0: Lambertian, albedo / pi
        node.inputs["Roughness"].default_value = 0.0
    elif record["kind"] == "mirror":
        node = nodes.new("ShaderNodeBsdfGlossy")  # sharp, no Fresnel: a tinted perfect mirror
        node.distribution = "SHARP"
    else:
        node = nodes.new("ShaderNodeBsdfGlass")  # sharp, exact Fresnel; tint on both lobes
        node.distribution = "SHARP"
        node.inputs["IOR"].default_value = record["ior"]
    node.inputs["Color"].default_value = rgba
    return node


def make_material(name, record, emission, two_sided):
    """A node material: the BSDF plus, for emitters, an Emission shader of strength 1.

    Strength 1 makes the radiance seen from the camera equal the colour, i.e. penumbra's
    "emission". Cycles' mesh emission is two-sided; one-sided emission (penumbra's default) is
    a Mix shader driven by Geometry > Backfacing that drops the emission on the back side.
    """
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    out.target = "CYCLES"
    shader = bsdf_node(nodes, record)
    if emission is not None:
        emit = nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*emission, 1.0)
        emit.inputs["Strength"].default_value = 1.0
        emit_out = emit.outputs[0]
        if not two_sided:
            geometry = nodes.new("ShaderNodeNewGeometry")
            mix = nodes.new("ShaderNodeMixShader")  # Fac 0: input 1 (emission); 1: nothing
            links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
            links.new(emit.outputs[0], mix.inputs[1])
            emit_out = mix.outputs[0]
        add = nodes.new("ShaderNodeAddShader")
        links.new(shader.outputs[0], add.inputs[0])
        links.new(emit_out, add.inputs[1])
        shader = add
    links.new(shader.outputs[0], out.inputs["Surface"])
    return mat


# --- objects ---------------------------------------------------------------------------------

def add_mesh(scene, record, material):
    mesh = bpy.data.meshes.new(record["name"])
    mesh.from_pydata(record["positions"], [], record["triangles"])
    mesh.validate(clean_customdata=False)
    mesh.materials.append(material)
    smooth = [record["smooth"]] * len(mesh.polygons)
    mesh.polygons.foreach_set("use_smooth", smooth)
    if record["normals"] is not None:
        mesh.use_auto_smooth = True  # Blender 3.x: custom split normals need auto smooth
        mesh.normals_split_custom_set_from_vertices(record["normals"])
    mesh.update()
    obj = bpy.data.objects.new(record["name"], mesh)
    scene.collection.objects.link(obj)
    return obj


def add_camera(scene, record, extent):
    """A perspective camera with the scene's vertical field of view (sensor fit VERTICAL)."""
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    cam.sensor_fit = "VERTICAL"
    cam.sensor_height = 24.0
    # Vertical fov -> focal length for the 24 mm sensor height: tan(vfov/2) = 12 / lens.
    cam.lens = 12.0 / math.tan(math.radians(record["vfov_deg"]) / 2.0)
    cam.shift_x = cam.shift_y = 0.0
    cam.clip_start = extent * 1e-5
    cam.clip_end = extent * 10.0
    obj = bpy.data.objects.new("camera", cam)
    r, u, f, p = record["right"], record["up"], record["forward"], record["position"]
    # Blender cameras look along local -z with local +y up and +x to the image's right.
    obj.matrix_world = Matrix(((r[0], u[0], -f[0], p[0]), (r[1], u[1], -f[1], p[1]),
                               (r[2], u[2], -f[2], p[2]), (0.0, 0.0, 0.0, 1.0)))
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def add_world(scene, background):
    world = bpy.data.worlds.new("background")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*background, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    # A black world has nothing to sample; otherwise let Cycles importance-sample it.
    world.cycles.sampling_method = "NONE" if max(background) == 0 else "AUTOMATIC"
    scene.world = world


def build(args):
    """Empties Blender and builds the scene; returns (scene, width, height)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    desc = scene_geometry.load(args.scene, args.scale, args.sphere_detail)
    width, height = desc["resolution"]
    if args.resolution:
        width, height = (int(v) for v in args.resolution.lower().split("x"))
    materials = {}
    coords = [c for m in desc["meshes"] for p in m["positions"] for c in p]
    extent = max(1e-6, max(abs(c) for c in coords + list(desc["camera"]["position"])))
    for record in desc["meshes"]:
        key = (record["material"], record["emission"], record["two_sided"])
        if key not in materials:
            name = record["material"] + ("" if record["emission"] is None else "+emission")
            materials[key] = make_material(name, desc["materials"][record["material"]],
                                           record["emission"], record["two_sided"])
        add_mesh(scene, record, materials[key])
    add_camera(scene, desc["camera"], extent)
    add_world(scene, desc["background"])
    return scene, width, height


# --- render settings -------------------------------------------------------------------------

def configure(scene, args, width, height):
    """Cycles settings for an unbiased, unfiltered, undenoised estimate of pixel-mean radiance."""
    r, c = scene.render, scene.cycles
    r.engine = "CYCLES"
    c.device = "CPU"
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.threads_mode = "FIXED" if args.threads > 0 else "AUTO"
    if args.threads > 0:
        r.threads = args.threads
    c.samples = args.spp
    c.seed, c.use_animated_seed = args.seed, False
    c.sampling_pattern = args.sampling_pattern
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0  # 0: no clamping
    c.light_sampling_threshold = 0.0  # 0: never skip a light sample (default 0.01 biases)
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = args.max_depth
    c.transmission_bounces = c.transparent_max_bounces = args.max_depth
    c.volume_bounces = 0
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0  # filter glossy: off (it biases)
    c.pixel_filter_type = "BOX"  # a 1-pixel box: the mean over the pixel square, as penumbra
    c.filter_width = 1.0
    c.use_auto_tile = False
    r.film_transparent = False
    c.film_exposure = 1.0
    r.use_compositing = r.use_sequencer = False
    r.dither_intensity = 0.0
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    s = r.image_settings
    s.file_format, s.color_mode, s.color_depth, s.exr_codec = "OPEN_EXR", "RGB", "32", "ZIP"


def read_exr(path):
    """An EXR as a (height, width, 3) float32 array, top row first, via Blender's image loader."""
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Linear"  # no transform: the file's linear values
    w, h = img.size
    px = np.empty(w * h * img.channels, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, -1)[::-1, :, :3].copy()


def main():
    args = parse_args()
    timings = {"blender": bpy.app.version_string,
               "startup_s": SCRIPT_START - args.launched_at if args.launched_at else None}
    t0 = time.perf_counter()
    scene, width, height = build(args)
    configure(scene, args, width, height)
    timings["build_s"] = time.perf_counter() - t0
    if args.save_blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save_blend))
    if args.output:
        scene.render.filepath = os.path.abspath(args.output)
        t1 = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        timings["render_call_s"] = time.perf_counter() - t1  # includes writing the EXR
        if args.pfm or args.png:
            image = read_exr(scene.render.filepath)
            if args.pfm:
                image_io.write_pfm(args.pfm, image)
            if args.png:
                image_io.write_png(args.png, image_io.srgb8(image))
    if args.timings:
        with open(args.timings, "w", encoding="utf-8") as f:
            json.dump(timings, f, indent=1)


if __name__ == "__main__":
    try:
        main()
    except scene_geometry.SceneError as e:
        print(f"penumbra_to_blender: {e}", file=sys.stderr)
        sys.exit(2)
