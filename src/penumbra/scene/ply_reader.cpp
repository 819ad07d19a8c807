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
#include "penumbra/scene/mesh_reader.h"

namespace penumbra {
namespace {

/// Scalar types of PLY properties; the integer types come first.
enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

constexpr std::string_view kTypeNames[] = {"char", "uchar", "short", "ushort",
                                           "int",  "uint",  "float", "double"};
constexpr size_t kTypeSizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
constexpr int64_t kIntMin[] = {INT8_MIN, 0, INT16_MIN, 0, INT32_MIN, 0};
constexpr int64_t kIntMax[] = {INT8_MAX, UINT8_MAX, INT16_MAX, UINT16_MAX, INT32_MAX, UINT32_MAX};

size_t type_size(PlyType t) {
  return kTypeSizes[static_cast<int>(t)];
}
std::string type_name(PlyType t) {
  return std::string(kTypeNames[static_cast<int>(t)]);
}
bool is_integer(PlyType t) {
  return t < PlyType::kFloat32;
}

/// Whether `v` lies in the range of the type `t` (any value fits a floating-point type).
bool fits(int64_t v, PlyType t) {
  const int i = static_cast<int>(t);
  return !is_integer(t) || (v >= kIntMin[i] && v <= kIntMax[i]);
}

/// The type named `s` (both the classic and the sized spellings), if any.
std::optional<PlyType> parse_type(std::string_view s) {
  constexpr std::string_view kSized[] = {"int8",  "uint8",  "int16",   "uint16",
                                         "int32", "uint32", "float32", "float64"};
  for (int i = 0; i < 8; ++i) {
    if (s == kTypeNames[i] || s == kSized[i]) return static_cast<PlyType>(i);
  }
  return std::nullopt;
}

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

/// Where a vertex or face property goes: a vertex attribute component, the face indices, nowhere.
enum Slot : int { kSkip = -1, kX, kY, kZ, kNx, kNy, kNz, kU, kV, kIndices };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kUint8;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // lists only
  int slot = kSkip;
  size_t line = 0;  // header line, for errors
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  size_t line = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;                     // first byte after the end_header line
  size_t end_line = 0;                        // line number of end_header
  size_t vertex = SIZE_MAX, face = SIZE_MAX;  // positions of those elements
  bool has_normals = false, has_uvs = false;
};

[[noreturn]] void header_error(const std::string& name, size_t line, const std::string& problem) {
  throw InputError(name, "line " + std::to_string(line), problem);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

std::vector<std::string_view> split(std::string_view text) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_space(text[i])) ++i;
    const size_t start = i;
    while (i < text.size() && !is_space(text[i])) ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

/// Parses one header statement (after the magic line) into `h`.
void parse_header_line(const std::vector<std::string_view>& w, size_t line, PlyHeader& h,
                       const std::string& name) {
  const auto type_of = [&](std::string_view s) {
    const std::optional<PlyType> t = parse_type(s);
    if (!t) header_error(name, line, "unknown type '" + std::string(s) + "'");
    return *t;
  };
  if (w[0] == "format") {
    if (w.size() != 3 || (w[2] != "1.0" && w[2] != "1")) {
      header_error(name, line,
                   "expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
    }
    if (w[1] == "ascii") {
      h.format = PlyFormat::kAscii;
    } else if (w[1] == "binary_little_endian") {
      h.format = PlyFormat::kBinaryLittleEndian;
    } else if (w[1] == "binary_big_endian") {
      h.format = PlyFormat::kBinaryBigEndian;
    } else {
      header_error(name, line, "unknown format '" + std::string(w[1]) + "'");
    }
  } else if (w[0] == "element") {
    if (w.size() != 3) header_error(name, line, "expected 'element <name> <count>'");
    if (w[2].starts_with('-')) header_error(name, line, "negative count " + std::string(w[2]));
    PlyElement e{std::string(w[1]), 0, line, {}};
    const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
    if (ec != std::errc() || ptr != w[2].data() + w[2].size()) {
      header_error(name, line, "bad element count '" + std::string(w[2]) + "'");
    }
    h.elements.push_back(std::move(e));
  } else if (w[0] == "property") {
    if (h.elements.empty()) header_error(name, line, "property before any element");
    PlyProperty p;
    p.line = line;
    if (w.size() == 5 && w[1] == "list") {
      p.is_list = true;
      p.count_type = type_of(w[2]);
      p.type = type_of(w[3]);
      p.name = w[4];
      if (!is_integer(p.count_type)) {
        header_error(name, line, "list count type '" + std::string(w[2]) + "' is not an integer");
      }
    } else if (w.size() == 3 && w[1] != "list") {
      p.type = type_of(w[1]);
      p.name = w[2];
    } else {
      header_error(name, line, "expected 'property <type> <name>' or 'property list ...'");
    }
    h.elements.back().properties.push_back(std::move(p));
  } else if (w[0] != "comment" && w[0] != "obj_info") {
    header_error(name, line, "unknown header keyword '" + std::string(w[0]) + "'");
  }
}

/// Reads the header, from the magic line to end_header.
PlyHeader parse_header(std::string_view data, const std::string& name) {
  PlyHeader h;
  bool has_format = false;
  size_t pos = 0;
  for (size_t line = 1;; ++line) {
    if (pos >= data.size()) header_error(name, line, "missing 'end_header' (end of file)");
    size_t eol = data.find('\n', pos);
    if (eol == std::string_view::npos) eol = data.size();
    std::string_view text = data.substr(pos, eol - pos);
    pos = eol + 1;
    if (text.ends_with('\r')) text.remove_suffix(1);
    if (line == 1) {
      if (text != "ply") header_error(name, line, "bad magic: the file does not start with 'ply'");
      continue;
    }
    const std::vector<std::string_view> words = split(text);
    if (words.empty()) continue;
    if (words[0] == "end_header") {
      if (!has_format) header_error(name, line, "missing 'format' line");
      h.body_offset = std::min(pos, data.size());
      h.end_line = line;
      return h;
    }
    has_format |= words[0] == "format";
    parse_header_line(words, line, h, name);
  }
}

/// The vertex attribute slot a property name fills.
int vertex_slot(std::string_view n) {
  if (n == "x") return kX;
  if (n == "y") return kY;
  if (n == "z") return kZ;
  if (n == "nx") return kNx;
  if (n == "ny") return kNy;
  if (n == "nz") return kNz;
  if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") return kU;
  if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") return kV;
  return kSkip;
}

/// Finds the vertex and face elements and assigns property slots; checks what is required.
void resolve_layout(PlyHeader& h, const std::string& name) {
  for (size_t k = 0; k < h.elements.size(); ++k) {
    const PlyElement& e = h.elements[k];
    size_t* which = e.name == "vertex" ? &h.vertex : e.name == "face" ? &h.face : nullptr;
    if (!which) continue;
    if (*which != SIZE_MAX) header_error(name, e.line, "second '" + e.name + "' element");
    *which = k;
  }
  if (h.vertex == SIZE_MAX) header_error(name, h.end_line, "no 'vertex' element");
  if (h.face == SIZE_MAX) header_error(name, h.end_line, "no 'face' element");

  PlyElement& vertex = h.elements[h.vertex];
  if (vertex.count > UINT32_MAX) {
    header_error(name, vertex.line,
                 "element 'vertex' declares " + std::to_string(vertex.count) +
                     " items, more than 32-bit indices can address");
  }
  bool found[kIndices] = {};
  for (PlyProperty& p : vertex.properties) {
    if (p.is_list) continue;
    p.slot = vertex_slot(p.name);
    if (p.slot != kSkip) found[p.slot] = true;
  }
  for (const char* axis : {"x", "y", "z"}) {
    if (!found[vertex_slot(axis)]) {
      header_error(name, vertex.line,
                   std::string("element 'vertex' has no property '") + axis + "'");
    }
  }
  h.has_normals = found[kNx] && found[kNy] && found[kNz];
  h.has_uvs = found[kU] && found[kV];
  for (PlyProperty& p : vertex.properties) {
    if ((p.slot >= kNx && p.slot <= kNz && !h.has_normals) || (p.slot >= kU && !h.has_uvs)) {
      p.slot = kSkip;  // an incomplete group is skipped
    }
  }

  PlyElement& face = h.elements[h.face];
  for (PlyProperty& p : face.properties) {
    if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
    if (!p.is_list) header_error(name, p.line, "'" + p.name + "' is not a list");
    if (!is_integer(p.type)) {
      header_error(name, p.line, "index type '" + type_name(p.type) + "' is not an integer");
    }
    p.slot = kIndices;
    return;
  }
  header_error(name, face.line, "element 'face' has no list property 'vertex_indices'");
}

/// Checks every element count against the bytes left after the header, before any allocation:
/// a binary item needs at least the sum of its sizes (lists empty, face lists of 3 indices), an
/// ascii value at least 2 bytes (a digit and a separator).
void check_sizes(const PlyHeader& h, size_t file_size, const std::string& name) {
  const bool ascii = h.format == PlyFormat::kAscii;
  uint64_t remaining = file_size - h.body_offset + (ascii ? 1 : 0);  // last value may lack '\n'
  for (const PlyElement& e : h.elements) {
    uint64_t min_bytes = 0;
    for (const PlyProperty& p : e.properties) {
      const uint64_t list_items = p.slot == kIndices ? 3 : 0;
      if (ascii) {
        min_bytes += 2 * (1 + list_items);
      } else {
        min_bytes += p.is_list ? type_size(p.count_type) + list_items * type_size(p.type)
                               : type_size(p.type);
      }
    }
    if (min_bytes == 0) continue;
    if (e.count > remaining / min_bytes) {
      header_error(name, e.line,
                   "element '" + e.name + "' declares " + std::to_string(e.count) +
                       " items of at least " + std::to_string(min_bytes) + " bytes, but only " +
                       std::to_string(file_size - h.body_offset) + " bytes follow the header");
    }
    remaining -= e.count * min_bytes;
  }
}

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
  static std::string shorten(std::string_view token) {
    return token.size() <= 32 ? std::string(token) : std::string(token.substr(0, 32)) + "...";
  }

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
  mesh.indices.reserve(3 * e.count);  // bounded by check_sizes: at least 3 indices per face
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
