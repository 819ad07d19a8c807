#!/usr/bin/env python3
"""Writes a small procedural HDR sky, scenes/maps/sky.pfm, for penumbra's "environment" light.

Pure Python (no packages). Run from anywhere: python3 scripts/make_sky_map.py [output.pfm]

The map is equirectangular in penumbra's convention (see render/light/environment_light.h):
row 0 is the zenith (+y), the bottom row the nadir, the centre column looks along -z and
u = 0.75 along +x; pixel (x, y) covers u in [x/W, (x+1)/W), theta = pi v in [pi y/H, pi (y+1)/H).

Parameters (the constants below):
- size 256 x 128 (1.4 degrees a pixel; 393 KB as 32-bit float PFM).
- sky: a gradient in elevation from a deep blue zenith to a pale hazy horizon, with a broad
  forward-scattering glow (aureole) around the sun; the zenith about a third as bright as
  the horizon.
- ground below the horizon: a warm grey-brown of albedo ~0.22 lit by the whole sky and sun
  (radiance albedo E_total / pi), darkening slightly towards the nadir, blended into the horizon
  haze over about one degree.
- sun: a disc of angular radius 2.5 degrees (larger than the real 0.27 so that it covers a few
  pixels), at elevation 35 degrees and azimuth 54 degrees from -z towards +x (u = 0.65),
  warm white (1, 0.93, 0.82) with mild limb darkening, anti-aliased by 8 x 8 sub-samples
  per pixel.
- brightness: the sun's irradiance on a horizontal plane is SUN_TO_SKY = 3 times the sky's
  (the upper hemisphere without the sun), and the total horizontal irradiance (luminance) is
  pi, so a white horizontal Lambertian surface in full sun has radiance 1 (scale it with the
  light's "radiance" parameter). The sun's radiance is then about 900.
"""
import math
import os
import struct
import sys

WIDTH, HEIGHT = 256, 128
SUN_ELEVATION = math.radians(35.0)
SUN_U = 0.65  # azimuth 2 pi (u - 0.5) = 54 degrees from -z towards +x
SUN_RADIUS = math.radians(2.5)
SUN_COLOR = (1.0, 0.93, 0.82)
SUN_TO_SKY = 3.0  # horizontal irradiance of the sun / of the sky
TOTAL_IRRADIANCE = math.pi  # horizontal irradiance of sky + sun (luminance)
GROUND_ALBEDO = (0.27, 0.22, 0.16)  # luminance ~0.22
ZENITH = (0.05, 0.17, 0.62)
HORIZON = (0.85, 0.92, 1.05)
GLOW = (1.0, 0.85, 0.6)
SUB = 8  # sub-samples per pixel side near the sun


