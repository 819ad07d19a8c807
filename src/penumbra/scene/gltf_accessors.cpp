#include "penumbra/scene/gltf_accessors.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"

namespace penumbra {

void GltfSource::fail(const std::string& path, const std::string& problem) const {
  throw InputError(file, path, problem);
}

std::string GltfSource::message(const std::string& path, const std::string& problem) const {
  return InputError(file, path, problem).what();
}

namespace {

// A checked accessor: where its elements start, the stride between them and their layout.
struct AccessorView {
  const unsigned char* data = nullptr;
  size_t count = 0, stride = 0;
  int component_type = 0, components = 0;
  bool normalized = false;
  std::string path;  // "/accessors/N"
};

size_t component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;  // INT and DOUBLE are not valid glTF 2.0 accessor types
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
  }
}

// Checks accessor `index` and its bufferView and buffer: offset + stride * (count - 1) + element
// size must lie within the bufferView, and the bufferView within its buffer.
AccessorView view_accessor(const GltfSource& src, int index, const std::string& user) {
  const tinygltf::Model& m = src.model;
  if (index < 0 || size_t(index) >= m.accessors.size())
    src.fail(user, "accessor " + std::to_string(index) + " out of range (" +
                       std::to_string(m.accessors.size()) + " accessors)");
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  AccessorView v;
  v.path = "/accessors/" + std::to_string(index);
  if (a.sparse.isSparse) src.fail(v.path + "/sparse", "sparse accessors are not supported");
  if (a.bufferView < 0)
    src.fail(v.path, "an accessor without a bufferView (all zeros) is not supported");
  if (size_t(a.bufferView) >= m.bufferViews.size())
    src.fail(v.path + "/bufferView", "bufferView " + std::to_string(a.bufferView) +
                                         " out of range (" + std::to_string(m.bufferViews.size()) +
                                         " bufferViews)");
  const size_t csize = component_size(a.componentType);
  if (csize == 0)
    src.fail(v.path + "/componentType",
             "invalid component type " + std::to_string(a.componentType));
  v.components = component_count(a.type);
  if (v.components == 0) src.fail(v.path + "/type", "invalid accessor type");
  if (a.count < 1) src.fail(v.path + "/count", "must be at least 1");
  const std::string bv_path = "/bufferViews/" + std::to_string(a.bufferView);
  const tinygltf::BufferView& bv = m.bufferViews[size_t(a.bufferView)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size())
    src.fail(bv_path + "/buffer", "buffer " + std::to_string(bv.buffer) + " out of range (" +
                                      std::to_string(m.buffers.size()) + " buffers)");
  const std::vector<unsigned char>& buffer = m.buffers[size_t(bv.buffer)].data;
  if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
    src.fail(bv_path + "/byteLength", "bytes " + std::to_string(bv.byteOffset) + " + " +
                                          std::to_string(bv.byteLength) + " exceed buffer " +
                                          std::to_string(bv.buffer) + " of " +
                                          std::to_string(buffer.size()) + " bytes");
  const size_t element = csize * size_t(v.components);
  v.stride = bv.byteStride == 0 ? element : bv.byteStride;
  if (v.stride < element || v.stride > 252)
    src.fail(bv_path + "/byteStride", "stride " + std::to_string(v.stride) +
                                          " must lie in [element size " + std::to_string(element) +
                                          ", 252]");
  // The last element ends at offset + stride * (count - 1) + element; no product can overflow
  // once count is bounded by the bufferView's length.
  const size_t room = bv.byteLength;
  if (a.byteOffset > room || a.count - 1 > (room - a.byteOffset) / v.stride ||
      a.byteOffset + v.stride * (a.count - 1) + element > room)
    src.fail(v.path + "/count",
             "count " + std::to_string(a.count) + " with stride " + std::to_string(v.stride) +
                 " and byteOffset " + std::to_string(a.byteOffset) + " exceeds bufferView " +
                 std::to_string(a.bufferView) + " of " + std::to_string(room) + " bytes");
  v.data = buffer.data() + bv.byteOffset + a.byteOffset;
  v.count = a.count;
  v.component_type = a.componentType;
  v.normalized = a.normalized;
  return v;
}

// Component `c` of element `i` as a float (normalized integers mapped to [0, 1]).
float component(const AccessorView& v, size_t i, int c) {
  const unsigned char* p = v.data + i * v.stride;
  switch (v.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p + 4 * size_t(c), 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return float(p[c]) / 255.0f;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t s;
      std::memcpy(&s, p + 2 * size_t(c), 2);
      return float(s) / 65535.0f;
    }
    default:
      return 0.0f;
  }
}

void require_layout(const GltfSource& src, const AccessorView& v, int components,
                    const char* what) {
  if (v.components != components) src.fail(v.path + "/type", std::string("expected ") + what);
}

void reserve_checked(const GltfSource& src, const AccessorView& v, size_t bytes_per_element) {
  check_memory(double(v.count) * double(bytes_per_element), src.file + ":" + v.path);
}

}  // namespace

std::vector<Vec3> read_gltf_vec3(const GltfSource& src, int index, const std::string& user) {
  const AccessorView v = view_accessor(src, index, user);
  require_layout(src, v, 3, "VEC3");
  if (v.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
    src.fail(v.path + "/componentType", "expected FLOAT (5126)");
  reserve_checked(src, v, sizeof(Vec3));
  std::vector<Vec3> out(v.count);
  for (size_t i = 0; i < v.count; ++i) {
    out[i] = Vec3(component(v, i, 0), component(v, i, 1), component(v, i, 2));
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y) || !std::isfinite(out[i].z))
      src.fail(v.path, "element " + std::to_string(i) + " is not finite");
  }
  return out;
}

std::vector<Vec2> read_gltf_uv(const GltfSource& src, int index, const std::string& user) {
  const AccessorView v = view_accessor(src, index, user);
  require_layout(src, v, 2, "VEC2");
  const bool ok = v.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                  (v.normalized && (v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                    v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
  if (!ok)
    src.fail(v.path + "/componentType",
             "expected FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
  reserve_checked(src, v, sizeof(Vec2));
  std::vector<Vec2> out(v.count);
  for (size_t i = 0; i < v.count; ++i) {
    out[i] = Vec2(component(v, i, 0), component(v, i, 1));
    if (!std::isfinite(out[i].x) || !std::isfinite(out[i].y))
      src.fail(v.path, "element " + std::to_string(i) + " is not finite");
  }
  return out;
}

std::vector<uint32_t> read_gltf_indices(const GltfSource& src, int index, const std::string& user) {
  const AccessorView v = view_accessor(src, index, user);
  require_layout(src, v, 1, "SCALAR");
  reserve_checked(src, v, sizeof(uint32_t));
  std::vector<uint32_t> out(v.count);
  for (size_t i = 0; i < v.count; ++i) {
    const unsigned char* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        out[i] = p[0];
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p, 2);
        out[i] = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        std::memcpy(&out[i], p, 4);
        break;
      default:
        src.fail(v.path + "/componentType",
                 "expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT indices");
    }
  }
  return out;
}

size_t gltf_accessor_count(const GltfSource& src, int index, const std::string& user) {
  return view_accessor(src, index, user).count;
}

}  // namespace penumbra
