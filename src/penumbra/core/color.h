#pragma once
/// Linear RGB colour (radiance, reflectance), float per channel.
#include <algorithm>
#include <cmath>

namespace penumbra {

/// A linear-RGB triple.
struct Rgb {
  float r = 0, g = 0, b = 0;
  constexpr Rgb() = default;
  constexpr Rgb(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
  constexpr explicit Rgb(float s) : r(s), g(s), b(s) {}
  constexpr float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb operator+(Rgb o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(Rgb o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(Rgb o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(float s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(float s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(Rgb o) { return *this = *this + o; }
  constexpr Rgb& operator*=(Rgb o) { return *this = *this * o; }
  constexpr Rgb& operator*=(float s) { return *this = *this * s; }
  constexpr bool operator==(const Rgb&) const = default;
  /// True when every channel is exactly zero.
  constexpr bool is_black() const { return r == 0.f && g == 0.f && b == 0.f; }
  /// Rec. 709 luminance.
  constexpr float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
  constexpr float max_channel() const { return std::max(r, std::max(g, b)); }
};

constexpr Rgb operator*(float s, Rgb c) { return c * s; }

}  // namespace penumbra