def luminance(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def direction(u, v):
    """Map-frame unit direction of map point (u, v)."""
    theta, phi = math.pi * v, 2 * math.pi * (u - 0.5)
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


SUN_DIR = direction(SUN_U, 0.5 - SUN_ELEVATION / math.pi)


def sky(w):
    """Sky radiance (relative units) along the unit direction w with w[1] >= 0."""
    elevation = math.asin(max(0.0, min(1.0, w[1])))
    t = math.exp(-elevation / 0.22)  # 1 at the horizon, small towards the zenith
    base = [ZENITH[k] + (HORIZON[k] - ZENITH[k]) * t for k in range(3)]
    cos_gamma = sum(a * b for a, b in zip(w, SUN_DIR))
    gamma = math.acos(max(-1.0, min(1.0, cos_gamma)))
    glow = 1.6 * math.exp(-gamma / 0.12) + 0.25 * math.exp(-gamma / 0.6)  # aureole, haze
    rayleigh = 0.75 * (1 + cos_gamma * cos_gamma)
    return [base[k] * rayleigh + GLOW[k] * glow for k in range(3)]


def sun_coverage(x, y):
    """Fraction of pixel (x, y)'s solid angle inside the sun disc, and the mean limb darkening."""
    inside, darkening = 0, 0.0
    z0, z1 = math.cos(math.pi * y / HEIGHT), math.cos(math.pi * (y + 1) / HEIGHT)
    for a in range(SUB):
        z = z0 + (a + 0.5) / SUB * (z1 - z0)  # equal-area sub-samples
        for b in range(SUB):
            phi = 2 * math.pi * ((x + (b + 0.5) / SUB) / WIDTH - 0.5)
            s = math.sqrt(max(0.0, 1 - z * z))
            w = (s * math.sin(phi), z, -s * math.cos(phi))
            gamma = math.acos(max(-1.0, min(1.0, sum(p * q for p, q in zip(w, SUN_DIR)))))
            if gamma < SUN_RADIUS:
                r = gamma / SUN_RADIUS
                inside += 1
                darkening += 1 - 0.5 * (1 - math.sqrt(1 - r * r))
    n = SUB * SUB
    return inside / n, (darkening / inside if inside else 0.0)


def pixel_solid_angle(y):
    return 2 * math.pi / WIDTH * (math.cos(math.pi * y / HEIGHT) - math.cos(math.pi * (y + 1) / HEIGHT))


def make_map():
    # The sky (upper rows) and its horizontal irradiance; the sun disc at unit radiance.
    rows, sun = [], {}
    e_sky = e_sun = 0.0
    sun_row = SUN_DIR[1]
    for y in range(HEIGHT):
        v = (y + 0.5) / HEIGHT
        row = []
        for x in range(WIDTH):
            w = direction((x + 0.5) / WIDTH, v)
            c = sky(w) if w[1] >= 0 else None
            row.append(c)
            if c is not None:
                e_sky += luminance(c) * w[1] * pixel_solid_angle(y)
            if math.acos(max(-1.0, min(1.0, sum(p * q for p, q in zip(w, SUN_DIR))))) < 3 * SUN_RADIUS:
                cover, dark = sun_coverage(x, y)
                if cover > 0:
                    sun[(x, y)] = cover * dark
                    e_sun += cover * dark * luminance(SUN_COLOR) * max(w[1], 0) * pixel_solid_angle(y)
        rows.append(row)
    # Brightness: sun = SUN_TO_SKY x sky, together TOTAL_IRRADIANCE.
    sky_scale = TOTAL_IRRADIANCE / (1 + SUN_TO_SKY) / e_sky
    sun_radiance = TOTAL_IRRADIANCE * SUN_TO_SKY / (1 + SUN_TO_SKY) / e_sun
    ground_radiance = TOTAL_IRRADIANCE / math.pi
    horizon = [c * sky_scale for c in sky((SUN_DIR[0], 0.0, SUN_DIR[2]))]
    image = []
    for y in range(HEIGHT):
        v = (y + 0.5) / HEIGHT
        out = []
        for x in range(WIDTH):
            w = direction((x + 0.5) / WIDTH, v)
            c = rows[y][x]
            if c is not None:
                c = [k * sky_scale for k in c]
            else:
                # Ground, blended into the horizon haze just below the horizon.
                depth = -w[1]
                ground = [a * ground_radiance * (0.8 + 0.2 * math.exp(-depth / 0.4)) for a in GROUND_ALBEDO]
                haze = math.exp(-depth / 0.02)
                c = [ground[k] + (horizon[k] * 0.8 - ground[k]) * haze for k in range(3)]
            if (x, y) in sun:
                f = sun[(x, y)]
                c = [c[k] * (1 - f) + f * sun_radiance * SUN_COLOR[k] for k in range(3)]
            out.append(c)
        image.append(out)
    return image, sky_scale * e_sky, sun_radiance * e_sun, sun_radiance


def write_pfm(path, image):
    """Little-endian colour PFM: rows from the bottom of the picture up."""
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (WIDTH, HEIGHT))
        for row in reversed(image):
            f.write(struct.pack("<%df" % (3 * WIDTH), *[ch for c in row for ch in c]))


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes", "maps", "sky.pfm")
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    image, e_sky, e_sun, l_sun = make_map()
    write_pfm(path, image)
    print("%s: %d x %d, horizontal irradiance sky %.3f sun %.3f, sun radiance %.0f"
          % (path, WIDTH, HEIGHT, e_sky, e_sun, l_sun))


if __name__ == "__main__":
    main()
