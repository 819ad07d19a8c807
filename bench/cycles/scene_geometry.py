"""Reads a penumbra JSON scene into plain Blender-space records (no bpy: testable with python3).

Only what the Cycles comparison needs is converted; anything else is an error that names the JSON
path, never silently dropped. Converted: the pinhole camera; meshes (inline), quads, spheres
(tessellated) and simple OBJ files; diffuse, mirror and dielectric materials; emission (one- or
two-sided); the render resolution and background. Not converted: point lights, textures, PLY files,
moving shapes, thin-lens cameras, shutters.

Axes: penumbra is right-handed with +y up, Blender right-handed with +z up. The rotation by +90
degrees about x, (x, y, z) -> (x, -z, y), takes one to the other (determinant +1, so windings, front
sides and image handedness are kept); lengths are then multiplied by `scale` (millimetres -> metres
by default: radiance does not depend on it, but Cycles' defaults assume metres).
"""
import json
import math
import os


class SceneError(Exception):
    """A scene feature that the converter does not handle, with its JSON path."""


def to_blender(p, scale):
    """Penumbra point or vector (y up) -> Blender (z up), scaled."""
    return (scale * p[0], -scale * p[2], scale * p[1])


# --- small 3D and 4x4 helpers (row-major matrices acting on column vectors) -------------------

def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def mul(a, s):
    return [a[i] * s for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def transform_point(m, p):
    return [m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2] + m[i][3] for i in range(3)]


def transform_vector(m, v):
    return [m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] for i in range(3)]


def determinant3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def cofactor3(m):
    """Cofactor matrix of the linear part (det(M) times the inverse transpose), padded to 4x4."""
    def minor(i, j):
        r = [k for k in range(3) if k != i]
        c = [k for k in range(3) if k != j]
        return m[r[0]][c[0]] * m[r[1]][c[1]] - m[r[0]][c[1]] * m[r[1]][c[0]]
    out = identity()
    for i in range(3):
        for j in range(3):
            out[i][j] = (-1) ** (i + j) * minor(i, j)
    return out


