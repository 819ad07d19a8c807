"""PFM read/write and an sRGB PNG preview writer, with numpy only (no OpenEXR bindings needed).

Images are float32 arrays of shape (height, width, 3), row 0 at the TOP of the picture. PFM stores
rows bottom-up (Netpbm, Debevec); penumbra writes little-endian colour PFM ("PF", scale -1.0).
"""
import struct
import zlib

import numpy as np


def read_pfm(path):
    """A colour or grey PFM as a (height, width, 3) float32 array, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    while len(tokens) < 4:  # magic, width, height, scale: whitespace-separated
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos].decode("ascii"))
    pos += 1  # the single whitespace byte after the scale
    magic, width, height, scale = tokens[0], int(tokens[1]), int(tokens[2]), float(tokens[3])
    if magic not in ("PF", "Pf"):
        raise ValueError(f"{path}: not a PFM file (magic {magic!r})")
    channels = 3 if magic == "PF" else 1
    dtype = "<f4" if scale < 0 else ">f4"
    pixels = np.frombuffer(data, dtype=dtype, count=width * height * channels, offset=pos)
    image = pixels.reshape(height, width, channels)[::-1].astype(np.float32)
    return np.repeat(image, 3, axis=2) if channels == 1 else image


def write_pfm(path, image):
    """Writes a (height, width, 3) array as little-endian colour PFM."""
    image = np.asarray(image, dtype="<f4")
    h, w = image.shape[:2]
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode("ascii"))
        f.write(np.ascontiguousarray(image[::-1, :, :3]).tobytes())


def srgb8(image, exposure=1.0):
    """Linear radiance -> 8-bit sRGB (clamped), the preview's tone mapping."""
    x = np.clip(np.asarray(image, dtype=np.float64) * exposure, 0.0, 1.0)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (x * 255.0 + 0.5).astype(np.uint8)


def write_png(path, rgb8):
    """Writes a (height, width, 3) uint8 array as an RGB PNG (zlib only)."""
    h, w = rgb8.shape[:2]
    raw = b"".join(b"\x00" + np.ascontiguousarray(rgb8[y, :, :3]).tobytes() for y in range(h))

    def chunk(kind, payload):
        body = kind + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))
