/// Fuzz target: the glTF 2.0 reader (parse_gltf_scene), in memory: JSON text or a .glb (by its
/// magic). External buffer URIs resolve under a directory that does not exist.
#include "fuzz_common.h"
#include "penumbra/scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    penumbra::parse_gltf_scene(std::string(bytes), "fuzz.gltf", "/nonexistent-penumbra-fuzz");
  });
}
