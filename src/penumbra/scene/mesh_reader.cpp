#include "penumbra/scene/mesh_reader.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>

#include "penumbra/core/error.h"
#include "penumbra/scene/obj_reader.h"
#include "penumbra/scene/ply_reader.h"

namespace penumbra {

TriangleMesh read_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return read_obj(path);
  if (ext == ".ply") return read_ply(path);
  throw InputError(path, "", "unsupported mesh format '" + ext + "' (expected one of: .obj, .ply)");
}

std::string read_file_contents(const std::string& path) {
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  if (!file) throw InputError(path, "", std::string("cannot open file: ") + std::strerror(errno));

  // Read the expected size in one call, then whatever is left (pipes, files that grew).
  std::string data;
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec) data.resize(static_cast<size_t>(size));
  data.resize(std::fread(data.data(), 1, data.size(), file.get()));
  char chunk[1 << 16];
  size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof(chunk), file.get())) > 0) data.append(chunk, got);
  if (std::ferror(file.get())) {
    throw InputError(path, "", std::string("cannot read file: ") + std::strerror(errno));
  }
  return data;
}

}  // namespace penumbra
