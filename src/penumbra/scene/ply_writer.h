#pragma once
/// Encoding triangle meshes as binary little-endian PLY files that ply_reader reads back exactly
/// (the caller writes the bytes: the app layer, atomically).
#include <string>

#include "penumbra/geometry/triangle_mesh.h"

namespace penumbra {

/// The bytes of `mesh` as a binary little-endian PLY file: vertices with float x, y, z (and nx,
/// ny, nz and u, v when the mesh has them), faces as a uchar count and uint indices. Floats are
/// stored as they are, so reading the file back gives the same mesh bit for bit.
std::string encode_ply(const TriangleMesh& mesh);

}  // namespace penumbra
