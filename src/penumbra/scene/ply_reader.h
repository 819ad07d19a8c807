#pragma once
/// Stanford PLY reader: ascii 1.0, binary_little_endian 1.0 and binary_big_endian 1.0.
///
/// - Element `vertex`: x, y, z required (any scalar type); nx, ny, nz and u, v (or s, t,
///   texture_u, texture_v, texture_s, texture_t) kept when all of a group are present. Other
///   properties, including lists, are skipped.
/// - Element `face`: the list `vertex_indices` (or `vertex_index`) with integer count and index
///   types; polygons are triangulated as the OBJ reader's (geometry/polygon_triangulator.h: the
///   fan (0,1,2), (0,2,3), ... for convex ones, ear clipping for concave ones, with warnings for
///   non-planar, self-intersecting and zero-area polygons), in file order, which is the primitive
///   id. Other face properties and other elements (edge, material, ...) are skipped.
/// - Scalar types: char/int8, uchar/uint8, short/int16, ushort/uint16, int/int32, uint/uint32,
///   float/float32, double/float64.
/// - Errors are InputError: header problems name the header line ("line N"), data problems the
///   byte offset ("byte N", binary) or the line (ascii). Element counts are checked against the
///   bytes left in the file before anything is allocated, so a lying header fails fast.
/// - Degenerate triangles (repeated index, zero area) are kept; faces of fewer than 3 vertices,
///   out-of-range indices and non-finite vertex attributes are errors. A file without a vertex
///   element with x, y, z, or without a face element, is an error (point clouds are not meshes).
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// Reads the PLY file at `path`; throws InputError ("path:PLACE: problem") on malformed input.
/// Warnings about polygons ("path:line N: ..." or "path:byte N: ...", at most 10 listed) are
/// appended to `warnings` when given.
TriangleMesh read_ply(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Parses a PLY file held in memory; `name` stands for the file in messages.
TriangleMesh parse_ply(std::string_view data, const std::string& name,
                       std::vector<std::string>* warnings = nullptr);

}  // namespace penumbra
