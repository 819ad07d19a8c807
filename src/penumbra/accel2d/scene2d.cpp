#include "penumbra/accel2d/scene2d.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/input_file.h"
#include "penumbra/core/text_escape.h"
#include "penumbra/geometry/convex_polygon2d.h"

namespace penumbra::lab2d {

bool Scene2D::all_segments() const {
  return std::all_of(shapes.begin(), shapes.end(), [](const Shape2& s) { return s.is_segment(); });
}

Box2d Scene2D::bounds() const {
  Box2d b;
  for (const Shape2& s : shapes)
    for (Vec2d p : s.v) b.extend(p);
  return b;
}

double Scene2D::scale() const {
  double m = 0;
  for (const Shape2& s : shapes)
    for (Vec2d p : s.v) m = std::max({m, std::abs(p.x), std::abs(p.y)});
  return m > 0 ? m : 1.0;
}

std::string Scene2D::place(size_t k) const {
  const int line = shapes[k].line;
  return line > 0 ? fmt::format("{}:{}", source, line) : fmt::format("{}: shape {}", source, k + 1);
}

namespace {

/// Splits a line (comment removed) into whitespace-separated words.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

/// The finite number `w` of magnitude at most kMaxCoordinate, or an InputError naming the line.
double number(std::string_view w, const std::string& name, int line) {
  double v = 0;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  if (ec != std::errc() || end != w.data() + w.size() || !std::isfinite(v))
    throw InputError(name, std::to_string(line),
                     fmt::format("'{}' is not a finite number", escape_for_message(w)));
  if (std::abs(v) > kMaxCoordinate)
    throw InputError(name, std::to_string(line),
                     fmt::format("'{}' is beyond the largest coordinate, ±{:g} (products of "
                                 "coordinates must stay finite)",
                                 escape_for_message(w), kMaxCoordinate));
  return v;
}

/// The points of words [first, end) taken as x y pairs.
std::vector<Vec2d> points(const std::vector<std::string_view>& w, size_t first,
                          const std::string& name, int line) {
  std::vector<Vec2d> out;
  for (size_t i = first; i + 1 < w.size(); i += 2)
    out.push_back({number(w[i], name, line), number(w[i + 1], name, line)});
  return out;
}

/// Checks the shapes once the scale (and so the tolerance) is known.
void check_shapes(Scene2D& scene) {
  const double eps = scene.eps();
  for (size_t k = 0; k < scene.shapes.size(); ++k) {
    Shape2& s = scene.shapes[k];
    if (s.is_segment()) {
      if (length(s.v[1] - s.v[0]) <= eps)
        throw Error(scene.place(k) + ": zero-length segment (shorter than the tolerance)");
      continue;
    }
    if (!is_convex(s.v, eps))
      throw Error(scene.place(k) + ": the polygon is not convex (or has repeated vertices)");
    if (std::abs(signed_area2(s.v)) <= eps * eps)
      throw Error(scene.place(k) + ": the polygon has zero area");
    if (signed_area2(s.v) < 0) std::reverse(s.v.begin(), s.v.end());  // counter-clockwise
  }
}

}  // namespace

Scene2D parse_scene2d(std::string_view text, const std::string& name) {
  Scene2D scene;
  scene.source = name;
  if (const auto why = describe_non_text(text)) throw InputError(name, "", *why);
  int line_no = 0;
  while (!text.empty()) {
    const size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++line_no;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    const auto w = words(line);
    if (w.empty()) continue;
    const std::string at = std::to_string(line_no);
    if (w[0] == "poly") {
      if (w.size() < 7 || (w.size() - 1) % 2 != 0)
        throw InputError(name, at,
                         "a polygon needs 'poly' and at least three x y pairs (an even count of "
                         "numbers)");
      scene.shapes.push_back({points(w, 1, name, line_no), line_no});
    } else if (w[0] == "ray") {
      if (w.size() != 5) throw InputError(name, at, "a ray is 'ray x y dx dy'");
      if (scene.ray) throw InputError(name, at, "a second ray (one per file)");
      const auto p = points(w, 1, name, line_no);
      if (p[1].x == 0 && p[1].y == 0) throw InputError(name, at, "the ray's direction is zero");
      scene.ray = Ray2{p[0], p[1]};
      scene.ray_line = line_no;
    } else {
      if (w.size() != 4)
        throw InputError(name, at,
                         fmt::format("a segment is four numbers 'x1 y1 x2 y2' (got {} words; "
                                     "polygons start with 'poly', rays with 'ray')",
                                     w.size()));
      scene.shapes.push_back({points(w, 0, name, line_no), line_no});
    }
  }
  check_shapes(scene);
  return scene;
}

Scene2D load_scene2d(const std::string& path) {
  return parse_scene2d(read_input_file(path), path);
}

void check_disjoint(const Scene2D& scene, bool segments_only) {
  const size_t n = scene.shapes.size();
  if (n == 0) return;
  if (segments_only)
    for (size_t k = 0; k < n; ++k)
      if (!scene.shapes[k].is_segment())
        throw Error(scene.place(k) +
                    ": a polygon, but this structure takes segments only (use "
                    "--structure objects for polygons)");
  // Bucket the shapes' boxes in a grid of about n cells; test the pairs sharing a bucket.
  const double eps = scene.eps();
  const Box2d box = scene.bounds();
  const Vec2d ext = box.extent();
  // An extent beyond the double range (coordinates near ±1.8e308) has no grid: one bucket.
  const bool finite = std::isfinite(ext.x) && std::isfinite(ext.y);
  const int res = finite ? std::clamp(int(std::sqrt(double(n))), 1, 1024) : 1;
  const Vec2d cell{std::max(ext.x, eps) / res, std::max(ext.y, eps) / res};
  // Clamped before the conversion: (v - lo) / w may be NaN or beyond int (a UBSan finding).
  auto index = [&](double v, double lo, double w) {
    const double t = (v - lo) / w;
    if (!(t > 0)) return 0;
    return t >= res - 1 ? res - 1 : int(t);
  };
  std::vector<std::vector<uint32_t>> buckets(size_t(res) * res);
  std::vector<uint32_t> seen(n, kNoShape);
  for (size_t k = 0; k < n; ++k) {
    Box2d b;
    for (Vec2d p : scene.shapes[k].v) b.extend(p);
    const int x0 = index(b.lo.x - eps, box.lo.x, cell.x),
              x1 = index(b.hi.x + eps, box.lo.x, cell.x);
    const int y0 = index(b.lo.y - eps, box.lo.y, cell.y),
              y1 = index(b.hi.y + eps, box.lo.y, cell.y);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        auto& bucket = buckets[size_t(y) * res + x];
        for (uint32_t j : bucket) {
          if (seen[j] == k) continue;
          seen[j] = uint32_t(k);
          const Shape2 &p = scene.shapes[j], &q = scene.shapes[k];
          if (p.is_segment() && q.is_segment()) {
            bool collinear = false;
            if (segments_meet(p.segment(), q.segment(), eps, collinear))
              throw Error(fmt::format(
                  "{}: the segment {} the segment at line {} (segments must be "
                  "disjoint)",
                  scene.place(k), collinear ? "overlaps (collinear)" : "crosses or touches",
                  p.line > 0 ? std::to_string(p.line) : scene.place(j)));
          } else if (convex_overlap(p.v, q.v, eps)) {
            throw Error(
                fmt::format("{}: the shape overlaps the shape at line {} (objects must be "
                            "disjoint)",
                            scene.place(k), p.line > 0 ? std::to_string(p.line) : scene.place(j)));
          }
        }
        bucket.push_back(uint32_t(k));
      }
  }
}

double shoot_brute(const Scene2D& scene, const Ray2& ray, uint32_t& id) {
  double best = INFINITY;
  id = kNoShape;
  for (size_t k = 0; k < scene.shapes.size(); ++k) {
    const double t = intersect_polygon(ray, scene.shapes[k].v);
    if (t < best) best = t, id = uint32_t(k);
  }
  return best;
}

}  // namespace penumbra::lab2d
