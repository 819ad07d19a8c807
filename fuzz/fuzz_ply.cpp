/// Fuzz target: the PLY reader (parse_ply): header, and ascii, binary little- and big-endian
/// bodies, in memory.
#include "fuzz_common.h"
#include "penumbra/scene/ply_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(
      data, size, [](std::string_view bytes) { penumbra::parse_ply(bytes, "fuzz.ply"); });
}
