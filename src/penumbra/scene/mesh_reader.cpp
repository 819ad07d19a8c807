#include "penumbra/scene/mesh_reader.h"

#include <cctype>
#include <filesystem>

#include "penumbra/core/error.h"
#include "penumbra/core/input_file.h"
#include "penumbra/scene/obj_reader.h"
#include "penumbra/scene/ply_reader.h"

namespace penumbra {

TriangleMesh read_mesh(const std::string& path, std::vector<std::string>* warnings) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".obj") return read_obj(path, warnings);
  if (ext == ".ply") return read_ply(path, warnings);
  throw InputError(path, "", "unsupported mesh format '" + ext + "' (expected one of: .obj, .ply)");
}

std::string read_file_contents(const std::string& path) {
  return read_input_file(path);
}

}  // namespace penumbra
