#include "penumbra/accel2d/grid2d.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/timer.h"

namespace penumbra::lab2d {

Grid2D::Grid2D(const ParamList& p)
    : lambda_(p.get_real("lambda", 1.0, 1e-3, 1e3)),
      max_res_(int(p.get_int("max", 4096, 1, 1 << 16))) {
  p.check_all_used();
}

std::string Grid2D::name() const {
  return fmt::format("grid:lambda={},max={}", lambda_, max_res_);
}

Box2d Grid2D::cell_box(int i, int j) const {
  return {{box_.lo.x + i * cell_.x, box_.lo.y + j * cell_.y},
          {box_.lo.x + (i + 1) * cell_.x, box_.lo.y + (j + 1) * cell_.y}};
}

void Grid2D::build(const Scene2D& scene) {
  const Timer timer;
  if (!scene.all_segments()) throw Error(scene.source + ": the grid takes segments only");
  segs_.clear();
  for (const Shape2& s : scene.shapes) segs_.push_back(s.segment());
  eps_ = scene.eps();
  // The bounding box grown by a margin, cut into about lambda · n cells of equal shape.
  box_ = scene.bounds();
  if (box_.empty()) box_ = {{0, 0}, {1, 1}};
  const double margin = 4 * eps_;
  box_.lo = box_.lo - Vec2d{margin, margin};
  box_.hi = box_.hi + Vec2d{margin, margin};
  const Vec2d ext = box_.extent();
  const double cells = std::max(1.0, lambda_ * double(segs_.size()));
  const double side = std::sqrt(ext.x * ext.y / cells);
  nx_ = std::clamp(int(std::ceil(ext.x / side)), 1, max_res_);
  ny_ = std::clamp(int(std::ceil(ext.y / side)), 1, max_res_);
  cell_ = {ext.x / nx_, ext.y / ny_};
  // Two passes: count the references per cell, then fill them (compressed rows).
  offsets_.assign(size_t(nx_) * ny_ + 1, 0);
  refs_.clear();
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> fill;
    if (pass == 1) {
      for (size_t c = 1; c < offsets_.size(); ++c) offsets_[c] += offsets_[c - 1];
      refs_.resize(offsets_.back());
      fill.assign(offsets_.begin(), offsets_.end() - 1);
    }
    for (uint32_t id = 0; id < segs_.size(); ++id) {
      const Segment2& s = segs_[id];
      auto cell_of = [&](double v, double lo, double w, int n) {
        return std::clamp(int(std::floor((v - lo) / w)), 0, n - 1);
      };
      const int i0 = cell_of(std::min(s.a.x, s.b.x) - eps_, box_.lo.x, cell_.x, nx_);
      const int i1 = cell_of(std::max(s.a.x, s.b.x) + eps_, box_.lo.x, cell_.x, nx_);
      const int j0 = cell_of(std::min(s.a.y, s.b.y) - eps_, box_.lo.y, cell_.y, ny_);
      const int j1 = cell_of(std::max(s.a.y, s.b.y) + eps_, box_.lo.y, cell_.y, ny_);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
          if (segment_overlaps_box(s, cell_box(i, j), eps_)) {
            const size_t c = size_t(j) * nx_ + i;
            if (pass == 0)
              ++offsets_[c + 1];
            else
              refs_[fill[c]++] = id;
          }
    }
  }
  build_ms_ = timer.elapsed_ms();
}

Hit2 Grid2D::shoot(const Ray2& ray, TraceLog* trace) const {
  Hit2 best;
  double t0, t1;
  if (!ray_box_interval(ray, box_, t0, t1)) return best;
  // The 2D DDA: the cell of the entry point, then the next x or y boundary, whichever is nearer.
  const Vec2d p = ray.o + ray.d * t0;
  int i = std::clamp(int(std::floor((p.x - box_.lo.x) / cell_.x)), 0, nx_ - 1);
  int j = std::clamp(int(std::floor((p.y - box_.lo.y) / cell_.y)), 0, ny_ - 1);
  const int step_i = ray.d.x > 0 ? 1 : (ray.d.x < 0 ? -1 : 0);
  const int step_j = ray.d.y > 0 ? 1 : (ray.d.y < 0 ? -1 : 0);
  auto next_t = [&](int k, int step, double lo, double w, double o, double d) {
    if (step == 0) return double(INFINITY);
    return (lo + (k + (step > 0 ? 1 : 0)) * w - o) / d;
  };
  double next_i = next_t(i, step_i, box_.lo.x, cell_.x, ray.o.x, ray.d.x);
  double next_j = next_t(j, step_j, box_.lo.y, cell_.y, ray.o.y, ray.d.y);
  const double delta_i = step_i ? cell_.x / std::abs(ray.d.x) : INFINITY;
  const double delta_j = step_j ? cell_.y / std::abs(ray.d.y) : INFINITY;
  while (true) {
    if (trace) trace->enter(0, fmt::format("c({},{})", i, j));
    const size_t c = size_t(j) * nx_ + i;
    for (uint32_t k = offsets_[c]; k < offsets_[c + 1]; ++k) {
      const uint32_t id = refs_[k];
      const double t = intersect(ray, segs_[id]);
      if (t < best.t || (t == best.t && t < INFINITY && id < best.id)) best.t = t, best.id = id;
    }
    // Segments within eps of a cell are in it, so a later cell's hits lie beyond this exit.
    const double exit = std::min({next_i, next_j, t1});
    if (best.t <= exit || exit >= t1) break;
    if (next_i < next_j) {
      i += step_i;
      next_i += delta_i;
    } else {
      j += step_j;
      next_j += delta_j;
    }
    if (i < 0 || i >= nx_ || j < 0 || j >= ny_) break;
  }
  return best;
}

Stats2D Grid2D::stats() const {
  Stats2D s;
  s.nodes = s.leaves = size_t(nx_) * ny_;
  s.fragments = refs_.size();
  s.build_ms = build_ms_;
  s.extra = {{"segments", double(segs_.size())}, {"nx", double(nx_)}, {"ny", double(ny_)}};
  return s;
}

Drawing2D Grid2D::draw(const Box2d& frame) const {
  Drawing2D d;
  d.frame = frame;
  for (int i = 1; i < nx_; ++i) {
    const double x = box_.lo.x + i * cell_.x;
    d.lines.push_back({{{x, box_.lo.y}, {x, box_.hi.y}}, ""});
  }
  for (int j = 1; j < ny_; ++j) {
    const double y = box_.lo.y + j * cell_.y;
    d.lines.push_back({{{box_.lo.x, y}, {box_.hi.x, y}}, ""});
  }
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      const Box2d b = cell_box(i, j);
      d.cells.push_back(
          {{b.lo, {b.hi.x, b.lo.y}, b.hi, {b.lo.x, b.hi.y}}, fmt::format("c({},{})", i, j)});
    }
  return d;
}

}  // namespace penumbra::lab2d
