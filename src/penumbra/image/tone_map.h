#pragma once
/// Transfer curves between linear values and display encodings.
#include <cmath>
#include <cstdint>

namespace penumbra {

/// Linear value to sRGB-encoded value with the IEC 61966-2-1 piecewise curve (not clamped).
inline float srgb_encode(float linear) {
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

/// sRGB-encoded value to linear value, the inverse of srgb_encode (not clamped).
inline float srgb_decode(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

/// Linear value to an 8-bit sRGB code: clamped to [0, 1] (NaN gives 0), encoded, rounded.
inline std::uint8_t srgb_encode_8bit(float linear) {
  // Written so that NaN fails the first test and maps to 0.
  const float clamped = linear > 0.0f ? (linear < 1.0f ? linear : 1.0f) : 0.0f;
  return static_cast<std::uint8_t>(std::lround(srgb_encode(clamped) * 255.0f));
}

}  // namespace penumbra
