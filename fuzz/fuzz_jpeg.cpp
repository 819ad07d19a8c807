/// Fuzz target: the JPEG reader (decode_jpeg), in memory. Images above 2^16 pixels are refused
/// here (the reader's limit is 2^28, whose 3 GiB would trip the fuzzer's memory limit): the
/// per-pixel conversion of the largest images took most of the time at 2^20 (perf: 1250
/// executions/s), while every path of the reader is reached by images of 256 x 256.
#include "fuzz_common.h"
#include "penumbra/image/jpeg.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    penumbra::decode_jpeg(bytes, "fuzz.jpg", std::size_t{1} << 16);
  });
}
