#include "penumbra/scene/obj_reader.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/text_escape.h"
#include "penumbra/geometry/polygon_triangulator.h"
#include "penumbra/scene/mesh_reader.h"
#include "penumbra/scene/mesh_warnings.h"

namespace penumbra {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

/// One face corner: 0-based indices into the file's v, vt and vn lists (kNone when absent).
struct Corner {
  uint32_t v, vt, vn;
  bool operator==(const Corner&) const = default;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Splits one line into whitespace-separated tokens; a '#' at the start of a token ends the line.
class Tokens {
 public:
  Tokens(const char* begin, const char* end) : p_(begin), end_(end) {}

  /// The next token, or an empty view at the end of the line.
  std::string_view next() {
    while (p_ < end_ && is_space(*p_)) ++p_;
    if (p_ == end_ || *p_ == '#') {
      p_ = end_;
      return {};
    }
    const char* start = p_;
    while (p_ < end_ && !is_space(*p_)) ++p_;
    return {start, static_cast<size_t>(p_ - start)};
  }

 private:
  const char* p_;
  const char* end_;
};

/// Parses a whole token as a float; false if it is not a number. Overflow gives inf, underflow 0.
bool parse_float(std::string_view token, float& out) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin < end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, out);
  if (ptr != end || begin == end) return false;
  if (ec == std::errc::result_out_of_range) {
    out = std::strtof(std::string(begin, end).c_str(), nullptr);  // rare: let strtof saturate
  } else if (ec != std::errc()) {
    return false;
  }
  return true;
}

/// Open-addressing hash table from a corner triple to its mesh vertex id (linear probing,
/// load factor at most 1/2); cheaper than std::unordered_map for millions of small keys.
class CornerTable {
 public:
  explicit CornerTable(size_t expected) {
    size_t capacity = 64;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, Slot{{}, kNone});
  }

  /// The id stored for `key`; if absent, stores `new_id` and returns it.
  uint32_t find_or_insert(Corner key, uint32_t new_id) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t i = hash(key) & mask;; i = (i + 1) & mask) {
      if (slots_[i].id == kNone) {
        slots_[i] = {key, new_id};
        ++size_;
        return new_id;
      }
      if (slots_[i].key == key) return slots_[i].id;
    }
  }

 private:
  struct Slot {
    Corner key;
    uint32_t id;
  };

  static size_t hash(Corner k) {
    uint64_t h =
        k.v * 0x9E3779B97F4A7C15ull ^ k.vt * 0xC2B2AE3D27D4EB4Full ^ k.vn * 0x165667B19E3779F9ull;
    return static_cast<size_t>(h ^ (h >> 29));
  }

  void grow() {
    std::vector<Slot> old(2 * slots_.size(), Slot{{}, kNone});
    old.swap(slots_);
    const size_t mask = slots_.size() - 1;
    for (const Slot& s : old) {
      if (s.id == kNone) continue;
      size_t i = hash(s.key) & mask;
      while (slots_[i].id != kNone) i = (i + 1) & mask;
      slots_[i] = s;
    }
  }

  std::vector<Slot> slots_;
  size_t size_ = 0;
};

/// Line-by-line OBJ parser over a memory buffer; builds the mesh once all lines are read.
class ObjParser {
 public:
  ObjParser(std::string_view text, const std::string& name, std::vector<std::string>* warnings)
      : text_(text), name_(name), warnings_(warnings, name) {}

  TriangleMesh parse() {
    // Text only: name binary data and UTF-16 rather than quoting their bytes as statements.
    if (text_.starts_with("\xEF\xBB\xBF")) text_.remove_prefix(3);  // a UTF-8 byte order mark
    if (const auto why = describe_non_text(text_)) throw InputError(name_, "", *why);
    const char* p = text_.data();
    const char* end = p + text_.size();
    while (p < end) {
      ++line_;
      const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
      if (!eol) eol = end;
      Tokens tokens(p, eol);
      const std::string_view keyword = tokens.next();
      if (!keyword.empty()) parse_statement(keyword, tokens);
      p = eol == end ? end : eol + 1;
    }
    warnings_.finish();
    return build();
  }

 private:
  void parse_statement(std::string_view keyword, Tokens& tokens) {
    float values[3] = {0, 0, 0};
    if (keyword == "v") {
      parse_numbers(tokens, keyword, values, 3);
      positions_.emplace_back(values[0], values[1], values[2]);
    } else if (keyword == "f") {
      parse_face(tokens);
    } else if (keyword == "vn") {
      parse_numbers(tokens, keyword, values, 3);
      normals_.emplace_back(values[0], values[1], values[2]);
    } else if (keyword == "vt") {
      parse_numbers(tokens, keyword, values, 1);
      uvs_.emplace_back(values[0], values[1]);
    } else if (keyword == "o" || keyword == "g" || keyword == "s" || keyword == "usemtl" ||
               keyword == "mtllib" || keyword == "l" || keyword == "p" || keyword == "vp") {
      // Accepted and ignored: names, groups, smoothing, materials, lines, points.
    } else {
      fail("unknown statement '" + quote(keyword) + "'");
    }
  }

