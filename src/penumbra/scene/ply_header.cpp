#include "penumbra/scene/ply_header.h"

#include <charconv>
#include <cstdlib>
#include <optional>

#include "penumbra/core/error.h"
#include "penumbra/core/text_escape.h"

namespace penumbra::ply {

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
static std::optional<PlyType> parse_type(std::string_view s) {
  constexpr std::string_view kSized[] = {"int8",  "uint8",  "int16",   "uint16",
                                         "int32", "uint32", "float32", "float64"};
  for (int i = 0; i < 8; ++i) {
    if (s == kTypeNames[i] || s == kSized[i]) return static_cast<PlyType>(i);
  }
  return std::nullopt;
}

/// A word of the header for a message or a name: escaped, at most 40 bytes (so a name that is
/// cut can never equal "vertex" or "x").
static std::string quote(std::string_view word) {
  return escape_for_message(word, 40);
}

[[noreturn]] static void header_error(const std::string& name, size_t line,
                                      const std::string& problem) {
  throw InputError(name, "line " + std::to_string(line), problem);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

static std::vector<std::string_view> split(std::string_view text) {
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
static void parse_header_line(const std::vector<std::string_view>& w, size_t line, PlyHeader& h,
                              const std::string& name) {
  const auto type_of = [&](std::string_view s) {
    const std::optional<PlyType> t = parse_type(s);
    if (!t) header_error(name, line, "unknown type '" + quote(s) + "'");
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
      header_error(name, line, "unknown format '" + quote(w[1]) + "'");
    }
  } else if (w[0] == "element") {
    if (w.size() != 3) header_error(name, line, "expected 'element <name> <count>'");
    if (w[2].starts_with('-')) header_error(name, line, "negative count " + quote(w[2]));
    PlyElement e{quote(w[1]), 0, line, {}};
    const auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
    if (ec != std::errc() || ptr != w[2].data() + w[2].size()) {
      header_error(name, line, "bad element count '" + quote(w[2]) + "'");
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
      p.name = quote(w[4]);
      if (!is_integer(p.count_type)) {
        header_error(name, line, "list count type '" + quote(w[2]) + "' is not an integer");
      }
    } else if (w.size() == 3 && w[1] != "list") {
      p.type = type_of(w[1]);
      p.name = quote(w[2]);
    } else {
      header_error(name, line, "expected 'property <type> <name>' or 'property list ...'");
    }
    h.elements.back().properties.push_back(std::move(p));
  } else if (w[0] != "comment" && w[0] != "obj_info") {
    header_error(name, line, "unknown header keyword '" + quote(w[0]) + "'");
  }
}

/// Reads the header, from the magic line to end_header.
PlyHeader parse_header(std::string_view data, const std::string& name) {
  PlyHeader h;
  if (data.empty()) throw InputError(name, "", "empty file (0 bytes)");
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
      if (text != "ply") {
        const auto why = describe_non_text(data.substr(0, 4));
        if (why && why->starts_with("UTF")) header_error(name, line, *why);
        header_error(name, line, "bad magic: the file does not start with 'ply'");
      }
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
static int vertex_slot(std::string_view n) {
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
/// a binary item needs at least the sum of its sizes (lists empty: a face of fewer than three
/// vertices is reported as such when it is read), an ascii value at least 2 bytes (a digit and a
/// separator).
void check_sizes(const PlyHeader& h, size_t file_size, const std::string& name) {
  const bool ascii = h.format == PlyFormat::kAscii;
  uint64_t remaining = file_size - h.body_offset + (ascii ? 1 : 0);  // last value may lack '\n'
  for (const PlyElement& e : h.elements) {
    uint64_t min_bytes = 0;
    for (const PlyProperty& p : e.properties) {
      if (ascii) {
        min_bytes += 2;
      } else {
        min_bytes += type_size(p.is_list ? p.count_type : p.type);
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

}  // namespace penumbra::ply
