#pragma once
/// tinygltf, configured for penumbra: no image decoding (stb_image is not used), no external image
/// files, no file system access but the guarded reader of gltf_model.cpp; the bytes of data: URI
/// images are kept (Image::image, with as_is set) for the importer to hand on undecoded. Every file
/// that includes tiny_gltf.h includes it through this header so that all see the same
/// configuration.
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
/// not climb out of it); data: URIs are decoded (an image's bytes kept, never decoded as an
/// image); external images are not read here (see read_gltf_file). tinygltf's errors become an
/// InputError naming `file_name` (and the image's JSON path for its image errors); its warnings
/// are appended to `warnings` as "FILE: message".
tinygltf::Model read_gltf_model(std::string_view bytes, const std::string& file_name,
                                const std::string& base_dir, std::vector<std::string>& warnings);

/// The bytes of the file `relative` (a percent-decoded URI) under `base_dir`, with the rules of
/// buffer files: a regular file inside the folder after resolving "..", "." and symbolic links,
/// its size checked against the memory limit. Otherwise throws InputError "FILE:JSON_PATH: ...".
std::string read_gltf_file(const std::string& base_dir, const std::string& relative,
                           const std::string& file_name, const std::string& json_path);

/// `uri` with its %XX escapes decoded (RFC 3986); a '%' not followed by two hex digits is kept.
std::string gltf_percent_decode(const std::string& uri);

}  // namespace penumbra
