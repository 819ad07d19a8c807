/// Fuzz target: the JSON scene loader (parse_scene), in memory. Mesh files named by the input are
/// resolved in a directory that does not exist; absolute paths reach the file system, which
/// read_input_file bounds (regular files only, read up to their size).
#include <string>

#include "fuzz_common.h"
#include "penumbra/scene/scene_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    penumbra::parse_scene(std::string(bytes), "fuzz.json", "/nonexistent-penumbra-fuzz");
  });
}
