#pragma once
/// Validated reads of glTF accessors (vertex attributes and indices): every index into accessors,
/// bufferViews and buffers, every offset, stride and count is checked against the bytes that are
/// really there before anything is allocated or read. Errors are InputErrors
/// "FILE:/json/path: problem" naming the accessor, bufferView or buffer at fault.
#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/vec.h"
#include "penumbra/scene/gltf_model.h"

namespace penumbra {

/// The model and the file name that messages start with.
struct GltfSource {
  const tinygltf::Model& model;  ///< the parsed file
  std::string file;              ///< its name, for messages
  /// Throws InputError "FILE:PATH: problem".
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const;
  /// "FILE:PATH: problem", the form of a SceneDesc warning.
  std::string message(const std::string& path, const std::string& problem) const;
};

/// The elements of accessor `index` as VEC3 of FLOAT (POSITION, NORMAL); `user` is the JSON path
/// that refers to the accessor ("/meshes/0/primitives/1/attributes/POSITION"). Non-finite values
/// are errors.
std::vector<Vec3> read_gltf_vec3(const GltfSource& src, int index, const std::string& user);

/// The elements of accessor `index` as VEC2 texture coordinates: FLOAT, or normalized UNSIGNED_BYTE
/// or UNSIGNED_SHORT (mapped to [0, 1]).
std::vector<Vec2> read_gltf_uv(const GltfSource& src, int index, const std::string& user);

/// The elements of accessor `index` as SCALAR indices of UNSIGNED_BYTE, UNSIGNED_SHORT or
/// UNSIGNED_INT.
std::vector<uint32_t> read_gltf_indices(const GltfSource& src, int index, const std::string& user);

/// The element count of accessor `index` (checked as for a read; nothing is read).
size_t gltf_accessor_count(const GltfSource& src, int index, const std::string& user);

}  // namespace penumbra
