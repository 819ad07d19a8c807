#pragma once
/// The warnings of the mesh readers (OBJ, PLY): at most kMaxMeshWarnings listed per file as
/// "FILE:PLACE: problem", the others only counted (so a hostile file cannot flood stderr) and
/// summed up in one last line; and the wording of what triangulating a polygon found.
#include <cstddef>
#include <string>
#include <vector>

#include "penumbra/geometry/polygon_triangulator.h"

namespace penumbra {

/// Warnings listed per file.
inline constexpr size_t kMaxMeshWarnings = 10;

/// One reader's warnings about one file, appended to a list the caller owns (or only counted when
/// there is none).
class MeshWarnings {
 public:
  MeshWarnings(std::vector<std::string>* out, std::string file);
  /// False when nothing more is listed (no list, or kMaxMeshWarnings listed): callers then only
  /// count(), without building a message.
  bool listing() const { return out_ && count_ < kMaxMeshWarnings; }
  /// Lists "FILE:PLACE: problem" (or counts it past the limit).
  void add(const std::string& place, const std::string& problem);
  /// Counts n warnings that are not listed.
  void count(size_t n) { count_ += n; }
  /// Lists or counts every problem of a polygon of n vertices that `r` reports.
  void polygon(const std::string& place, const PolygonReport& r, size_t n);
  /// Appends "FILE: N more warnings like these (the first 10 are listed)" when some were not
  /// listed. Call once, at the end of the file.
  void finish();

 private:
  std::vector<std::string>* out_;
  std::string file_;  ///< escaped for messages
  size_t count_ = 0;
};

/// What `r` found wrong with a polygon of n vertices, one sentence each ("face of 5 vertices is
/// not planar (...); triangulated anyway").
std::vector<std::string> polygon_problems(const PolygonReport& r, size_t n);

}  // namespace penumbra
