/// JPEG reading and writing with libjpeg. libjpeg's default error handler prints and calls exit();
/// ours copies the message and longjmps back. As in png.cpp, every setjmp sits in a function whose
/// locals are all trivial, so the jump never skips a C++ destructor, and the libjpeg structures
/// are destroyed by their owner after the jump.
#include "penumbra/image/jpeg.h"

// jpeglib.h needs FILE and size_t declared first.
#include <cstdio>
#include <cstdlib>

#include <jpeglib.h>

#include <csetjmp>
#include <cstdint>
#include <vector>

#include "penumbra/core/input_file.h"
#include "penumbra/image/tone_map.h"

namespace penumbra {
namespace {

// Progressive files may hold any number of scans, each a pass over the whole image: a small file
// with thousands of scans takes minutes to decode. TurboJPEG's TJFLAG_LIMITSCANS bound.
constexpr int kMaxScans = 500;

// libjpeg's error manager with the jump target and the message of the first error.
struct JpegErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char text[JMSG_LENGTH_MAX] = "unknown libjpeg error";
};

void on_jpeg_error(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  (*info->err->format_message)(info, errors->text);
  std::longjmp(errors->jump, 1);
}

// Warnings (corrupt data that libjpeg recovers from) are not printed; the image is kept.
void on_jpeg_message(j_common_ptr, int) {}

// Stops a progressive decode after kMaxScans scans.
void on_jpeg_progress(j_common_ptr info) {
  auto* d = reinterpret_cast<j_decompress_ptr>(info);
  if (d->progressive_mode && d->input_scan_number > kMaxScans) {
    auto* errors = reinterpret_cast<JpegErrors*>(info->err);
    std::snprintf(errors->text, sizeof(errors->text), "more than %d progressive scans", kMaxScans);
    std::longjmp(errors->jump, 1);
  }
}

// Owns a decompressor with our error manager and progress monitor.
struct JpegReader {
  JpegReader() {
    info.err = jpeg_std_error(&errors.mgr);
    errors.mgr.error_exit = on_jpeg_error;
    errors.mgr.emit_message = on_jpeg_message;
    progress.progress_monitor = on_jpeg_progress;
  }
  ~JpegReader() { jpeg_destroy_decompress(&info); }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  jpeg_decompress_struct info{};
  JpegErrors errors;
  jpeg_progress_mgr progress{};
};

// Creates the decompressor and reads the header, asking for 8-bit RGB; false on error.
bool jpeg_read_header_rgb(JpegReader* r, const unsigned char* data, unsigned long size) {
  if (setjmp(r->errors.jump)) return false;
  jpeg_create_decompress(&r->info);
  r->info.progress = &r->progress;
  jpeg_mem_src(&r->info, data, size);
  jpeg_read_header(&r->info, TRUE);
  r->info.out_color_space = JCS_RGB;
  return true;
}

// Decodes every row into `rows` (height pointers to width * 3 bytes); false on error.
bool jpeg_read_rows(JpegReader* r, unsigned char** rows) {
  if (setjmp(r->errors.jump)) return false;
  jpeg_start_decompress(&r->info);
  if (r->info.output_components != 3) {
    std::snprintf(r->errors.text, sizeof(r->errors.text), "%d output components, not 3",
                  r->info.output_components);
    return false;
  }
  while (r->info.output_scanline < r->info.output_height)
    jpeg_read_scanlines(&r->info, rows + r->info.output_scanline,
                        r->info.output_height - r->info.output_scanline);
  jpeg_finish_decompress(&r->info);
  return true;
}

// Owns a compressor with our error manager.
struct JpegWriter {
  JpegWriter() {
    info.err = jpeg_std_error(&errors.mgr);
    errors.mgr.error_exit = on_jpeg_error;
    errors.mgr.emit_message = on_jpeg_message;
  }
  ~JpegWriter() {
    jpeg_destroy_compress(&info);
    std::free(out);  // jpeg_mem_dest's buffer, malloc'ed by libjpeg
  }
  JpegWriter(const JpegWriter&) = delete;
  JpegWriter& operator=(const JpegWriter&) = delete;

