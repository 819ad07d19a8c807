#pragma once
/// The PLY header (Turk 1994, "The PLY Polygon File Format"): element and property declarations,
/// their layout in penumbra's mesh, and the size checks made before the body is read. Internal
/// to the PLY reader (ply_reader.cpp reads the body).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::ply {

/// Scalar types of PLY properties; the integer types come first.
enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

/// Bytes of one value of `t`.
size_t type_size(PlyType t);
/// The classic name of `t` ("uchar", "float", ...).
std::string type_name(PlyType t);
/// True for the integer types.
bool is_integer(PlyType t);
/// Whether `v` lies in the range of the type `t` (any value fits a floating-point type).
bool fits(int64_t v, PlyType t);
/// PLY's whitespace.
bool is_space(char c);

/// The file's encoding.
enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

/// Where a vertex or face property goes: a vertex attribute component, the face indices, nowhere.
enum Slot : int { kSkip = -1, kX, kY, kZ, kNx, kNy, kNz, kU, kV, kIndices };

/// One property of an element, with its slot in the mesh.
struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kUint8;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;  // lists only
  int slot = kSkip;
  size_t line = 0;  // header line, for errors
};

/// One element declaration.
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  size_t line = 0;
  std::vector<PlyProperty> properties;
};

/// The parsed header.
struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;                     // first byte after the end_header line
  size_t end_line = 0;                        // line number of end_header
  size_t vertex = SIZE_MAX, face = SIZE_MAX;  // positions of those elements
  bool has_normals = false, has_uvs = false;
};

/// Reads the header of `data`, from the magic line to end_header; throws InputError naming
/// `name` and the line.
PlyHeader parse_header(std::string_view data, const std::string& name);
/// Finds the vertex and face elements and assigns property slots; checks what is required.
void resolve_layout(PlyHeader& h, const std::string& name);
/// Checks every element count against the bytes left after the header, before any allocation.
void check_sizes(const PlyHeader& h, size_t file_size, const std::string& name);

}  // namespace penumbra::ply
