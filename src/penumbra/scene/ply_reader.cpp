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
#include "penumbra/scene/mesh_reader.h"
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

template <class Cursor>
void read_faces(Cursor& c, const PlyHeader& h, TriangleMesh& mesh) {
  const PlyElement& e = h.elements[h.face];
  const uint64_t vertex_count = h.elements[h.vertex].count;
  // Room for one triangle per face, bounded by the bytes left (a face has at least one index).
  mesh.indices.reserve(3 * std::min<uint64_t>(e.count, c.left()));
  for (uint64_t i = 0; i < e.count; ++i) {
    c.set_item(e, i);
    for (const PlyProperty& p : e.properties) {
      if (p.slot == kIndices) {
        // Fan triangulation (0,1,2), (0,2,3), ... without storing the polygon.
        const size_t at = c.mark();
        const int64_t n = c.count(p.count_type);
        if (n < 3) c.fail(at, "face with " + std::to_string(n) + " vertices (needs at least 3)");
        const uint32_t first = read_index(c, p.type, vertex_count);
        uint32_t previous = read_index(c, p.type, vertex_count);
        for (int64_t k = 2; k < n; ++k) {
          const uint32_t current = read_index(c, p.type, vertex_count);
          mesh.indices.push_back(first);
          mesh.indices.push_back(previous);
          mesh.indices.push_back(current);
          previous = current;
        }
      } else if (p.is_list) {
        c.skip_list(p);
      } else {
        c.skip(p.type);
      }
    }
  }
}

template <class Cursor>
void read_body(Cursor& c, const PlyHeader& h, TriangleMesh& mesh) {
  for (size_t k = 0; k < h.elements.size(); ++k) {
    const PlyElement& e = h.elements[k];
    if (k == h.vertex) {
      read_vertices(c, h, mesh);
    } else if (k == h.face) {
      read_faces(c, h, mesh);
    } else if (!e.properties.empty()) {
      for (uint64_t i = 0; i < e.count; ++i) {
        c.set_item(e, i);
        for (const PlyProperty& p : e.properties) p.is_list ? c.skip_list(p) : c.skip(p.type);
      }
    }
  }
  c.finish();
}

}  // namespace

TriangleMesh read_ply(const std::string& path) {
  const std::string data = read_file_contents(path);
  return parse_ply(data, path);
}

TriangleMesh parse_ply(std::string_view data, const std::string& name) {
  PlyHeader header = parse_header(data, name);
  resolve_layout(header, name);
  check_sizes(header, data.size(), name);
  TriangleMesh mesh;
  if (header.format == PlyFormat::kAscii) {
    AsciiCursor cursor(data, header.body_offset, header.end_line + 1, name);
    read_body(cursor, header, mesh);
  } else {
    const bool file_big = header.format == PlyFormat::kBinaryBigEndian;
    const bool swap = file_big != (std::endian::native == std::endian::big);
    BinaryCursor cursor(data, header.body_offset, swap, name);
    read_body(cursor, header, mesh);
  }
  return mesh;
}

}  // namespace penumbra