  /// Reads at least `required` numbers into `out` (at most 3 kept); any further tokens must be
  /// numbers too (w, vertex colours) and are ignored.
  void parse_numbers(Tokens& tokens, std::string_view keyword, float* out, int required) {
    int count = 0;
    for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next(), ++count) {
      float value = 0;
      if (!parse_float(token, value)) fail("bad number '" + quote(token) + "'");
      if (!std::isfinite(value)) fail("non-finite number '" + quote(token) + "'");
      if (count < 3) out[count] = value;
    }
    if (count < required) {
      // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string here.
      std::string problem(1, '\'');
      problem.append(keyword).append("' needs ").append(std::to_string(required));
      fail(problem + " numbers, found " + std::to_string(count));
    }
  }

  /// Reads the corners of one polygon and appends its triangles to corners_.
  void parse_face(Tokens& tokens) {
    face_.clear();
    for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
      std::string_view parts[3];
      size_t part_count = 0, start = 0;
      for (;;) {
        const size_t slash = token.find('/', start);
        if (part_count == 3) fail("bad face vertex '" + quote(token) + "'");
        parts[part_count++] = token.substr(start, slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
      }
      if (parts[0].empty()) fail("bad face vertex '" + quote(token) + "'");
      face_.push_back({resolve(parts[0], positions_.size(), "vertex"),
                       parts[1].empty() ? kNone : resolve(parts[1], uvs_.size(), "uv"),
                       parts[2].empty() ? kNone : resolve(parts[2], normals_.size(), "normal")});
    }
    if (face_.size() < 3) {
      fail("face with " + std::to_string(face_.size()) + " vertices (needs at least 3)");
    }
    if (face_.size() >= kNone) fail("face with more than 2^32 - 2 vertices");
    if (face_.size() == 3) {
      corners_.insert(corners_.end(), face_.begin(), face_.end());
      return;
    }
    points_.clear();
    for (const Corner& c : face_) points_.push_back(positions_[c.v]);
    triangles_.clear();
    const PolygonReport report = triangulator_.triangulate(points_, triangles_);
    for (const uint32_t i : triangles_) corners_.push_back(face_[i]);
    if (report.any()) warnings_.polygon("line " + std::to_string(line_), report, face_.size());
  }

  /// Converts a 1-based or negative (relative) OBJ index into a 0-based index below `count`.
  uint32_t resolve(std::string_view text, size_t count, const char* what) {
    const char* begin = text.data();
    const char* end = begin + text.size();
    if (*begin == '+') ++begin;
    int64_t index = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, index);
    if (ec != std::errc() || ptr != end) fail("bad index '" + quote(text) + "'");
    if (index == 0) fail(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
    const int64_t n = static_cast<int64_t>(count);
    const int64_t resolved = index > 0 ? index - 1 : n + index;
    if (resolved < 0 || resolved >= n) {
      fail(std::string(what) + " index " + quote(text) + " out of range (" + std::to_string(count) +
           " defined so far)");
    }
    if (resolved >= kNone) fail("too many vertices for 32-bit indices");
    return static_cast<uint32_t>(resolved);
  }

  /// Turns corner triples into per-vertex attributes and triangle indices.
  TriangleMesh build() {
    bool has_uvs = true, has_normals = true;
    for (const Corner& c : corners_) {
      has_uvs &= c.vt != kNone;
      has_normals &= c.vn != kNone;
    }
    TriangleMesh mesh;
    mesh.indices.reserve(corners_.size());
    if (!has_uvs && !has_normals) {
      // Positions only: keep the file's vertices and their order.
      mesh.positions = std::move(positions_);
      for (const Corner& c : corners_) mesh.indices.push_back(c.v);
      return mesh;
    }
    // One mesh vertex per distinct triple, ignoring attributes dropped for the whole mesh.
    CornerTable table(positions_.size());
    for (Corner c : corners_) {
      if (!has_uvs) c.vt = 0;
      if (!has_normals) c.vn = 0;
      const auto next = static_cast<uint32_t>(mesh.positions.size());
      const uint32_t id = table.find_or_insert(c, next);
      if (id == next) {
        mesh.positions.push_back(positions_[c.v]);
        if (has_uvs) mesh.uvs.push_back(uvs_[c.vt]);
        if (has_normals) mesh.normals.push_back(normals_[c.vn]);
      }
      mesh.indices.push_back(id);
    }
    return mesh;
  }

  /// A token of the file for a message: escaped, at most 40 bytes.
  static std::string quote(std::string_view token) { return escape_for_message(token, 40); }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(name_, "line " + std::to_string(line_), problem);
  }

  std::string_view text_;
  const std::string& name_;
  MeshWarnings warnings_;
  size_t line_ = 0;
  std::vector<Vec3> positions_;
  std::vector<Vec3> normals_;
  std::vector<Vec2> uvs_;
  std::vector<Corner> corners_;      // three per triangle, in face order
  std::vector<Corner> face_;         // scratch: the corners of the current face
  std::vector<Vec3> points_;         // scratch: their positions
  std::vector<uint32_t> triangles_;  // scratch: the face's triangles, as indices into face_
  PolygonTriangulator triangulator_;
};

}  // namespace

TriangleMesh read_obj(const std::string& path, std::vector<std::string>* warnings) {
  const std::string text = read_file_contents(path);
  return parse_obj(text, path, warnings);
}

TriangleMesh parse_obj(std::string_view text, const std::string& name,
                       std::vector<std::string>* warnings) {
  return ObjParser(text, name, warnings).parse();
}

}  // namespace penumbra