def operation_matrix(op, where):
    """4x4 matrix of one transform operation (docs/scene-format.md, "Transforms")."""
    if len(op) != 1:
        raise SceneError(f"{where}: a transform operation has exactly one key")
    (kind, value), = op.items()
    m = identity()
    if kind == "translate":
        for i in range(3):
            m[i][3] = float(value[i])
    elif kind == "scale":
        s = [float(value)] * 3 if isinstance(value, (int, float)) else [float(x) for x in value]
        for i in range(3):
            m[i][i] = s[i]
    elif kind == "rotate":
        a = math.radians(float(value["angle"]))
        x, y, z = normalize([float(c) for c in value["axis"]])
        c, s, t = math.cos(a), math.sin(a), 1 - math.cos(a)
        m = [[t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
             [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
             [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0], [0, 0, 0, 1]]
    elif kind == "matrix":
        m = [[float(value[4 * i + j]) for j in range(4)] for i in range(4)]
    else:
        raise SceneError(f"{where}/{kind}: unknown transform operation")
    return m


def shape_matrix(shape, where):
    """Object-to-world matrix of a shape: its operations applied in the listed order."""
    m = identity()
    for i, op in enumerate(shape.get("transform", [])):
        m = matmul(operation_matrix(op, f"{where}/transform/{i}"), m)
    return m


# --- shapes -> triangle meshes ---------------------------------------------------------------

def sphere_mesh(center, radius, rings, segments):
    """UV sphere: positions, outward-wound triangles and radial normals."""
    positions, normals = [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            n = [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
            normals.append(n)
            positions.append(add(center, mul(n, radius)))
    tris = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * segments + j, i * segments + (j + 1) % segments
            c, d = a + segments, b + segments
            if i > 0:
                tris.append([a, c, b])      # counter-clockwise seen from outside
            if i < rings - 1:
                tris.append([b, c, d])
    return positions, tris, normals


def read_obj(path, where):
    """Vertex positions and faces (fan-triangulated) of a Wavefront OBJ file; normals ignored."""
    positions, tris = [], []
    with open(path, encoding="utf-8") as f:
        for line_no, line in enumerate(f, 1):
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                positions.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = []
                for token in parts[1:]:
                    i = int(token.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(positions) + i)
                if len(idx) < 3:
                    raise SceneError(f"{path}:{line_no}: a face needs three vertices ({where})")
                tris.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return positions, tris


def shape_triangles(shape, where, scene_dir, sphere_detail):
    """Object-space positions, triangles and optional per-vertex normals of one shape."""
    kind = shape["type"]
    if kind == "mesh":
        return ([[float(c) for c in p] for p in shape["positions"]],
                [list(t) for t in shape["indices"]], shape.get("normals"))
    if kind == "quad":
        o, e1, e2 = shape["origin"], shape["edge1"], shape["edge2"]
        return [o, add(o, e1), add(add(o, e1), e2), add(o, e2)], [[0, 1, 2], [0, 2, 3]], None
    if kind == "sphere":
        return sphere_mesh(shape["center"], float(shape["radius"]), sphere_detail,
                           2 * sphere_detail)
    if kind == "obj":
        positions, tris = read_obj(os.path.join(scene_dir, shape["file"]), where)
        return positions, tris, None
    raise SceneError(f"{where}/type: shape type '{kind}' is not converted "
                     "(mesh, quad, sphere, obj)")


# --- materials and camera --------------------------------------------------------------------

def colour(value, where):
    """An RGB triple from a colour value; textures are refused."""
    if isinstance(value, (int, float)):
        return (float(value),) * 3
    if isinstance(value, dict):
        raise SceneError(f"{where}: textures are not converted")
    return tuple(float(c) for c in value)


def material_record(name, m):
    """A plain material record: kind plus the colours Cycles needs."""
    where = f"/materials/{name}"
    kind = m.get("type")
    if kind == "diffuse":
        return {"kind": "diffuse", "color": colour(m.get("albedo", 0.5), where + "/albedo")}
    if kind == "mirror":
        return {"kind": "mirror",
                "color": colour(m.get("reflectance", 1.0), where + "/reflectance")}
    if kind == "dielectric":
        return {"kind": "dielectric", "color": colour(m.get("tint", 1.0), where + "/tint"),
                "ior": float(m.get("ior", 1.5))}
    raise SceneError(f"{where}/type: material type '{kind}' is not converted "
                     "(diffuse, mirror, dielectric)")


def camera_record(cam, scale):
    """Blender-space eye, forward and up vectors and the vertical field of view."""
    if cam.get("type") != "pinhole":
        raise SceneError("/camera/type: only pinhole cameras are converted, "
                         f"not '{cam.get('type')}'")
    if any(float(t) != 0.0 for t in cam.get("shutter", [0, 0])):
        raise SceneError("/camera/shutter: motion blur is not converted")
    eye = [float(c) for c in cam["position"]]
    forward = normalize(sub([float(c) for c in cam["look_at"]], eye))
    right = normalize(cross(forward, [float(c) for c in cam.get("up", [0, 1, 0])]))
    up = cross(right, forward)
    return {"position": to_blender(eye, scale), "forward": to_blender(forward, 1.0),
            "up": to_blender(up, 1.0), "right": to_blender(right, 1.0),
            "vfov_deg": float(cam.get("vfov", 45.0))}


def load(path, scale=0.001, sphere_detail=64):
    """The scene as Blender-space records: camera, materials, meshes, resolution, background."""
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    if scene.get("lights"):
        raise SceneError("/lights: point lights are not converted (use emissive shapes)")
    render = scene.get("render", {})
    materials = {n: material_record(n, m) for n, m in scene.get("materials", {}).items()}
    meshes = []
    for i, shape in enumerate(scene["shapes"]):
        where = f"/shapes/{i}"
        if "transform_end" in shape:
            raise SceneError(f"{where}/transform_end: moving shapes are not converted")
        m = shape_matrix(shape, where)
        positions, tris, normals = shape_triangles(shape, where, os.path.dirname(path),
                                                   sphere_detail)
        flip = determinant3(m) < 0  # a mirroring transform keeps the front side (scene-format.md)
        world_n = None
        if normals is not None:
            # Normals transform by the inverse transpose, here det(M) * M^-T (the cofactor
            # matrix) times the sign of det(M), so that no inverse is needed.
            c = cofactor3(m)
            sign = -1.0 if flip else 1.0
            world_n = [to_blender(normalize(mul(transform_vector(c, n), sign)), 1.0)
                       for n in normals]
        emission = shape.get("emission")
        e = colour(emission, where + "/emission") if emission is not None else (0.0, 0.0, 0.0)
        meshes.append({
            "name": shape.get("name", f"shape{i}"),
            "positions": [to_blender(transform_point(m, p), scale) for p in positions],
            "triangles": [[t[0], t[2], t[1]] if flip else list(t) for t in tris],
            "normals": world_n,
            "material": shape["material"],
            "emission": e if any(c > 0 for c in e) else None,
            "two_sided": bool(shape.get("two_sided", False)),
            "smooth": shape["type"] == "sphere" or normals is not None,
        })
    res = render.get("resolution", [256, 256])
    bg = render.get("background", 0.0)
    return {"camera": camera_record(scene["camera"], scale), "materials": materials,
            "meshes": meshes, "resolution": (int(res[0]), int(res[1])),
            "background": colour(bg, "/render/background"),
            "max_depth": int(render.get("max_depth", 8))}
