/// Fuzz target: the Wavefront OBJ reader (parse_obj), in memory, with its warnings: at most the
/// first 10 and a count, and no raw bytes in them either.
#include <string>
#include <vector>

#include "fuzz_common.h"
#include "penumbra/scene/obj_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    std::vector<std::string> warnings;
    penumbra::parse_obj(bytes, "fuzz.obj", &warnings);
    if (warnings.size() > 11) std::abort();
    for (const std::string& w : warnings) {
      if (!penumbra::fuzz::is_clean_message(w)) std::abort();
    }
  });
}
