/// Fuzz target: the gzip reader behind pbrt's `.gz` files (gunzip), in memory, with the output
/// bounded at 1 MiB: zip bombs must stop there.
#include "fuzz_common.h"
#include "penumbra/scene/gzip_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    penumbra::gunzip(bytes, "fuzz.gz", std::uint64_t{1} << 20);
  });
}
