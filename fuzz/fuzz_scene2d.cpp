/// Fuzz target: the 2D laboratory's text format (parse_scene2d) and the disjointness check that
/// `penumbra bsp2d` runs on what it reads.
#include "fuzz_common.h"
#include "penumbra/accel2d/scene2d.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return penumbra::fuzz::check_reader(data, size, [](std::string_view bytes) {
    const penumbra::lab2d::Scene2D scene = penumbra::lab2d::parse_scene2d(bytes, "fuzz.txt");
    penumbra::lab2d::check_disjoint(scene, false);
  });
}
