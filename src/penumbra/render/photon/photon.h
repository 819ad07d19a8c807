#pragma once
/// The photon record stored in photon maps: position, incident direction and power in 28 bytes.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "penumbra/core/color.h"
#include "penumbra/core/vec.h"

namespace penumbra {

/// A unit vector in 32 bits: the octahedral map (Meyer et al. 2010, "On Floating-Point Normal
/// Vectors"), 16 bits per coordinate; the angular error is below 1e-4 radians.
struct OctDirection {
  uint16_t u = 0, v = 0;

  static OctDirection encode(Vec3 d) {
    const float l1 = std::fabs(d.x) + std::fabs(d.y) + std::fabs(d.z);
    float x = d.x / l1, y = d.y / l1;
    if (d.z < 0.0f) {  // fold the lower hemisphere over the diagonals
      const float fx = (1.0f - std::fabs(y)) * (x >= 0.0f ? 1.0f : -1.0f);
      const float fy = (1.0f - std::fabs(x)) * (y >= 0.0f ? 1.0f : -1.0f);
      x = fx, y = fy;
    }
    return {quantize(x), quantize(y)};
  }
  Vec3 decode() const {
    const float x = dequantize(u), y = dequantize(v);
    Vec3 d{x, y, 1.0f - std::fabs(x) - std::fabs(y)};
    if (d.z < 0.0f) {
      const float ox = d.x;
      d.x = (1.0f - std::fabs(d.y)) * (ox >= 0.0f ? 1.0f : -1.0f);
      d.y = (1.0f - std::fabs(ox)) * (d.y >= 0.0f ? 1.0f : -1.0f);
    }
    return normalize(d);
  }

 private:
  static uint16_t quantize(float x) {
    return uint16_t(std::lround((std::clamp(x, -1.0f, 1.0f) * 0.5f + 0.5f) * 65535.0f));
  }
  static float dequantize(uint16_t q) { return float(q) / 65535.0f * 2.0f - 1.0f; }
};

/// A photon stored where it hit a non-specular surface.
struct Photon {
  Vec3 p;           ///< where it landed
  OctDirection wi;  ///< unit direction back towards where it came from
  Rgb power;        ///< flux it carries (W), already divided by the photons emitted

  Vec3 incident() const { return wi.decode(); }
};
static_assert(sizeof(Photon) == 28, "photon records are 28 bytes");

}  // namespace penumbra
