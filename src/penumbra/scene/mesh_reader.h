#pragma once
/// Mesh file loading: dispatch on the file extension to the OBJ or PLY reader, and the whole-file
/// read the readers share (one read into memory, then parsing with pointers, no stream per token).
#include <string>
#include <vector>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// Reads a triangle mesh from `path`, choosing the reader by extension (.obj or .ply, any case);
/// throws InputError for an unknown extension or a malformed file. The reader's warnings
/// ("FILE:PLACE: problem", e.g. an OBJ polygon that is not planar) are appended to `warnings`
/// when given.
TriangleMesh read_mesh(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Returns the whole content of the file at `path` (read_input_file: regular files only, read up
/// to their size); throws InputError if it cannot be read.
std::string read_file_contents(const std::string& path);

}  // namespace penumbra
