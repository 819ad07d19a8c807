#pragma once
/// tinygltf, configured for penumbra: no image decoding (stb_image is not used), no external image
/// files, no file system access but the guarded reader of gltf_model.cpp. Every file that includes
/// tiny_gltf.h includes it through this header so that all see the same configuration.
#include <string>
#include <string_view>
#include <vector>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_FS
#include <tiny_gltf.h>

namespace penumbra {

/// Parses a glTF 2.0 file held in memory: a .glb when `bytes` starts with the magic "glTF", else
/// JSON text. External buffers are read from files inside `base_dir` only (relative URIs that do
/// not climb out of it); data: URIs are decoded; images are never read or decoded. tinygltf's
/// errors become an InputError naming `file_name`; its warnings are appended to `warnings` as
/// "FILE: message".
tinygltf::Model read_gltf_model(std::string_view bytes, const std::string& file_name,
                                const std::string& base_dir, std::vector<std::string>& warnings);

}  // namespace penumbra
