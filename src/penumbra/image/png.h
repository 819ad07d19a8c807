#pragma once
/// 8-bit sRGB PNG files through libpng.
#include <cstddef>
#include <string>
#include <string_view>

#include "penumbra/image/image.h"

namespace penumbra {

/// Writes an 8-bit RGB PNG tagged sRGB: each value is multiplied by exposure, clamped to [0, 1]
/// (NaN to 0) and encoded with the sRGB curve. Throws Error naming the file on failure.
void write_png(const RgbImage& image, const std::string& path, float exposure = 1.0f);
/// The bytes write_png writes. Throws Error for an empty image or if libpng fails.
std::string encode_png(const RgbImage& image, float exposure = 1.0f);

/// Reads a PNG (any bit depth and colour type; alpha dropped, 16-bit cut to 8) and converts its
/// 8-bit sRGB codes to linear values. Throws InputError naming the file if libpng rejects it.
RgbImage read_png(const std::string& path);

/// Decodes PNG bytes held in memory (read_png's decoder); `name` names them in messages. Images of
/// more than `max_pixels` pixels are refused before the pixels are allocated.
RgbImage decode_png(std::string_view bytes, const std::string& name,
                    std::size_t max_pixels = kMaxImagePixels);

}  // namespace penumbra
