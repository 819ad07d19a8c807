// The one translation unit that compiles tinygltf's implementation (the Debian package ships the
// header and a shared library built with stb_image and unrestricted file access; compiling it here
// with gltf_model.h's switches gives neither), and the guarded file system callbacks.
#include "penumbra/scene/gltf_model.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
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

// Images are not decoded (textures are reported in a warning by the material mapping).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
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
  loader.SetImageLoader(&skip_image, nullptr);
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
    throw InputError(file_name, "", problem);
  }
  return model;
}

}  // namespace penumbra
