#include "penumbra/scene/ply_reader.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "penumbra/core/error.h"
#include "penumbra/core/text_escape.h"
#include "penumbra/geometry/polygon_triangulator.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/mesh_warnings.h"
#include "penumbra/scene/ply_header.h"

namespace penumbra {
namespace {

using namespace ply;

/// A `T` stored at `p`, byte-swapped when the file's byte order is not the machine's.
template <class T>
T load(const unsigned char* p, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

/// Where an error happened in the data: the element and item being read.
std::string item_context(const PlyElement* e, uint64_t item) {
  return e ? " (element '" + e->name + "', item " + std::to_string(item) + ")" : "";
}

/// Reads binary values with bounds checks; places are byte offsets from the start of the file.
class BinaryCursor {
 public:
  static constexpr const char* kPlaceKind = "byte";
  BinaryCursor(std::string_view data, size_t offset, bool swap, const std::string& name)
      : begin_(reinterpret_cast<const unsigned char*>(data.data())),
        p_(begin_ + offset),
        end_(begin_ + data.size()),
        swap_(swap),
        name_(name) {}

  size_t mark() const { return static_cast<size_t>(p_ - begin_); }
  void set_item(const PlyElement& e, uint64_t item) {
    element_ = &e;
    item_ = item;
  }
  [[noreturn]] void fail(size_t mark, const std::string& problem) const {
    throw InputError(name_, "byte " + std::to_string(mark),
                     problem + item_context(element_, item_));
  }

  double real(PlyType t) {
    const unsigned char* p = take(type_size(t));
    switch (t) {
      case PlyType::kFloat32:
        return load<float>(p, swap_);
      case PlyType::kFloat64:
        return load<double>(p, swap_);
      default:
        return static_cast<double>(decode_integer(p, t));
    }
  }
  int64_t integer(PlyType t) { return decode_integer(take(type_size(t)), t); }
  void skip(PlyType t) { take(type_size(t)); }
  int64_t count(PlyType t) {
    const size_t at = mark();
    const int64_t n = integer(t);
    if (n < 0) fail(at, "negative list count " + std::to_string(n));
    return n;
  }
  void skip_list(const PlyProperty& p) {
    const uint64_t n = static_cast<uint64_t>(count(p.count_type));
    if (n > static_cast<uint64_t>(end_ - p_) / type_size(p.type)) fail(mark(), "truncated list");
    p_ += n * type_size(p.type);
  }
  /// Bytes not yet read.
  size_t left() const { return static_cast<size_t>(end_ - p_); }
  /// Fails if bytes follow the last element.
  void finish() {
    element_ = nullptr;
    if (p_ != end_) {
      fail(mark(), std::to_string(left()) + " bytes of trailing data after the last element");
    }
  }

 private:
  const unsigned char* take(size_t n) {
    if (static_cast<size_t>(end_ - p_) < n) fail(mark(), "unexpected end of file");
    const unsigned char* p = p_;
    p_ += n;
    return p;
  }
  int64_t decode_integer(const unsigned char* p, PlyType t) const {
    switch (t) {
      case PlyType::kInt8:
        return load<int8_t>(p, swap_);
      case PlyType::kUint8:
        return load<uint8_t>(p, swap_);
      case PlyType::kInt16:
        return load<int16_t>(p, swap_);
      case PlyType::kUint16:
        return load<uint16_t>(p, swap_);
      case PlyType::kInt32:
        return load<int32_t>(p, swap_);
      case PlyType::kUint32:
        return load<uint32_t>(p, swap_);
      default:
        fail(static_cast<size_t>(p - begin_), "expected an integer type");
    }
  }

  const unsigned char* begin_;
  const unsigned char* p_;
  const unsigned char* end_;
  bool swap_;
  const std::string& name_;
  const PlyElement* element_ = nullptr;
  uint64_t item_ = 0;
};

/// Parses a whole token as a number of type T; overflow gives inf, underflow 0.
template <class T>
bool parse_number(std::string_view token, T& out) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin < end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, out);
  if (ptr != end || begin == end) return false;
  if constexpr (std::is_floating_point_v<T>) {
    if (ec == std::errc::result_out_of_range) {
      out = static_cast<T>(std::strtod(std::string(begin, end).c_str(), nullptr));  // saturate
      return true;
    }
  }
  return ec == std::errc();
}

/// Reads whitespace-separated ascii values; places are line numbers.
class AsciiCursor {
 public:
  static constexpr const char* kPlaceKind = "line";
  AsciiCursor(std::string_view data, size_t offset, size_t line, const std::string& name)
      : p_(data.data() + offset), end_(data.data() + data.size()), line_(line), name_(name) {}

  size_t mark() {
    skip_space();
    return line_;
  }
  void set_item(const PlyElement& e, uint64_t item) {
    element_ = &e;
    item_ = item;
  }
  [[noreturn]] void fail(size_t line, const std::string& problem) const {
    throw InputError(name_, "line " + std::to_string(line),
                     problem + item_context(element_, item_));
  }

