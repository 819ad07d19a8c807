#include "penumbra/accel/auto_width_bvh.h"

namespace penumbra {

AutoWidthBvh::AutoWidthBvh(const ParamList& params)
    : params_(params), narrow_(params), wider_(params) {}

int AutoWidthBvh::width_for(size_t prims) {
#if defined(__AVX512F__)
  return prims > kWide16Above ? 16 : 8;
#else
  // Without AVX-512 a 16-wide box test takes two or four vector operations per plane.
  (void)prims;
  return 8;
#endif
}

void AutoWidthBvh::build(const PrimitiveSet& prims) {
  wide_ = width_for(prims.size()) == 16;
  // Only one of the two holds a tree: the other is made anew, dropping an earlier build's.
  if (wide_) {
    narrow_ = WideBvh<8>(params_);
    wider_.build(prims);
    stats_ = wider_.stats();
  } else {
    wider_ = WideBvh<16>(params_);
    narrow_.build(prims);
    stats_ = narrow_.stats();
  }
  stats_.extra.emplace_back("width", double(width()));
}

}  // namespace penumbra
