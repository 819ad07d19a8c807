#pragma once
/// Builds small glTF files in tests: binary data in one base64 data: URI buffer, accessors and
/// bufferViews appended by the builder, the rest of the document given as JSON.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/scene/gltf_loader.h"

namespace penumbra::test {

/// Standard base64 with padding.
inline std::string base64(const std::vector<uint8_t>& data) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t v = uint32_t(data[i]) << 16;
    if (i + 1 < data.size()) v |= uint32_t(data[i + 1]) << 8;
    if (i + 2 < data.size()) v |= data[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[v & 63] : '=';
  }
  return out;
}

/// Accumulates a binary buffer and its accessors; doc() gives the whole glTF document.
class GltfBuilder {
 public:
  /// An accessor of `type` ("VEC3", "SCALAR", ...) over 4-byte floats.
  int floats(const std::vector<float>& v, const char* type, int components) {
    return add(v.data(), v.size() * 4, 5126, type, v.size() / size_t(components));
  }
  /// A SCALAR UNSIGNED_INT accessor.
  int indices(const std::vector<uint32_t>& v) {
    return add(v.data(), v.size() * 4, 5125, "SCALAR", v.size());
  }
  /// A SCALAR UNSIGNED_SHORT accessor.
  int indices16(const std::vector<uint16_t>& v) {
    return add(v.data(), v.size() * 2, 5123, "SCALAR", v.size());
  }
  /// Raw bytes as an accessor of the given component type, type and count.
  int add(const void* p, size_t bytes, int component_type, const char* type, size_t count) {
    while (data_.size() % 4) data_.push_back(0);
    const size_t offset = data_.size();
    data_.resize(offset + bytes);
    std::memcpy(data_.data() + offset, p, bytes);
    views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    accessors_.push_back({{"bufferView", views_.size() - 1},
                          {"componentType", component_type},
                          {"type", type},
                          {"count", count}});
    return int(accessors_.size() - 1);
  }
  /// The accessor list, to change an entry before doc().
  nlohmann::json& accessors() { return accessors_; }
  /// The binary data so far.
  const std::vector<uint8_t>& data() const { return data_; }
  /// `rest` (nodes, meshes, ...) with asset, buffers, bufferViews and accessors added.
  nlohmann::json doc(nlohmann::json rest) const {
    rest["asset"] = {{"version", "2.0"}};
    if (!data_.empty()) {
      rest["buffers"] = nlohmann::json::array(
          {{{"byteLength", data_.size()},
            {"uri", "data:application/octet-stream;base64," + base64(data_)}}});
      rest["bufferViews"] = views_;
      rest["accessors"] = accessors_;
    }
    return rest;
  }

 private:
  std::vector<uint8_t> data_;
  nlohmann::json views_ = nlohmann::json::array();
  nlohmann::json accessors_ = nlohmann::json::array();
};

/// A unit right triangle in the z = 0 plane: positions (0,0,0), (1,0,0), (0,1,0), indexed.
inline nlohmann::json triangle_mesh(GltfBuilder& b) {
  const int pos = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
  const int idx = b.indices({0, 1, 2});
  return {{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}};
}

/// Parses the document as "model.gltf" in the working directory.
inline SceneDesc load_gltf(const nlohmann::json& doc) {
  return parse_gltf_scene(doc.dump(), "model.gltf", "");
}

/// True when some warning contains `text`.
inline bool has_warning(const SceneDesc& s, const std::string& text) {
  for (const std::string& w : s.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace penumbra::test
