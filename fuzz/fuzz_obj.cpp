/// Fuzz target: the Wavefront OBJ reader (parse_obj), in memory.
#include "fuzz_common.h"
#include "penumbra/scene/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(
      data, size, [](std::string_view bytes) { penumbra::parse_obj(bytes, "fuzz.obj"); });
}
