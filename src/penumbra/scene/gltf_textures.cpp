#include "penumbra/scene/gltf_textures.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <utility>

#include "penumbra/core/memory_limit.h"

namespace penumbra {

using nlohmann::json;

namespace {

// The image type of encoded bytes by their signature: "image/png", "image/jpeg" or "".
std::string sniff_mime(const std::string& bytes) {
  if (bytes.starts_with("\x89PNG")) return "image/png";
  if (bytes.starts_with("\xFF\xD8")) return "image/jpeg";
  return "";
}

// The image type an external URI's extension names ("" when none is known).
std::string mime_of_extension(const std::string& uri) {
  std::string ext = std::filesystem::path(uri).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".webp") return "image/webp";
  if (ext == ".ktx2") return "image/ktx2";
  return "";
}

// A sampler's wrap mode as penumbra's wrap name.
std::string wrap_name(const GltfSource& src, int mode, const std::string& at) {
  switch (mode) {
    case kGltfRepeat:
      return "repeat";
    case kGltfClampToEdge:
      return "clamp";
    case kGltfMirroredRepeat:
      return "mirror";
  }
  src.fail(at, "unknown wrap mode " + std::to_string(mode) +
                   " (valid: 10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT)");
}

}  // namespace

GltfTextures::GltfTextures(const GltfSource& src, std::string base_dir,
                           std::vector<EmbeddedImage>& images)
    : src_(src), base_dir_(std::move(base_dir)), images_(images), names_(src.model.images.size()) {}

std::string GltfTextures::image(int index, const std::string& user,
                                std::vector<std::string>& warnings) {
  const tinygltf::Model& m = src_.model;
  if (index < 0 || size_t(index) >= m.images.size())
    src_.fail(user, "image " + std::to_string(index) + " out of range (" +
                        std::to_string(m.images.size()) + " images)");
  if (names_[size_t(index)]) return *names_[size_t(index)];
  const tinygltf::Image& img = m.images[size_t(index)];
  const std::string at = "/images/" + std::to_string(index);
  std::string bytes, mime = img.mimeType;
  if (img.bufferView >= 0) {
    // A bufferView image (.glb): the view checked against its buffer before the copy.
    if (size_t(img.bufferView) >= m.bufferViews.size())
      src_.fail(at + "/bufferView", "bufferView " + std::to_string(img.bufferView) +
                                        " out of range (" + std::to_string(m.bufferViews.size()) +
                                        " bufferViews)");
    const tinygltf::BufferView& view = m.bufferViews[size_t(img.bufferView)];
    const std::string view_at = "/bufferViews/" + std::to_string(img.bufferView);
    if (view.buffer < 0 || size_t(view.buffer) >= m.buffers.size())
      src_.fail(view_at + "/buffer", "buffer " + std::to_string(view.buffer) + " out of range");
    const tinygltf::Buffer& buffer = m.buffers[size_t(view.buffer)];
    if (view.byteOffset > buffer.data.size() ||
        view.byteLength > buffer.data.size() - view.byteOffset)
      src_.fail(view_at, "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                             std::to_string(view.byteLength) + " exceeds buffer " +
                             std::to_string(view.buffer) + " of " +
                             std::to_string(buffer.data.size()) + " bytes (used by " + at + ")");
    check_memory(double(view.byteLength), src_.file + ":" + at + ": image");
    bytes.assign(reinterpret_cast<const char*>(buffer.data.data()) + view.byteOffset,
                 view.byteLength);
  } else if (img.as_is) {
    bytes.assign(img.image.begin(), img.image.end());  // a data: URI, decoded by tinygltf
  } else if (img.uri.starts_with("data:")) {
    const size_t end = img.uri.find_first_of(";,");
    mime = img.uri.substr(5, end == std::string::npos ? 0 : end - 5);
  } else if (!img.uri.empty()) {
    const std::string relative = gltf_percent_decode(img.uri);
    if (mime.empty()) mime = mime_of_extension(relative);
    if (mime.empty() || mime == "image/png" || mime == "image/jpeg")
      bytes = read_gltf_file(base_dir_, relative, src_.file, at + "/uri");
  } else {
    src_.fail(at, "an image needs a \"uri\" or a \"bufferView\"");
  }
  if (mime.empty()) mime = sniff_mime(bytes);
  if (mime == "image/jpg") mime = "image/jpeg";  // a common misspelling among exporters
  if (mime != "image/png" && mime != "image/jpeg") {
    warnings.push_back(
        src_.message(at, (mime.empty() ? std::string("image of unknown type") : mime) +
                             " not read (penumbra reads PNG and JPEG): factors used"));
    names_[size_t(index)] = "";
    return "";
  }
  const std::string name = src_.file + "#" + at;
  images_.push_back({name, mime, std::make_shared<const std::string>(std::move(bytes))});
  names_[size_t(index)] = name;
  return name;
}

std::optional<json> GltfTextures::texture(const tinygltf::TextureInfo& info, const std::string& at,
                                          Rgb factor, std::vector<std::string>& warnings) {
  const tinygltf::Model& m = src_.model;
  if (size_t(info.index) >= m.textures.size())
    src_.fail(at + "/index", "texture " + std::to_string(info.index) + " out of range (" +
                                 std::to_string(m.textures.size()) + " textures)");
  if (info.texCoord != 0) {
    warnings.push_back(src_.message(
        at + "/texCoord",
        "texCoord " + std::to_string(info.texCoord) + " not read (only TEXCOORD_0): factors used"));
    return std::nullopt;
  }
  if (info.extensions.count("KHR_texture_transform"))
    warnings.push_back(src_.message(at + "/extensions/KHR_texture_transform",
                                    "KHR_texture_transform ignored: the untransformed uvs used"));
  const std::string tex_at = "/textures/" + std::to_string(info.index);
  const tinygltf::Texture& tex = m.textures[size_t(info.index)];
  if (tex.source < 0) {
    warnings.push_back(
        src_.message(tex_at,
                     "no PNG or JPEG source (EXT_texture_webp, KHR_texture_basisu are not read): "
                     "factors used"));
    return std::nullopt;
  }
  const std::string name = image(tex.source, tex_at + "/source", warnings);
  if (name.empty()) return std::nullopt;
  json wrap = json::array({"repeat", "repeat"});
  if (tex.sampler >= 0) {
    if (size_t(tex.sampler) >= m.samplers.size())
      src_.fail(tex_at + "/sampler", "sampler " + std::to_string(tex.sampler) + " out of range (" +
                                         std::to_string(m.samplers.size()) + " samplers)");
    const std::string s_at = "/samplers/" + std::to_string(tex.sampler);
    const tinygltf::Sampler& s = m.samplers[size_t(tex.sampler)];
    wrap = json::array(
        {wrap_name(src_, s.wrapS, s_at + "/wrapS"), wrap_name(src_, s.wrapT, s_at + "/wrapT")});
    if (s.magFilter == kGltfNearest)
      warnings.push_back(
          src_.message(s_at + "/magFilter", "NEAREST filtering not supported: bilinear used"));
  }
  return json{{"type", "image"},
              {"file", name},
              {"wrap", wrap},
              {"factor", json::array({factor.r, factor.g, factor.b})}};
}

}  // namespace penumbra
