/// Fuzz target: the pbrt-v4 scene reader (parse_pbrt_scene), in memory. Relative Include,
/// Import and mesh names resolve under a directory that does not exist.
#include "fuzz_common.h"
#include "penumbra/scene/pbrt_parser.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    penumbra::parse_pbrt_scene(std::string(bytes), "fuzz.pbrt", "/nonexistent-penumbra-fuzz");
  });
}
