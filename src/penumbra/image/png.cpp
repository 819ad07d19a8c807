/// PNG reading and writing with libpng. libpng reports errors by longjmp; every setjmp below sits
/// in a function whose locals are all trivial, so the jump never skips a C++ destructor.
#include "penumbra/image/png.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "penumbra/core/input_file.h"
#include "penumbra/core/output_file.h"
#include "penumbra/core/text_escape.h"
#include "penumbra/image/tone_map.h"

namespace penumbra {
namespace {

// Where libpng's error handler leaves its message before jumping back.
struct PngMessage {
  char text[256] = "unknown libpng error";
};

void on_png_error(png_structp png, png_const_charp message) {
  auto* out = static_cast<PngMessage*>(png_get_error_ptr(png));
  std::snprintf(out->text, sizeof(out->text), "%s", message);
  png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

// libpng's output callbacks: the encoded bytes go to a string.
void write_to_string(png_structp png, png_bytep data, png_size_t count) {
  static_cast<std::string*>(png_get_io_ptr(png))
      ->append(reinterpret_cast<const char*>(data), count);
}
void flush_nothing(png_structp) {}

// Largest ancillary chunk (text, ICC profile, ...) libpng may buffer; bigger ones are skipped.
constexpr png_alloc_size_t kMaxChunkBytes = png_alloc_size_t{8} << 20;

// PNG bytes held in memory, read by libpng through read_from_memory.
struct PngSource {
  const png_byte* data;
  std::size_t size;
  std::size_t pos;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t count) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (count > source->size - source->pos) png_error(png, "file ends in the middle of a chunk");
  std::memcpy(out, source->data + source->pos, count);
  source->pos += count;
}

// Walks the chunks (length, type, data, CRC) before libpng sees them: libpng allocates a chunk's
// declared length before reading it, so a 74-byte file could ask for 1.2 GB (fuzz finding, issue
// #18). A chunk longer than the bytes that follow is an InputError naming its byte offset.
void check_png_chunks(std::string_view file, const std::string& path) {
  constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
  if (!file.starts_with(kSignature)) {
    throw InputError(path, "byte 0", "not a PNG file (bad signature)");
  }
  for (std::size_t pos = kSignature.size(); pos + 8 <= file.size();) {
    std::uint32_t length = 0;
    for (int i = 0; i < 4; ++i) length = length << 8 | static_cast<std::uint8_t>(file[pos + i]);
    const std::string type = escape_for_message(file.substr(pos + 4, 4));
    if (length > file.size() - pos - 8 || file.size() - pos - 8 - length < 4) {
      throw InputError(path, "byte " + std::to_string(pos),
                       "chunk '" + type + "' declares " + std::to_string(length) +
                           " bytes, but only " + std::to_string(file.size() - pos - 8) +
                           " follow (with its CRC)");
    }
    if (type == "IEND") return;
    pos += 12 + length;
  }
}

// Owns libpng's read or write structure and its info structure.
class PngHandle {
 public:
  PngHandle(bool write, PngMessage* message) : write_(write) {
    png =
        write
            ? png_create_write_struct(PNG_LIBPNG_VER_STRING, message, on_png_error, on_png_warning)
            : png_create_read_struct(PNG_LIBPNG_VER_STRING, message, on_png_error, on_png_warning);
    info = png ? png_create_info_struct(png) : nullptr;
  }
  ~PngHandle() {
    if (write_) {
      png_destroy_write_struct(&png, &info);
    } else {
      png_destroy_read_struct(&png, &info, nullptr);
    }
  }
  PngHandle(const PngHandle&) = delete;
  PngHandle& operator=(const PngHandle&) = delete;

  png_structp png = nullptr;
  png_infop info = nullptr;

