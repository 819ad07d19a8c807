#include "penumbra/render/radiosity/radiosity_solution.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "penumbra/core/error.h"
#include "penumbra/core/input_file.h"
#include "penumbra/image/image_io.h"
#include "penumbra/image/tone_map.h"

namespace penumbra {

namespace {

/// One corner record: position, 8-bit colour, radiosity (little endian, packed: 27 bytes).
constexpr size_t kVertexBytes = 3 * 4 + 3 + 3 * 4;

/// The header lines after the format and comment lines, for a given vertex and face count.
std::string header_body(size_t vertices, size_t faces) {
  return fmt::format(
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property float radiosity_r\nproperty float radiosity_g\nproperty float radiosity_b\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      vertices, faces);
}

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // the machine is little endian (x86-64, AArch64)
  out.append(b, sizeof(T));
}

template <class T>
T get(const std::string& in, size_t& at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

size_t corner_count(const RadiosityMesh& mesh) {
  size_t n = 0;
  for (const RadiosityElement& e : mesh.elements()) n += e.corners;
  return n;
}

}  // namespace

void write_radiosity_solution(const std::string& path, const RadiosityMesh& mesh,
                              const std::vector<Rgb>& corners, const std::string& comment) {
  const size_t nv = corner_count(mesh);
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment penumbra radiosity solution";
  if (!comment.empty()) out += ": " + comment;
  out += "\n";
  // The adaptive subdivision, so that a reader can rebuild the same mesh from the scene.
  for (const std::vector<uint32_t>& round : mesh.refinements()) {
    out += "comment split";
    for (const uint32_t f : round) out += fmt::format(" {}", f);
    out += "\n";
  }
  out += header_body(nv, mesh.size());
  for (size_t e = 0; e < mesh.size(); ++e) {
    const RadiosityElement& el = mesh.elements()[e];
    for (int k = 0; k < el.corners; ++k) {
      const Vec3 p = mesh.vertices()[el.v[k]];
      const Rgb b = corners[4 * e + size_t(k)];
      put(out, p.x), put(out, p.y), put(out, p.z);
      for (int c = 0; c < 3; ++c) put(out, srgb_encode_8bit(b[c] * std::numbers::inv_pi_v<float>));
      put(out, b.r), put(out, b.g), put(out, b.b);
    }
  }
  int32_t next = 0;
  for (const RadiosityElement& el : mesh.elements()) {
    put(out, uint8_t(el.corners));
    for (int k = 0; k < el.corners; ++k) put(out, next++);
  }
  write_file_atomically(path, out);
}

std::vector<Rgb> read_radiosity_solution(const std::string& path, RadiosityMesh& mesh,
                                         size_t max_elements) {
  // Read whole through read_input_file: regular files only, up to their size.
  std::istringstream f(read_input_file(path), std::ios::binary);
  // The header, line by line: it must be exactly what write_radiosity_solution writes for this
  // mesh (the comment aside).
  std::string line;
  int line_no = 0;
  const auto expect = [&](const std::string& want) {
    ++line_no;
    if (!std::getline(f, line) || line != want)
      throw InputError(path, fmt::format("line {}", line_no),
                       fmt::format("expected '{}' in a radiosity solution header, found '{}'", want,
                                   line.substr(0, 80)));
  };
  expect("ply");
  expect("format binary_little_endian 1.0");
  ++line_no;
  if (!std::getline(f, line) || line.rfind("comment penumbra radiosity solution", 0) != 0)
    throw InputError(path, fmt::format("line {}", line_no),
                     "not a radiosity solution written by `penumbra radiosity`");
  // Adaptive subdivision rounds: replay them on the mesh as built.
  while (f.peek() == 'c') {
    ++line_no;
    std::getline(f, line);
    const std::string where = fmt::format("line {}", line_no);
    if (line.rfind("comment split", 0) != 0)
      throw InputError(path, where, "expected 'comment split' or 'element vertex'");
    std::vector<uint32_t> split;
    const char* c = line.c_str() + 13;
    while (*c == ' ') {
      char* end = nullptr;
      const unsigned long long v = std::strtoull(c + 1, &end, 10);
      if (end == c + 1 || v > UINT32_MAX || (*end != ' ' && *end != '\0'))
        throw InputError(path, where, "a split list holds non-negative element numbers");
      split.push_back(static_cast<uint32_t>(v));
      c = end;
    }
    if (mesh.size() + 6 * split.size() > max_elements)
      throw InputError(path, where,
                       fmt::format("the subdivision would exceed {} elements", max_elements));
    try {
      mesh.subdivide(split);
    } catch (const Error& e) {
      throw InputError(path, where, e.what());
    }
  }
  const size_t nv = corner_count(mesh);
  const std::string body = header_body(nv, mesh.size());
  size_t start = 0;
  while (start < body.size()) {
    const size_t end = body.find('\n', start);
    const std::string want = body.substr(start, end - start);
    if (want.rfind("element", 0) == 0) {
      // A count mismatch means another scene or patch size: say so.
      ++line_no;
      if (!std::getline(f, line) || line != want)
        throw InputError(path, fmt::format("line {}", line_no),
                         fmt::format("'{}' does not match this scene's mesh ('{}'): solved for "
                                     "another scene or patch size",
                                     line.substr(0, 80), want));
    } else {
      expect(want);
    }
    start = end + 1;
  }
  const std::streamoff data_start = f.tellg();
  const std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  size_t face_bytes = 0;
  for (const RadiosityElement& e : mesh.elements()) face_bytes += 1 + 4 * size_t(e.corners);
  if (data.size() != nv * kVertexBytes + face_bytes)
    throw InputError(path, fmt::format("byte {}", data_start + std::streamoff(data.size())),
                     fmt::format("the data is {} bytes, the header announces {}", data.size(),
                                 nv * kVertexBytes + face_bytes));
  // Corners: their positions must be this mesh's (within rounding of the same computation).
  std::vector<Rgb> corners(4 * mesh.size());
  const float tol = 1e-5f * std::max(1.0f, [&] {
                      float m = 0.0f;
                      for (const Vec3& v : mesh.vertices()) m = std::max(m, max_component(abs(v)));
                      return m;
                    }());
  size_t at = 0;
  for (size_t e = 0; e < mesh.size(); ++e) {
    const RadiosityElement& el = mesh.elements()[e];
    for (int k = 0; k < el.corners; ++k) {
      const size_t offset = size_t(data_start) + at;
      Vec3 p;
      p.x = get<float>(data, at), p.y = get<float>(data, at), p.z = get<float>(data, at);
      at += 3;  // the 8-bit colour
      Rgb b;
      b.r = get<float>(data, at), b.g = get<float>(data, at), b.b = get<float>(data, at);
      if (!(max_component(abs(p - mesh.vertices()[el.v[k]])) <= tol))
        throw InputError(path, fmt::format("byte {}", offset),
                         fmt::format("corner {} of element {} lies elsewhere than in this "
                                     "scene's mesh: solved for another scene",
                                     k, e));
      if (!(std::isfinite(b.r) && std::isfinite(b.g) && std::isfinite(b.b)) || b.r < 0 || b.g < 0 ||
          b.b < 0)
        throw InputError(path, fmt::format("byte {}", offset + 15),
                         "radiosity is negative or not finite");
      corners[4 * e + size_t(k)] = b;
    }
  }
  return corners;
}

}  // namespace penumbra
