#pragma once
/// 8-bit sRGB JPEG files through libjpeg (Debian's libjpeg-turbo).
#include <cstddef>
#include <string>
#include <string_view>

#include "penumbra/image/image.h"

namespace penumbra {

/// Reads a baseline or progressive JPEG (greyscale, YCbCr or RGB; CMYK is refused) and converts
/// its 8-bit sRGB codes to linear values. Throws InputError naming the file
/// if libjpeg rejects it.
RgbImage read_jpeg(const std::string& path);

/// Decodes JPEG bytes held in memory (read_jpeg's decoder); `name` names them in messages. Images
/// of more than `max_pixels` pixels are refused after the header and before the pixels are
/// allocated; every libjpeg error is an InputError (libjpeg's own handler would exit()).
RgbImage decode_jpeg(std::string_view bytes, const std::string& name,
                     std::size_t max_pixels = kMaxImagePixels);

/// The bytes of a baseline JPEG of `image` (sRGB-encoded as write_png does, 4:4:4 chroma at
/// quality 90 and above) at `quality` in [1, 100]: for tests and fuzz seeds. Throws Error for an
/// empty image.
std::string encode_jpeg(const RgbImage& image, int quality = 95);

}  // namespace penumbra
