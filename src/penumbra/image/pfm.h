#pragma once
/// Portable Float Map (PFM) files: a short text header, then raw 32-bit floats, bottom row first.
#include <cstddef>
#include <string>
#include <string_view>

#include "penumbra/image/image.h"

namespace penumbra {

/// Writes a colour ("PF") PFM: little-endian floats (scale -1.0), rows stored from the bottom up.
/// Throws Error if the image is empty or the file cannot be written.
void write_pfm(const RgbImage& image, const std::string& path);
/// The bytes write_pfm writes. Throws Error for an empty image.
std::string encode_pfm(const RgbImage& image);

/// Reads a colour ("PF") or greyscale ("Pf", expanded to RGB) PFM of either endianness; the
/// magnitude of the scale is ignored, so values come back bit-exact. Throws InputError naming the
/// file and byte offset for a malformed file or one that cannot be read.
RgbImage read_pfm(const std::string& path);

/// Decodes PFM bytes held in memory (read_pfm's parser); `name` names them in messages. Images of
/// more than `max_pixels` pixels are refused before anything is allocated.
RgbImage decode_pfm(std::string_view bytes, const std::string& name,
                    std::size_t max_pixels = kMaxImagePixels);

}  // namespace penumbra
