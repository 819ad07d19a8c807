#pragma once
/// Loop subdivision of triangle meshes (Loop 1987, "Smooth Subdivision Surfaces Based on
/// Triangles", M.S. thesis, University of Utah), with Hoppe et al.'s crease and corner rules for
/// boundaries and non-manifold edges (Hoppe, DeRose, Duchamp, Halstead, Jin, McDonald, Schweitzer,
/// Stuetzle 1994, "Piecewise Smooth Surface Reconstruction"), and, as pbrt-v4's loopsubdiv, the
/// final vertices pushed to the limit surface with limit normals from Loop's tangent masks.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// The most subdivision levels accepted (each multiplies the triangle count by 4).
constexpr int kMaxLoopLevels = 10;

/// What `loop_subdivide` made, and what it had to treat specially.
struct LoopSubdivision {
  TriangleMesh mesh;                ///< positions, limit normals (when asked for) and triangles
  size_t nonmanifold_edges = 0;     ///< control-mesh edges of more than two triangles (creases)
  size_t nonmanifold_vertices = 0;  ///< control-mesh vertices kept fixed as corners because
                                    ///< their triangles do not form one fan
};

/// Subdivides the triangles `indices` (3 per triangle) over `positions` `levels` times; with
/// `limit` the final vertices are moved to their limit positions and given limit normals, as
/// pbrt-v4 does. Rules, for a vertex of valence n:
/// - even (old) interior vertex: (1 - n beta) v + beta sum(neighbours), beta = 3/16 for n = 3,
///   else 3 / (8n) (Warren's simplification of Loop's weights, as pbrt);
/// - odd (edge) vertex of an interior edge: 3/8 (a + b) + 1/8 (c + d), c and d opposite;
/// - a boundary edge (one triangle) or a non-manifold one (more than two) is a crease: odd
///   vertex (a + b) / 2; a vertex on exactly two crease edges: 3/4 v + 1/8 (c0 + c1) with c0, c1
///   its crease neighbours; a vertex on one or more than two, or whose triangles form no single
///   fan, is a corner and stays fixed;
/// - limit: interior (1 - n g) v + g sum(neighbours), g = 1 / (n + 3 / (8 beta)); crease
///   3/5 v + 1/5 (c0 + c1); corner v. Normals: cross(S, T) of Loop's tangent masks (interior:
///   S = sum cos(2 pi j / n) p_j, T = sum sin(2 pi j / n) p_j; boundary: pbrt's masks), applied to
///   the final control points, turned to the side of the surrounding triangles' normals (so they
///   agree with the winding); the area-weighted triangle normal where no mask applies.
/// Throws Error for levels outside [0, kMaxLoopLevels], an index out of range, a triangle with a
/// repeated index, two triangles on the same three vertices, a non-finite position, or a result
/// over the memory limit (core/memory_limit.h) or 2^31 triangles.
LoopSubdivision loop_subdivide(const std::vector<Vec3>& positions,
                               const std::vector<uint32_t>& indices, int levels, bool limit = true);

}  // namespace penumbra
