#include "penumbra/scene/mesh_warnings.h"

#include <utility>

#include <fmt/format.h>

#include "penumbra/core/text_escape.h"

namespace penumbra {

MeshWarnings::MeshWarnings(std::vector<std::string>* out, std::string file)
    : out_(out), file_(escape_for_message(file, SIZE_MAX)) {}

void MeshWarnings::add(const std::string& place, const std::string& problem) {
  if (listing()) out_->push_back(file_ + ":" + place + ": " + problem);
  ++count_;
}

void MeshWarnings::polygon(const std::string& place, const PolygonReport& r, size_t n) {
  if (!listing()) {  // counted only: no message is built
    count_ += size_t{r.no_area} + r.non_planar() + r.crossing + (r.stuck_vertices > 0) +
              r.too_many_vertices + r.budget_spent;
    return;
  }
  for (const std::string& p : polygon_problems(r, n)) add(place, p);
}

void MeshWarnings::finish() {
  if (out_ && count_ > kMaxMeshWarnings)
    out_->push_back(fmt::format("{}: {} more warnings like these (the first {} are listed)", file_,
                                count_ - kMaxMeshWarnings, kMaxMeshWarnings));
}

std::vector<std::string> polygon_problems(const PolygonReport& r, size_t n) {
  std::vector<std::string> out;
  const std::string face = fmt::format("face of {} vertices ", n);
  if (r.no_area)
    out.push_back(fmt::format(
        "{}encloses no area (its vertices are collinear or coincide, or it winds both ways "
        "equally); kept as {} degenerate triangles",
        face, n - 2));
  if (r.non_planar())
    out.push_back(fmt::format(
        "{}is not planar (a vertex is {:.2g} of its size from its plane); triangulated anyway",
        face, r.off_plane));
  if (r.crossing) {
    const size_t e = r.crossing_edges[0], f = r.crossing_edges[1];
    out.push_back(
        fmt::format("{}intersects itself (its edges from corner {} to {} and from {} to {} cross); "
                    "triangulated anyway, its triangles may overlap",
                    face, e + 1, (e + 1) % n + 1, f + 1, (f + 1) % n + 1));
  }
  if (r.stuck_vertices > 0)
    out.push_back(fmt::format(
        "{}could not be ear-clipped to the end (it touches or crosses itself); its last {} "
        "vertices were fan-triangulated",
        face, r.stuck_vertices));
  if (r.too_many_vertices)
    out.push_back(
        fmt::format("{}is concave and has more than {} vertices, the most that are ear-clipped; "
                    "fan-triangulated, so its triangles may cover area outside it",
                    face, kMaxEarClipVertices));
  if (r.budget_spent)
    out.push_back(fmt::format(
        "{}is concave, and this file's concave faces have used up the ear-clipping budget (the "
        "work of {} faces of {} vertices); fan-triangulated, so its triangles may cover area "
        "outside it",
        face, int(kEarClipBudget / (double(kMaxEarClipVertices) * kMaxEarClipVertices)),
        kMaxEarClipVertices));
  return out;
}

}  // namespace penumbra
