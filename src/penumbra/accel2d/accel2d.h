#pragma once
/// The interface of the 2D laboratory's structures: build over a scene, shoot a ray (optionally
/// recording the traversal path), statistics, and a drawing of the partition.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/accel2d/scene2d.h"
#include "penumbra/accel2d/trace_log.h"

namespace penumbra::lab2d {

/// The first shape a ray meets.
struct Hit2 {
  double t = INFINITY;     ///< ray parameter of the hit point
  uint32_t id = kNoShape;  ///< index of the shape in the scene
  /// True when the ray hit something.
  bool hit() const { return id != kNoShape; }
};

/// Size and shape of a built structure.
struct Stats2D {
  size_t nodes = 0;      ///< internal nodes and leaves (or grid cells)
  size_t leaves = 0;     ///< leaves (or cells)
  size_t depth = 0;      ///< longest root-to-leaf path in edges
  size_t fragments = 0;  ///< stored references: fragments (BSP) or shape references
  double build_ms = 0;   ///< wall time of build()
  std::vector<std::pair<std::string, double>> extra;  ///< structure-specific figures
};

/// What the SVG shows: each splitting line clipped to its cell (with its label), the leaves' cells
/// (with their labels), all within `frame`.
struct Drawing2D {
  /// A splitting line clipped to its cell.
  struct Line {
    Segment2 s;
    std::string label;
  };
  /// A leaf's cell.
  struct Cell {
    std::vector<Vec2d> poly;
    std::string label;
  };
  Box2d frame;
  std::vector<Line> lines;
  std::vector<Cell> cells;
};

/// A 2D ray-shooting structure. One virtual call per ray; nothing virtual below it.
class Accel2D {
 public:
  virtual ~Accel2D() = default;
  /// The name and parameters, e.g. "bsp:order=random,seed=1".
  virtual std::string name() const = 0;
  /// Builds over the scene's shapes (copied); throws Error when the structure cannot take them.
  virtual void build(const Scene2D& scene) = 0;
  /// The first shape hit on [tmin, tmax]; with `trace`, also the nodes entered and returned to.
  virtual Hit2 shoot(const Ray2& ray, TraceLog* trace = nullptr) const = 0;
  /// Size and build time.
  virtual Stats2D stats() const = 0;
  /// The partition drawn inside `frame` (cells are clipped to it).
  virtual Drawing2D draw(const Box2d& frame) const = 0;
};

}  // namespace penumbra::lab2d
