#pragma once
/// Wavefront OBJ reader: v, vt, vn and f statements into an indexed TriangleMesh.
///
/// - Faces: `v`, `v/vt`, `v//vn`, `v/vt/vn`; positive (1-based) and negative (relative to the end
///   of the list so far) indices; polygons are fan-triangulated (0,1,2), (0,2,3), ... and the
///   triangle order is the face order, so it is the primitive id.
/// - Attributes are per vertex: each distinct (v, vt, vn) triple becomes one mesh vertex. If any
///   face corner lacks a uv (normal), uvs (normals) are dropped for the whole mesh and the triple
///   is deduplicated without them. Without uvs and normals, positions are kept as in the file.
/// - UVs are stored as written (v is not flipped); a `vt` with one value gets v = 0.
/// - Accepted and ignored: comments, blank lines, o, g, s, usemtl, mtllib, l, p, vp; extra numbers
///   on v/vt/vn lines (w, vertex colours). Any other statement is an error, as are bad or
///   non-finite numbers, index 0, out-of-range indices and faces with fewer than 3 vertices; the
///   InputError names the line. Indices must refer to vertices defined earlier in the file.
/// - Degenerate triangles (repeated index, zero area) are kept.
#include <string>
#include <string_view>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// Reads the OBJ file at `path`; throws InputError ("path:line N: problem") on malformed input.
TriangleMesh read_obj(const std::string& path);

/// Parses OBJ text held in memory; `name` stands for the file in error messages.
TriangleMesh parse_obj(std::string_view text, const std::string& name);

}  // namespace penumbra
