#pragma once
/// glTF textures, samplers and images as penumbra image textures: a textureInfo becomes the JSON of
/// an {"type": "image"} texture whose "file" names an EmbeddedImage of the SceneDesc
/// ("FILE#/images/ N"), the image's encoded bytes from a data: URI, a bufferView or a file inside
/// the glTF file's folder. Images are read when a texture first uses them, each once; nothing is
/// decoded here.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/core/color.h"
#include "penumbra/scene/gltf_accessors.h"
#include "penumbra/scene/scene_desc.h"

namespace penumbra {

/// glTF sampler wrap modes.
inline constexpr int kGltfRepeat = 10497, kGltfClampToEdge = 33071, kGltfMirroredRepeat = 33648;
/// glTF's NEAREST filter.
inline constexpr int kGltfNearest = 9728;

/// The textures of one glTF file and the images they have read.
class GltfTextures {
 public:
  /// Images go to `images` (a SceneDesc's); external files are read from `base_dir`.
  GltfTextures(const GltfSource& src, std::string base_dir, std::vector<EmbeddedImage>& images);

  /// The texture JSON for textureInfo `info` at JSON path `at` (".../baseColorTexture"), each
  /// lookup multiplied by `factor`; std::nullopt (with a warning) when it cannot be used: another
  /// texCoord than 0, no source penumbra reads (webp, KTX2), an image of another type than PNG
  /// or JPEG. Bad indices, bufferViews and files are errors naming their JSON path.
  std::optional<nlohmann::json> texture(const tinygltf::TextureInfo& info, const std::string& at,
                                        Rgb factor, std::vector<std::string>& warnings);

 private:
  /// The EmbeddedImage name of image `index`, read on first use; "" (with a warning) when it is
  /// of a type penumbra does not read.
  std::string image(int index, const std::string& user, std::vector<std::string>& warnings);

  const GltfSource& src_;
  std::string base_dir_;
  std::vector<EmbeddedImage>& images_;
  std::vector<std::optional<std::string>> names_;  ///< per glTF image, once read
};

}  // namespace penumbra
