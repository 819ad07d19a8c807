"""Image regions that lie inside one surface each, their checks and their mean radiance.

A region is a pixel rectangle [x0, y0, x1, y1) of an image of the regions file's "resolution"
((0, 0) the top-left corner), scaled to the resolution of the image it is applied to. Each names
the shape and one triangle of the surface it must lie on; `validate` checks this on penumbra's
first-hit renders (raycast:mode=albedo and mode=normal): every pixel of the region must show that
shape's albedo and that triangle's normal, which fails for a rectangle that touches an edge or
another surface.
"""
import json
import math

import numpy as np


def load(path):
    """The regions of a regions file: dicts with name, rect (as fractions), shape, triangle."""
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    w, h = data["resolution"]
    out = []
    for r in data["regions"]:
        x0, y0, x1, y1 = r["rect"]
        out.append({**r, "rect": (x0 / w, y0 / h, x1 / w, y1 / h)})
    return out


def pixel_rect(region, width, height):
    """(x0, y0, x1, y1) in whole pixels of a width x height image, rounded inwards."""
    x0, y0, x1, y1 = region["rect"]
    return (int(math.ceil(x0 * width)), int(math.ceil(y0 * height)),
            int(math.floor(x1 * width)), int(math.floor(y1 * height)))


def pixels(image, region):
    """The region's pixels, shape (rows, columns, 3)."""
    x0, y0, x1, y1 = pixel_rect(region, image.shape[1], image.shape[0])
    return image[y0:y1, x0:x1, :]


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


def expected_surface(scene, region):
    """(albedo, unit normal) of the region's shape and triangle, in penumbra's world space."""
    shapes = {s.get("name"): s for s in scene["shapes"]}
    shape = shapes[region["shape"]]
    albedo = scene["materials"][shape["material"]]["albedo"]
    p = np.asarray(shape["positions"], dtype=np.float64)
    i, j, k = shape["indices"][region["triangle"]]
    return np.asarray(albedo, dtype=np.float64), _unit(np.cross(p[j] - p[i], p[k] - p[i]))


def validate(regions, scene, albedo_image, normal_image, tolerance=2e-3):
    """Problems found (empty when every region lies inside its surface)."""
    problems = []
    for r in regions:
        albedo, normal = expected_surface(scene, r)
        a = pixels(albedo_image, r).reshape(-1, 3)
        n = pixels(normal_image, r).reshape(-1, 3) * 2.0 - 1.0  # mode=normal shows (n + 1) / 2
        if a.shape[0] < 16:
            problems.append(f"{r['name']}: only {a.shape[0]} pixels at this resolution")
            continue
        da = np.abs(a - albedo).max()
        # Signed: the floor and the ceiling differ only in the normal's sign.
        cos = (n @ normal) / np.maximum(np.linalg.norm(n, axis=1), 1e-12)
        if da > tolerance:
            problems.append(f"{r['name']}: albedo differs from {r['shape']}'s by up to {da:.4f}")
        if cos.min() < 1 - tolerance:
            problems.append(f"{r['name']}: normal departs from triangle {r['triangle']} of "
                            f"{r['shape']} (min cos {cos.min():.4f})")
    return problems


def mean_and_error(image, region):
    """Per-channel mean and its standard error from one image.

    The noise variance is estimated from differences of horizontally adjacent pixels,
    var = mean((x[i+1] - x[i])^2) / 2, which cancels the smooth shading gradient across the
    region that the plain pixel variance would count as noise (pixels are independent estimates
    in both renderers, so the error of the mean is sigma / sqrt(n)).
    """
    px = pixels(image, region).astype(np.float64)
    n = px.shape[0] * px.shape[1]
    d = px[:, 1:, :] - px[:, :-1, :]
    sigma2 = (d * d).reshape(-1, 3).mean(axis=0) / 2.0
    return px.reshape(-1, 3).mean(axis=0), np.sqrt(sigma2 / n)


MIN_SEEDS_FOR_SPREAD = 5


def mean_and_error_over_seeds(images, region):
    """Per-channel mean over renders with different seeds and its standard error.

    From MIN_SEEDS_FOR_SPREAD renders on, the error comes from the spread of their region means;
    with fewer, whose spread is itself too uncertain (one degree of freedom for two), from the
    adjacent-pixel differences of their average image.
    """
    if len(images) < MIN_SEEDS_FOR_SPREAD:
        return mean_and_error(np.mean(np.asarray(images, dtype=np.float64), axis=0), region)
    means = np.array([pixels(im, region).reshape(-1, 3).mean(axis=0) for im in images])
    return means.mean(axis=0), means.std(axis=0, ddof=1) / math.sqrt(len(images))


def outline(image8, regions):
    """A copy of an 8-bit image with each region's border drawn in yellow."""
    out = image8.copy()
    h, w = out.shape[:2]
    for r in regions:
        x0, y0, x1, y1 = pixel_rect(r, w, h)
        out[y0, x0:x1] = out[y1 - 1, x0:x1] = (255, 255, 0)
        out[y0:y1, x0] = out[y0:y1, x1 - 1] = (255, 255, 0)
    return out
