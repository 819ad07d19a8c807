#pragma once
/// OpenEXR files through the OpenEXR library: 32-bit float R, G, B channels, ZIP compression.
#include <cstddef>
#include <string>
#include <string_view>

#include "penumbra/image/image.h"

namespace penumbra {

/// Writes a scanline EXR with 32-bit float R, G, B channels and ZIP compression.
/// Throws Error naming the file if the image is empty or OpenEXR fails.
void write_exr(const RgbImage& image, const std::string& path);
/// The bytes write_exr writes. Throws Error for an empty image or if OpenEXR fails.
std::string encode_exr(const RgbImage& image);

/// Reads the R, G, B channels of an EXR as floats (half channels are widened, missing ones read as
/// 0; a luminance-only "Y" file is copied to all three). The data window becomes the image.
/// Throws InputError naming the file if OpenEXR rejects it or it holds no colour channels.
RgbImage read_exr(const std::string& path);

/// Decodes EXR bytes held in memory (read_exr's decoder); `name` names them in messages. Data
/// windows of more than `max_pixels` pixels are refused before the pixels are allocated.
RgbImage decode_exr(std::string_view bytes, const std::string& name,
                    std::size_t max_pixels = kMaxImagePixels);

}  // namespace penumbra
