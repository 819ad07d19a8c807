#pragma once
/// Portable Float Map (PFM) files: a short text header, then raw 32-bit floats, bottom row first.
#include <string>

#include "penumbra/image/image.h"

namespace penumbra {

/// Writes a colour ("PF") PFM: little-endian floats (scale -1.0), rows stored from the bottom up.
/// Throws Error if the image is empty or the file cannot be written.
void write_pfm(const RgbImage& image, const std::string& path);

/// Reads a colour ("PF") or greyscale ("Pf", expanded to RGB) PFM of either endianness; the
/// magnitude of the scale is ignored, so values come back bit-exact. Throws InputError naming the
/// file and byte offset for a malformed file, Error if it cannot be opened.
RgbImage read_pfm(const std::string& path);

}  // namespace penumbra