 private:
  bool write_;
};

// Writes header and rows; false (with the message set) if libpng fails.
bool png_write_all(png_structp png, png_infop info, std::string* out, int width, int height,
                   png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, out, write_to_string, flush_nothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  return true;
}

// Reads the header and sets transforms to 8-bit RGB; false (with the message set) on failure.
bool png_read_header(png_structp png, png_infop info, PngSource* source, png_uint_32* width,
                     png_uint_32* height) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_read_fn(png, source, read_from_memory);
  // No chunk buffer above kMaxChunkBytes: a text chunk that claims 640 MB in a file of 130 bytes
  // was allocated and cleared before its data was found missing (fuzz finding, issue #18).
  png_set_chunk_malloc_max(png, kMaxChunkBytes);
  png_read_info(png, info);
  png_set_expand(png);  // palette to RGB, low-bit grey to 8 bits, tRNS to alpha
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_gray_to_rgb(png);
  png_read_update_info(png, info);
  *width = png_get_image_width(png, info);
  *height = png_get_image_height(png, info);
  return true;
}

// Reads all rows after png_read_header; false (with the message set) on failure.
bool png_read_rows(png_structp png, png_infop info, png_bytepp rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

}  // namespace

std::string encode_png(const RgbImage& image, float exposure) {
  if (image.empty()) throw Error("cannot encode an empty image as PNG");

  // Encode every row to 8-bit sRGB before libpng is involved.
  const std::size_t stride = static_cast<std::size_t>(image.width()) * 3;
  std::vector<png_byte> bytes(stride * image.height());
  std::vector<png_bytep> rows(image.height());
  for (int y = 0; y < image.height(); ++y) {
    rows[y] = bytes.data() + stride * y;
    const Rgb* pixels = image.row(y);
    for (int x = 0; x < image.width(); ++x) {
      for (int c = 0; c < 3; ++c) rows[y][3 * x + c] = srgb_encode_8bit(pixels[x][c] * exposure);
    }
  }

  std::string out;
  PngMessage message;
  PngHandle handle(true, &message);
  if (!handle.info) throw Error("cannot encode PNG: out of memory");
  if (!png_write_all(handle.png, handle.info, &out, image.width(), image.height(), rows.data()))
    throw Error(std::string("cannot encode PNG: ") + message.text);
  return out;
}

void write_png(const RgbImage& image, const std::string& path, float exposure) {
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  std::string bytes;
  try {
    bytes = encode_png(image, exposure);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  write_output_file(path, bytes);
}

RgbImage read_png(const std::string& path) {
  return decode_png(read_input_file(path), path);
}

RgbImage decode_png(std::string_view file, const std::string& path, std::size_t max_pixels) {
  PngSource source{reinterpret_cast<const png_byte*>(file.data()), file.size(), 0};
  if (file.empty()) throw InputError(path, "", "empty file (0 bytes), not a PNG");
  check_png_chunks(file, path);
  PngMessage message;
  PngHandle handle(false, &message);
  if (!handle.info) throw Error(path + ": cannot read PNG: out of memory");

  png_uint_32 width = 0, height = 0;
  if (!png_read_header(handle.png, handle.info, &source, &width, &height)) {
    throw InputError(path, "", std::string("invalid PNG: ") + message.text);
  }
  if (std::uint64_t{width} * height > max_pixels) {
    throw InputError(path, "",
                     "PNG of " + std::to_string(width) + " x " + std::to_string(height) +
                         " pixels is larger than the limit of " + std::to_string(max_pixels));
  }

  const std::size_t stride = std::size_t{width} * 3;
  std::vector<png_byte> bytes(stride * height);
  std::vector<png_bytep> rows(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = bytes.data() + stride * y;
  if (!png_read_rows(handle.png, handle.info, rows.data())) {
    throw InputError(path, "", std::string("invalid PNG: ") + message.text);
  }

  // 8-bit sRGB codes to linear values through a table.
  float to_linear[256];
  for (int i = 0; i < 256; ++i) to_linear[i] = srgb_decode(static_cast<float>(i) / 255.0f);
  RgbImage image(static_cast<int>(width), static_cast<int>(height));
  for (std::size_t i = 0; i < image.size(); ++i) {
    image.data()[i] =
        Rgb(to_linear[bytes[3 * i]], to_linear[bytes[3 * i + 1]], to_linear[bytes[3 * i + 2]]);
  }
  return image;
}

}  // namespace penumbra