  double real(PlyType t) {
    const std::string_view token = next();
    if (is_integer(t)) return static_cast<double>(to_integer(token, t));
    if (t == PlyType::kFloat32) {
      float value = 0;
      if (parse_number(token, value)) return value;
    } else {
      double value = 0;
      if (parse_number(token, value)) return value;
    }
    fail(line_, "expected a number, found '" + shorten(token) + "'");
  }
  int64_t integer(PlyType t) { return to_integer(next(), t); }
  void skip(PlyType) { next(); }
  int64_t count(PlyType t) {
    const std::string_view token = next();
    int64_t n = 0;
    if (parse_number(token, n) && n < 0) fail(line_, "negative list count " + std::to_string(n));
    return to_integer(token, t);
  }
  void skip_list(const PlyProperty& p) {
    for (int64_t i = count(p.count_type); i > 0; --i) next();
  }
  /// Bytes not yet read.
  size_t left() const { return static_cast<size_t>(end_ - p_); }
  /// Fails if anything but whitespace follows the last element.
  void finish() {
    element_ = nullptr;
    skip_space();
    if (p_ != end_) {
      fail(line_, "trailing data after the last element: '" + shorten(next()) + "'");
    }
  }

 private:
  void skip_space() {
    for (; p_ < end_ && is_space(*p_); ++p_) line_ += *p_ == '\n';
  }
  std::string_view next() {
    skip_space();
    if (p_ == end_) fail(line_, "unexpected end of file");
    const char* start = p_;
    while (p_ < end_ && !is_space(*p_)) ++p_;
    return {start, static_cast<size_t>(p_ - start)};
  }
  int64_t to_integer(std::string_view token, PlyType t) const {
    int64_t value = 0;
    if (!parse_number(token, value)) {
      fail(line_, "expected an integer, found '" + shorten(token) + "'");
    }
    if (!fits(value, t)) fail(line_, shorten(token) + " is out of range for " + type_name(t));
    return value;
  }
  static std::string shorten(std::string_view token) { return escape_for_message(token, 40); }

  const char* p_;
  const char* end_;
  size_t line_;
  const std::string& name_;
  const PlyElement* element_ = nullptr;
  uint64_t item_ = 0;
};

template <class Cursor>
void read_vertices(Cursor& c, const PlyHeader& h, TriangleMesh& mesh) {
  const PlyElement& e = h.elements[h.vertex];
  mesh.positions.resize(e.count);
  if (h.has_normals) mesh.normals.resize(e.count);
  if (h.has_uvs) mesh.uvs.resize(e.count);
  double v[kIndices] = {};
  for (uint64_t i = 0; i < e.count; ++i) {
    c.set_item(e, i);
    const size_t at = c.mark();
    for (const PlyProperty& p : e.properties) {
      if (p.is_list) {
        c.skip_list(p);
      } else if (p.slot != kSkip) {
        v[p.slot] = c.real(p.type);
      } else {
        c.skip(p.type);
      }
    }
    // Narrowing to float may overflow to inf, which the finiteness checks catch.
    mesh.positions[i] = Vec3(float(v[kX]), float(v[kY]), float(v[kZ]));
    if (!is_finite(mesh.positions[i])) c.fail(at, "non-finite vertex position");
    if (h.has_normals) {
      mesh.normals[i] = Vec3(float(v[kNx]), float(v[kNy]), float(v[kNz]));
      if (!is_finite(mesh.normals[i])) c.fail(at, "non-finite vertex normal");
    }
    if (h.has_uvs) {
      mesh.uvs[i] = Vec2(float(v[kU]), float(v[kV]));
      if (!std::isfinite(mesh.uvs[i].x) || !std::isfinite(mesh.uvs[i].y)) {
        c.fail(at, "non-finite vertex uv");
      }
    }
  }
}

/// Reads one vertex index and checks it against the vertex count.
template <class Cursor>
uint32_t read_index(Cursor& c, PlyType t, uint64_t vertex_count) {
  const size_t at = c.mark();
  const int64_t index = c.integer(t);
  if (index < 0 || static_cast<uint64_t>(index) >= vertex_count) {
    c.fail(at, "vertex index " + std::to_string(index) + " out of range (" +
                   std::to_string(vertex_count) + " vertices)");
  }
  return static_cast<uint32_t>(index);
}

/// Triangulates polygons as they are read (the OBJ reader's PolygonTriangulator: the fan for
/// convex ones, ear clipping for the others), with the warnings of what it finds. Polygons read
/// before the vertices (a face element first) get the fan at first and are triangulated again
/// when the vertices are known (finish()).
class FaceTriangulator {
 public:
  FaceTriangulator(TriangleMesh& mesh, bool vertices_known, MeshWarnings& warnings)
      : mesh_(mesh), vertices_known_(vertices_known), warnings_(warnings) {}

