// The one translation unit that compiles tinygltf's implementation (the Debian package ships the
// header and a shared library built with stb_image and unrestricted file access; compiling it here
// with gltf_model.h's switches gives neither), and the guarded file system callbacks.
#include "penumbra/scene/gltf_model.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <system_error>

#include "penumbra/core/error.h"
#include "penumbra/core/memory_limit.h"

#define TINYGLTF_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// What the callbacks may read: regular files inside `base` (after resolving "..", "." and
// symbolic links), so a buffer URI such as "../../etc/passwd" or "/etc/passwd" reads nothing.
struct FsGuard {
  fs::path base;
  std::string file;  // the glTF file, for messages
};

bool inside_base(const std::string& path, const FsGuard& guard) {
  if (guard.base.empty()) return false;
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::path(path), ec);
  if (ec) return false;
  const fs::path rel = p.lexically_relative(guard.base);
  if (rel.empty() || rel.is_absolute()) return false;
  return *rel.begin() != "..";
}

bool file_exists(const std::string& path, void* user) {
  std::error_code ec;
  return inside_base(path, *static_cast<FsGuard*>(user)) && fs::is_regular_file(path, ec);
}

// No "~" or "$VAR" expansion (tinygltf's own used wordexp, which runs shell substitutions).
std::string expand_file_path(const std::string& path, void*) {
  return path;
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
  const FsGuard& guard = *static_cast<FsGuard*>(user);
  if (!inside_base(path, guard)) {
    if (err) *err += "refused to read \"" + path + "\": outside the glTF file's folder\n";
    return false;
  }
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) {
    if (err) *err += "cannot read \"" + path + "\"\n";
    return false;
  }
  check_memory(double(size), guard.file + ": buffer file \"" + path + "\"");
  std::ifstream in(path, std::ios::binary);
  out->resize(size_t(size));
  if (size > 0) in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size));
  if (!in) {
    if (err) *err += "cannot read \"" + path + "\"\n";
    return false;
  }
  return true;
}

bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&,
                      void*) {
  if (err) *err += "writing is disabled\n";
  return false;
}

// Images are not decoded. A data: URI's bytes are kept for the importer (gltf_textures.cpp); a
// bufferView image's are not: tinygltf hands them over without checking the view against its
// buffer, so the importer reads bufferViews itself, checked.
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && bytes && size > 0) {
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
  }
  return true;
}

// tinygltf's image errors ("... for image[3] ...") with the JSON path of the image; other errors
// as they are.
InputError gltf_error(const std::string& file, const std::string& problem) {
  static const std::regex image_index(R"(image\[(\d+)\])");
  std::smatch m;
  if (std::regex_search(problem, m, image_index)) {
    const std::string at = "/images/" + m[1].str();
    if (problem.find("Failed to decode 'uri'") != std::string::npos)
      return InputError(file, at + "/uri", "bad data: URI (not valid base64 data)");
    if (problem.find("bufferView") != std::string::npos)
      return InputError(file, at + "/bufferView", problem);
    return InputError(file, at, problem);
  }
  return InputError(file, "", problem);
}

// tinygltf's messages are lines; each becomes "FILE: line".
std::vector<std::string> message_lines(const std::string& text, const std::string& file) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(InputError(file, "", line).what());
  return out;
}

}  // namespace

tinygltf::Model read_gltf_model(std::string_view bytes, const std::string& file_name,
                                const std::string& base_dir, std::vector<std::string>& warnings) {
  FsGuard guard{{}, file_name};
  std::error_code ec;
  guard.base = fs::weakly_canonical(fs::path(base_dir.empty() ? "." : base_dir), ec);
  if (ec) guard.base.clear();

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_image_bytes, nullptr);
  loader.SetFsCallbacks(
      {&file_exists, &expand_file_path, &read_whole_file, &write_whole_file, &guard});
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
  if (bytes.size() > UINT32_MAX)
    throw InputError(file_name, "", "larger than 4 GiB, the limit of glTF files");
  const std::string dir = base_dir.empty() ? "." : base_dir;
  bool ok;
  if (binary)
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                     reinterpret_cast<const unsigned char*>(bytes.data()),
                                     unsigned(bytes.size()), dir);
  else
    ok = loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), dir);
  for (std::string& w : message_lines(warn, file_name)) warnings.push_back(std::move(w));
  if (!ok || !err.empty()) {
    std::string problem = err.empty() ? "not a valid glTF file" : err;
    while (!problem.empty() && problem.back() == '\n') problem.pop_back();
    throw gltf_error(file_name, problem);
  }
  return model;
}

std::string read_gltf_file(const std::string& base_dir, const std::string& relative,
                           const std::string& file_name, const std::string& json_path) {
  FsGuard guard{{}, file_name};
  std::error_code ec;
  guard.base = fs::weakly_canonical(fs::path(base_dir.empty() ? "." : base_dir), ec);
  if (ec) guard.base.clear();
  const fs::path path = fs::path(base_dir.empty() ? "." : base_dir) / relative;
  if (relative.empty() || fs::path(relative).is_absolute() || !inside_base(path.string(), guard))
    throw InputError(file_name, json_path,
                     "\"" + relative + "\" is outside the glTF file's folder: not read");
  if (!fs::is_regular_file(path, ec))
    throw InputError(file_name, json_path, "image file \"" + path.string() + "\" not found");
  std::vector<unsigned char> bytes;
  std::string err;
  if (!read_whole_file(&bytes, &err, path.string(), &guard))
    throw InputError(file_name, json_path, "cannot read \"" + path.string() + "\"");
  return std::string(bytes.begin(), bytes.end());
}

std::string gltf_percent_decode(const std::string& uri) {
  const auto hex = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace penumbra
