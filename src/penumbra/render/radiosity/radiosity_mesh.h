#pragma once
/// The radiosity mesh: every surface of a world cut into small planar elements (patches), each
/// side of a surface its own element, with shared vertices for Gouraud display (Cohen, Wallace
/// 1993, "Radiosity and Realistic Image Synthesis", chapter 8).
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

class World;

/// One element: a planar triangle or parallelogram on one side of a world primitive.
struct RadiosityElement {
  uint32_t v[4] = {0, 0, 0, 0};  ///< vertex indices in RadiosityMesh::vertices, counter-clockwise
                                 ///< seen from the side `normal` points to (v[3] unused for
                                 ///< triangles)
  uint8_t corners = 3;           ///< 3 (triangle) or 4 (parallelogram v0, v1, v2, v3 with
                                 ///< v2 = v1 + v3 - v0)
  Vec3 centroid;
  Vec3 normal;  ///< unit normal of the side this element is (it reflects and emits into the
                ///< half-space it points to)
  float area = 0;
  Rgb rho;                     ///< diffuse reflectance in [0, 1)
  Rgb emission;                ///< emitted radiosity (W/m^2): pi times the emitted radiance
  uint32_t prim = 0;           ///< the world primitive it lies on
  uint32_t twin = UINT32_MAX;  ///< the element on the other side of the same piece of surface
};

/// The elements of a world. Element i and its twin share vertices and geometry and have opposite
/// normals. Vertices are shared between neighbouring elements of one primitive and, where the
/// positions coincide (within 1e-6 of the scene's size), between primitives and shapes too, so
/// per-vertex radiosity can be averaged for display. Elements are numbered by primitive, then
/// by piece: element 2k is the front side of piece k (the side World::area_normal points to; a
/// sphere's outside unless its transform flips it), element 2k + 1 its twin.
class RadiosityMesh {
 public:
  /// Meshes every primitive of `world` into elements no larger than about `patch_size` (world
  /// units) across: a parallelogram into an n1 x n2 grid (n = ceil(edge / patch_size)), a
  /// triangle into s^2 similar triangles (s = ceil(longest edge / patch_size)) unless it
  /// and the next triangle of its shape form a parallelogram, which is meshed as one grid, a sphere into
  /// an n_lon x n_lat longitude x latitude grid (n_lon = max(8, ceil(2 pi r / patch_size)),
  /// n_lat = max(4, ceil(pi r / patch_size))) of planar chord triangles with vertices on the
  /// sphere: one per cell in the two polar bands, two per cell elsewhere (a cell's four corners
  /// form an isosceles trapezoid, not a parallelogram, so it is cut along its diagonal from
  /// (ring l, meridian k) to (l + 1, k + 1); the element's area is the chord triangle's, a
  /// little less than the sphere's). Each piece gives two elements (both sides). Reflectance is the
  /// material's albedo(); a material that is not purely diffuse is treated as diffuse with its
  /// albedo, and its shape is named once in `warnings` (when not null). Emission comes from
  /// World::shape_emission (front side only unless the shape emits on both sides). Moving
  /// primitives are meshed at time 0. Throws Error when the mesh would exceed `max_elements`.
  static RadiosityMesh build(const World& world, float patch_size, size_t max_elements,
                             std::vector<std::string>* warnings = nullptr);

  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<RadiosityElement>& elements() const { return elements_; }
  size_t size() const { return elements_.size(); }

  /// The element on primitive `prim` containing the world point p (a hit on that primitive),
  /// on the side facing the unit direction `towards` (e.g. the direction back to the camera);
  /// UINT32_MAX if the primitive was not meshed. The cell comes from p's parameters on the
  /// primitive (clamped to it): (u, v) along a parallelogram's edges, barycentrics on a
  /// triangle, (theta, phi) on a sphere, whose cell is then split by the plane through the
  /// centre and the cut diagonal (so a sphere point belongs to the triangle it projects to
  /// radially, up to the difference between a chord and the latitude circle at the cell's top
  /// and bottom edges).
  uint32_t locate(uint32_t prim, Vec3 p, Vec3 towards) const;
  /// Interpolation weights of the corners of element e at the point p on it (barycentric for a
  /// triangle, bilinear for a parallelogram; they sum to 1), for Gouraud shading.
  void corner_weights(uint32_t e, Vec3 p, float w[4]) const;

  /// Adaptive subdivision: splits each piece whose front element is listed (even indices, each
  /// once; the twin goes with it) into four from its edge midpoints, a parallelogram into four
  /// parallelograms, a triangle into three corner triangles and the inverted middle one. Edge
  /// midpoints are shared with neighbours split in this or an earlier call, so Gouraud corners
  /// average across them (an unsplit neighbour leaves a T-vertex). Elements are renumbered depth
  /// first in the order of the original pieces, children in place of their parent, so that a
  /// mesh built the same way and split by the same lists is the same mesh; `locate` descends to
  /// the leaf. Throws Error for an index that is odd, out of range or repeated.
  void subdivide(const std::vector<uint32_t>& front_elements);
  /// Every subdivide call's list, in order (empty for a mesh as built).
  const std::vector<std::vector<uint32_t>>& refinements() const { return refinements_; }

 private:
  /// How one primitive was cut: its first element and grid, to find an element from a point.
  struct PrimGrid {
    uint32_t first = UINT32_MAX;  ///< first element (front-side elements come in pairs with
                                  ///< their twins)
    uint16_t n1 = 0, n2 = 0;      ///< parallelogram and sphere grids; triangles: n1 = s
    uint8_t kind = 0;             ///< the primitive's PrimKind
  };

  /// The vertex of ring `l` (0 = the +z pole, n_lat = the -z pole), meridian `k` (mod n_lon) of
  /// sphere primitive `prim`'s grid (build and locate compute it the same way).
  Vec3 sphere_vertex(uint32_t prim, int l, int k) const;

  std::vector<Vec3> vertices_;
  std::vector<RadiosityElement> elements_;
  std::vector<PrimGrid> prims_;
  // Filled by build: what locate needs (the world's primitives are not kept).
  std::vector<Vec3> prim_frame_;  ///< per primitive: origin, axis 1, axis 2 (3 entries each);
                                  ///< a sphere: centre, (radius, 0, 0), unused

  /// The subdivision tree, filled by the first subdivide: piece k < base_pieces_ is piece k of
  /// the mesh as built (front element 2k then); split pieces have 4 consecutive children.
  struct Piece {
    Vec3 o, e1, e2;  ///< the front element's corner v0 and edges to v1 and to its last corner
    uint32_t child = UINT32_MAX;
    uint32_t element = 0;  ///< front element of a leaf
    uint8_t corners = 3;
  };
  /// The leaf of the tree under piece `piece` containing p.
  uint32_t descend(uint32_t piece, Vec3 p) const;
  std::vector<Piece> pieces_;
  std::vector<uint32_t> element_piece_;  ///< per front element / 2: its leaf piece
  uint32_t base_pieces_ = 0;
  std::unordered_map<uint64_t, uint32_t> midpoint_;  ///< edge (vertex pair) -> midpoint vertex
  std::vector<std::vector<uint32_t>> refinements_;
};

}  // namespace penumbra