  /// Appends the triangles of the polygon `poly` (at least 3 vertex indices) read at `place`.
  void add(const std::vector<uint32_t>& poly, const std::string& place_kind, size_t place) {
    const size_t offset = mesh_.indices.size();
    for (size_t k = 2; k < poly.size(); ++k)  // the fan (0, k - 1, k)
      mesh_.indices.insert(mesh_.indices.end(), {poly[0], poly[k - 1], poly[k]});
    if (poly.size() == 3) return;
    if (vertices_known_)
      triangulate(offset, poly.size(), place_kind, place);
    else
      pending_.push_back({offset, poly.size(), place});
  }

  /// Triangulates the polygons read before the vertices.
  void finish(const std::string& place_kind) {
    for (const Pending& p : pending_) triangulate(p.offset, p.n, place_kind, p.place);
    pending_.clear();
  }

 private:
  struct Pending {
    size_t offset, n, place;
  };

  // The polygon is read back from its fan: (v0, v1, v2), (v0, v2, v3), ...; its n - 2 triangles
  // replace the fan's in place, so the primitive ids stay in file order.
  void triangulate(size_t offset, size_t n, const std::string& place_kind, size_t place) {
    uint32_t* fan = mesh_.indices.data() + offset;
    corners_.assign({fan[0], fan[1]});
    points_.assign({mesh_.positions[fan[0]], mesh_.positions[fan[1]]});
    for (size_t t = 0; t + 2 < n; ++t) {
      corners_.push_back(fan[3 * t + 2]);
      points_.push_back(mesh_.positions[fan[3 * t + 2]]);
    }
    triangles_.clear();
    const PolygonReport report = triangulator_.triangulate(points_, triangles_);
    for (size_t i = 0; i < triangles_.size(); ++i) fan[i] = corners_[triangles_[i]];
    if (report.any()) warnings_.polygon(place_kind + " " + std::to_string(place), report, n);
  }

  TriangleMesh& mesh_;
  bool vertices_known_;
  MeshWarnings& warnings_;
  PolygonTriangulator triangulator_;
  std::vector<uint32_t> corners_, triangles_;
  std::vector<Vec3> points_;
  std::vector<Pending> pending_;
};

template <class Cursor>
void read_faces(Cursor& c, const PlyHeader& h, TriangleMesh& mesh, FaceTriangulator& faces) {
  const PlyElement& e = h.elements[h.face];
  const uint64_t vertex_count = h.elements[h.vertex].count;
  // Room for one triangle per face, bounded by the bytes left (a face has at least one index).
  mesh.indices.reserve(3 * std::min<uint64_t>(e.count, c.left()));
  std::vector<uint32_t> poly;
  for (uint64_t i = 0; i < e.count; ++i) {
    c.set_item(e, i);
    for (const PlyProperty& p : e.properties) {
      if (p.slot == kIndices) {
        const size_t at = c.mark();
        const int64_t n = c.count(p.count_type);
        if (n < 3) c.fail(at, "face with " + std::to_string(n) + " vertices (needs at least 3)");
        poly.clear();
        for (int64_t k = 0; k < n; ++k) poly.push_back(read_index(c, p.type, vertex_count));
        faces.add(poly, Cursor::kPlaceKind, at);
      } else if (p.is_list) {
        c.skip_list(p);
      } else {
        c.skip(p.type);
      }
    }
  }
}

template <class Cursor>
void read_body(Cursor& c, const PlyHeader& h, TriangleMesh& mesh, MeshWarnings& warnings) {
  FaceTriangulator faces(mesh, h.vertex < h.face, warnings);
  for (size_t k = 0; k < h.elements.size(); ++k) {
    const PlyElement& e = h.elements[k];
    if (k == h.vertex) {
      read_vertices(c, h, mesh);
    } else if (k == h.face) {
      read_faces(c, h, mesh, faces);
    } else if (!e.properties.empty()) {
      for (uint64_t i = 0; i < e.count; ++i) {
        c.set_item(e, i);
        for (const PlyProperty& p : e.properties) p.is_list ? c.skip_list(p) : c.skip(p.type);
      }
    }
  }
  c.finish();
  faces.finish(Cursor::kPlaceKind);
  warnings.finish();
}

}  // namespace

TriangleMesh read_ply(const std::string& path, std::vector<std::string>* warnings) {
  const std::string data = read_file_contents(path);
  return parse_ply(data, path, warnings);
}

TriangleMesh parse_ply(std::string_view data, const std::string& name,
                       std::vector<std::string>* warnings) {
  MeshWarnings mesh_warnings(warnings, name);
  PlyHeader header = parse_header(data, name);
  resolve_layout(header, name);
  check_sizes(header, data.size(), name);
  TriangleMesh mesh;
  if (header.format == PlyFormat::kAscii) {
    AsciiCursor cursor(data, header.body_offset, header.end_line + 1, name);
    read_body(cursor, header, mesh, mesh_warnings);
  } else {
    const bool file_big = header.format == PlyFormat::kBinaryBigEndian;
    const bool swap = file_big != (std::endian::native == std::endian::big);
    BinaryCursor cursor(data, header.body_offset, swap, name);
    read_body(cursor, header, mesh, mesh_warnings);
  }
  return mesh;
}

}  // namespace penumbra
