#pragma once
/// The input of the 2D laboratory: segments and convex polygons read from a text file (format in
/// docs/lab2d.md) or generated, with the checks each structure needs (errors name FILE:LINE).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/geometry/segment2d.h"

namespace penumbra::lab2d {

/// Relative tolerance of every side decision: eps = kTolerance · scale (docs/lab2d.md).
constexpr double kTolerance = 1e-9;

/// Largest coordinate magnitude the text format accepts: the side tests multiply coordinate
/// differences, which must stay finite (2e150 squared is 4e300 < DBL_MAX).
constexpr double kMaxCoordinate = 1e150;

/// No shape: the id of a missed ray.
constexpr uint32_t kNoShape = 0xffffffffu;

/// One input shape: two vertices for a segment, three or more (convex, counter-clockwise) for a
/// polygon; `line` is its line in the input file (0 when generated).
struct Shape2 {
  std::vector<Vec2d> v;
  int line = 0;
  /// True for a segment.
  bool is_segment() const { return v.size() == 2; }
  /// The segment (a segment shape only).
  Segment2 segment() const { return {v[0], v[1]}; }
};

/// Segments and polygons in input order (shape k is labelled s{k+1} or O{k+1}), and an optional
/// ray given in the file.
struct Scene2D {
  std::string source;  ///< file name, or a description of the generator
  std::vector<Shape2> shapes;
  std::optional<Ray2> ray;  ///< a `ray` line of the file
  int ray_line = 0;

  /// True when every shape is a segment.
  bool all_segments() const;
  /// The box of all vertices.
  Box2d bounds() const;
  /// The largest absolute coordinate (1 for an empty scene): the unit of the tolerance.
  double scale() const;
  /// kTolerance · scale(): distances below it count as zero.
  double eps() const { return kTolerance * scale(); }
  /// "FILE:LINE" of shape k (or "SOURCE: segment k+1" for generated shapes).
  std::string place(size_t k) const;
};

/// Parses the text format; `name` names the input in errors ("NAME:LINE: problem").
Scene2D parse_scene2d(std::string_view text, const std::string& name);

/// Reads (read_input_file) and parses the file at path; throws InputError when it cannot be read.
Scene2D load_scene2d(const std::string& path);

/// Throws InputError naming both lines when two shapes meet: segments that cross, touch or overlap
/// (collinear), polygons (or a polygon and a segment) whose interiors overlap. With
/// `segments_only`, also rejects polygons. Expected O(n) for evenly spread inputs (a bucket grid).
void check_disjoint(const Scene2D& scene, bool segments_only);

/// The brute-force answer: the first shape the ray meets (smallest t, then smallest id).
double shoot_brute(const Scene2D& scene, const Ray2& ray, uint32_t& id);

}  // namespace penumbra::lab2d
