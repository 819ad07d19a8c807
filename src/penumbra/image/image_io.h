#pragma once
/// Reading and writing images by file extension, with writes that never leave a partial file.
#include <functional>
#include <string>
#include <string_view>

#include "penumbra/image/image.h"

namespace penumbra {

/// The image file formats penumbra reads and writes.
enum class ImageFormat { kPng, kExr, kPfm };

/// The format named by path's extension (.png, .exr, .pfm; any case); throws Error listing the
/// valid extensions for any other.
ImageFormat image_format_for(const std::string& path);
/// Throws Error when an image could not be written to `path` later: its directory is missing,
/// not a directory, or not writable; `path` is a directory, a device, FIFO or socket (also through
/// a symbolic link), or a read-only file (never replaced). Called before a render starts, so a
/// typo in the output path costs nothing, and again by write_atomically.
void check_writable(const std::string& path);

/// Checks path with check_writable, runs write(temp_path) on a temporary file beside path, then
/// renames it onto path, so path is either untouched or complete. If write or the rename throws,
/// the temporary file is removed and the exception propagates (an Error naming the temporary file
/// is re-thrown as an Error naming path; a failed rename throws Error).
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write);

/// Writes `bytes` to path through write_atomically and write_output_file (core/output_file.h):
/// every write checked and the file flushed to the disk before the rename.
void write_file_atomically(const std::string& path, std::string_view bytes);

/// Writes image to path in the format its extension names (PNG: 8-bit sRGB, exposure 1), through
/// write_atomically. Throws Error on an unknown extension or a failed write.
void write_image(const RgbImage& image, const std::string& path);

/// Reads the image at path in the format its extension names, as linear RGB: those above and
/// JPEG (.jpg, .jpeg; read only).
RgbImage read_image(const std::string& path);

/// Decodes a PNG or JPEG file held in memory (told apart by their signatures, not by a name), as
/// linear RGB; `name` names it in messages. Throws InputError for other bytes, or images of more
/// than `max_pixels` pixels (refused before the pixels are allocated).
RgbImage decode_image(std::string_view bytes, const std::string& name,
                      std::size_t max_pixels = kMaxImagePixels);

}  // namespace penumbra