  jpeg_compress_struct info{};
  JpegErrors errors;
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
};

// Compresses width x height RGB rows; false on error.
bool jpeg_write_all(JpegWriter* w, int width, int height, int quality, unsigned char** rows) {
  if (setjmp(w->errors.jump)) return false;
  jpeg_create_compress(&w->info);
  jpeg_mem_dest(&w->info, &w->out, &w->out_size);
  w->info.image_width = JDIMENSION(width);
  w->info.image_height = JDIMENSION(height);
  w->info.input_components = 3;
  w->info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&w->info);
  jpeg_set_quality(&w->info, quality, TRUE);
  if (quality >= 90)  // no chroma subsampling: small test images keep their colours
    for (int c = 0; c < 3; ++c)
      w->info.comp_info[c].h_samp_factor = 1, w->info.comp_info[c].v_samp_factor = 1;
  jpeg_start_compress(&w->info, TRUE);
  while (w->info.next_scanline < w->info.image_height)
    jpeg_write_scanlines(&w->info, rows + w->info.next_scanline,
                         w->info.image_height - w->info.next_scanline);
  jpeg_finish_compress(&w->info);
  return true;
}

}  // namespace

RgbImage read_jpeg(const std::string& path) {
  return decode_jpeg(read_input_file(path), path);
}

RgbImage decode_jpeg(std::string_view bytes, const std::string& name, std::size_t max_pixels) {
  if (bytes.empty()) throw InputError(name, "", "empty file (0 bytes), not a JPEG");
  if (bytes.size() < 3 || static_cast<unsigned char>(bytes[0]) != 0xFF ||
      static_cast<unsigned char>(bytes[1]) != 0xD8)
    throw InputError(name, "byte 0", "not a JPEG file (no start-of-image marker)");
  if (bytes.size() > 0xFFFFFFFFu) throw InputError(name, "", "JPEG larger than 4 GiB");
  JpegReader reader;
  if (!jpeg_read_header_rgb(&reader, reinterpret_cast<const unsigned char*>(bytes.data()),
                            static_cast<unsigned long>(bytes.size())))
    throw InputError(name, "", std::string("invalid JPEG: ") + reader.errors.text);
  const std::uint64_t width = reader.info.image_width, height = reader.info.image_height;
  if (width * height > max_pixels)
    throw InputError(name, "",
                     "JPEG of " + std::to_string(width) + " x " + std::to_string(height) +
                         " pixels is larger than the limit of " + std::to_string(max_pixels));
  if (width == 0 || height == 0) throw InputError(name, "", "JPEG of no pixels");

  // Decode to 8-bit rows (the output size equals the image size: no scaling is asked for).
  const std::size_t stride = std::size_t(width) * 3;
  std::vector<unsigned char> pixels(stride * height);
  std::vector<unsigned char*> rows(height);
  for (std::size_t y = 0; y < height; ++y) rows[y] = pixels.data() + stride * y;
  if (!jpeg_read_rows(&reader, rows.data()))
    throw InputError(name, "", std::string("invalid JPEG: ") + reader.errors.text);

  // 8-bit sRGB codes to linear values through a table.
  float to_linear[256];
  for (int i = 0; i < 256; ++i) to_linear[i] = srgb_decode(static_cast<float>(i) / 255.0f);
  RgbImage image(static_cast<int>(width), static_cast<int>(height));
  for (std::size_t i = 0; i < image.size(); ++i)
    image.data()[i] =
        Rgb(to_linear[pixels[3 * i]], to_linear[pixels[3 * i + 1]], to_linear[pixels[3 * i + 2]]);
  return image;
}

std::string encode_jpeg(const RgbImage& image, int quality) {
  if (image.empty()) throw Error("cannot encode an empty image as JPEG");
  if (quality < 1 || quality > 100) throw Error("JPEG quality must lie in [1, 100]");
  const std::size_t stride = static_cast<std::size_t>(image.width()) * 3;
  std::vector<unsigned char> bytes(stride * image.height());
  std::vector<unsigned char*> rows(image.height());
  for (int y = 0; y < image.height(); ++y) {
    rows[y] = bytes.data() + stride * y;
    const Rgb* pixels = image.row(y);
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) rows[y][3 * x + c] = srgb_encode_8bit(pixels[x][c]);
  }
  JpegWriter writer;
  if (!jpeg_write_all(&writer, image.width(), image.height(), quality, rows.data()))
    throw Error(std::string("cannot encode JPEG: ") + writer.errors.text);
  return std::string(reinterpret_cast<const char*>(writer.out), writer.out_size);
}

}  // namespace penumbra
