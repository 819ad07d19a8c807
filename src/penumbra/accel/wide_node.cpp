#include "penumbra/accel/wide_node.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

constexpr int kMinExponent = -126, kMaxExponent = 127;  // normal powers of two

/// The smallest byte whose decoded plane is >= x (outward for an upper plane), or -1 if even
/// 255 decodes below x.
int quantise_up(const CompressedNode& c, int a, float x) {
  const double guess = std::ceil((double(x) - c.origin[a]) / c.step(a));
  int q = static_cast<int>(std::clamp(guess, 0.0, 255.0));
  while (q > 0 && c.decode(a, uint8_t(q - 1)) >= x) --q;
  while (q <= 255 && c.decode(a, uint8_t(q)) < x) ++q;
  return q <= 255 ? q : -1;
}

/// The largest byte whose decoded plane is <= x (outward for a lower plane). x is never below
/// the origin, which byte 0 decodes to exactly.
int quantise_down(const CompressedNode& c, int a, float x) {
  const double guess = std::floor((double(x) - c.origin[a]) / c.step(a));
  int q = static_cast<int>(std::clamp(guess, 0.0, 255.0));
  while (q < 255 && c.decode(a, uint8_t(q + 1)) <= x) ++q;
  while (q > 0 && c.decode(a, uint8_t(q)) > x) --q;
  return q;
}

}  // namespace

CompressedNode compress_node(const WideNode<8>& node) {
  CompressedNode c{};
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int i = 0; i < 8; ++i) {
    if (!(node.box[0][i] <= node.box[1][i])) continue;  // an empty slot
    const bool first = c.valid == 0;
    c.valid |= uint8_t(1u << i);
    for (int a = 0; a < 3; ++a) {
      lo[a] = first ? node.box[2 * a][i] : std::min(lo[a], node.box[2 * a][i]);
      hi[a] = first ? node.box[2 * a + 1][i] : std::max(hi[a], node.box[2 * a + 1][i]);
    }
  }
  for (int a = 0; a < 3; ++a) {
    c.origin[a] = lo[a];
    // The smallest step with 255 steps covering the extent; grown by one octave whenever
    // rounding leaves a child's upper plane out of reach.
    const double extent = double(hi[a]) - double(lo[a]);
    int e = kMinExponent;
    if (extent > 0)
      e = std::clamp(int(std::ceil(std::log2(extent / 255.0))), kMinExponent, kMaxExponent);
    for (;; ++e) {
      c.exponent[a] = static_cast<int8_t>(e);
      bool ok = true;
      for (int i = 0; i < 8 && ok; ++i) {
        if (!(c.valid >> i & 1)) continue;
        const int q_hi = quantise_up(c, a, node.box[2 * a + 1][i]);
        ok = q_hi >= 0;
        if (!ok) break;
        c.q[2 * a][i] = uint8_t(quantise_down(c, a, node.box[2 * a][i]));
        c.q[2 * a + 1][i] = uint8_t(q_hi);
      }
      if (ok || e == kMaxExponent) break;
    }
  }
  for (int i = 0; i < 8; ++i) c.child[i] = node.child[i], c.count[i] = node.count[i];
  return c;
}

}  // namespace penumbra
