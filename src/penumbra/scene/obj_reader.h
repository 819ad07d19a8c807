#pragma once
/// Wavefront OBJ reader: v, vt, vn and f statements into an indexed TriangleMesh.
///
/// - Faces: `v`, `v/vt`, `v//vn`, `v/vt/vn`; positive (1-based) and negative (relative to the end
///   of the list so far) indices. A face of n vertices gives n - 2 triangles with its winding, in
///   face order (so the order is the primitive id): convex polygons the fan (0,1,2), (0,2,3), ...,
///   concave ones ear clipping (geometry/polygon_triangulator.h).
/// - Warnings, not errors, "FILE:line N: problem", for polygons that are not planar (a vertex
///   further than 1e-3 of the polygon's size from its plane), have no area, cross themselves or
///   are too large to ear-clip (concave, more than 10,000 vertices: the fan). Each is
///   triangulated anyway. The first 10 of a file are listed, then their count.
/// - Attributes are per vertex: each distinct (v, vt, vn) triple becomes one mesh vertex. If any
///   face corner lacks a uv (normal), uvs (normals) are dropped for the whole mesh and the triple
///   is deduplicated without them. Without uvs and normals, positions are kept as in the file.
/// - UVs are stored as written (v is not flipped); a `vt` with one value gets v = 0.
/// - Accepted and ignored: comments, blank lines, o, g, s, usemtl, mtllib, l, p, vp; extra numbers
///   on v/vt/vn lines (w, vertex colours). Any other statement is an error, as are bad or
///   non-finite numbers, index 0, out-of-range indices and faces with fewer than 3 vertices; the
///   InputError names the line. Indices must refer to vertices defined earlier in the file.
/// - Degenerate triangles (repeated index, zero area) are kept, and polygons with repeated or
///   collinear vertices are triangulated, without a warning; some of their n - 2 triangles may
///   have zero area.
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// Reads the OBJ file at `path`; throws InputError ("path:line N: problem") on malformed input.
/// Warnings are appended to `warnings` when given (dropped otherwise).
TriangleMesh read_obj(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Parses OBJ text held in memory; `name` stands for the file in messages.
TriangleMesh parse_obj(std::string_view text, const std::string& name,
                       std::vector<std::string>* warnings = nullptr);

}  // namespace penumbra
