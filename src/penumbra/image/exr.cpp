/// EXR reading and writing with OpenEXR's general InputFile/OutputFile frame-buffer interface.
#include "penumbra/image/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <IexBaseExc.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <utility>

#include "penumbra/core/input_file.h"
#include "penumbra/core/output_file.h"

namespace penumbra {
namespace {

static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb must be three packed floats");

// Describes one float channel of image's pixels (channel 0, 1, 2 = r, g, b) to OpenEXR.
Imf::Slice rgb_slice(const Rgb* pixels, int channel, const Imath::Box2i& window) {
  const char* base = reinterpret_cast<const char*>(pixels) + channel * sizeof(float);
  return Imf::Slice::Make(Imf::FLOAT, base, window, sizeof(Rgb),
                          sizeof(Rgb) * static_cast<std::size_t>(window.max.x - window.min.x + 1));
}

// EXR bytes held in memory, as OpenEXR's input stream; reading past the end throws as its file
// streams do.
class MemoryStream : public Imf::IStream {
 public:
  MemoryStream(std::string_view bytes, const std::string& name)
      : Imf::IStream(name.c_str()), bytes_(bytes) {}

  bool read(char c[], int n) override {
    if (n < 0 || static_cast<std::uint64_t>(n) > bytes_.size() - pos_) {
      throw Iex::InputExc("unexpected end of file");
    }
    std::memcpy(c, bytes_.data() + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::uint64_t>(n);
    return pos_ < bytes_.size();
  }
  std::uint64_t tellg() override { return pos_; }
  void seekg(std::uint64_t pos) override { pos_ = std::min<std::uint64_t>(pos, bytes_.size()); }

 private:
  std::string_view bytes_;
  std::uint64_t pos_ = 0;
};

// OpenEXR's output stream into a string: OutputFile writes the line-offset table in its
// destructor and swallows any error there, so it writes to memory (which cannot fail) and the
// bytes are written to the file afterwards, every write checked.
class StringStream : public Imf::OStream {
 public:
  StringStream() : Imf::OStream("memory") {}
  void write(const char c[], int n) override {
    if (n < 0) throw Iex::ArgExc("negative write");
    const std::uint64_t end = pos_ + std::uint64_t(n);
    if (end > bytes_.size()) bytes_.resize(end);
    std::memcpy(bytes_.data() + pos_, c, std::size_t(n));
    pos_ = end;
  }
  std::uint64_t tellp() override { return pos_; }
  void seekp(std::uint64_t pos) override { pos_ = pos; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
  std::uint64_t pos_ = 0;
};

// Reads the little-endian int32 at bytes[pos].
std::int32_t load_int32(std::string_view bytes, std::size_t pos) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<std::uint8_t>(bytes[pos + i]);
  return static_cast<std::int32_t>(v);
}

// Bytes of the attribute types whose OpenEXR reader reads a fixed size whatever size the file
// declares (ImfStandardAttributes, OpenEXR 3.1); 0 for the others.
std::size_t fixed_size(std::string_view type) {
  static constexpr std::pair<std::string_view, std::size_t> kSizes[] = {
      {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
      {"compression", 1}, {"double", 8},   {"envmap", 1},
      {"float", 4},       {"int", 4},      {"keycode", 28},
      {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
      {"m44f", 64},       {"m44d", 128},   {"rational", 8},
      {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
      {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
      {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
  for (const auto& [name, size] : kSizes) {
    if (name == type) return size;
  }
  return 0;
}

// Walks the headers of an EXR (magic, version, then per part: attributes "name\0type\0size
// value", ended by a NUL) as OpenEXR reads them, before it does. OpenEXR allocates what an
// attribute's size (or a preview's dimensions) say before it reads the data, so a 468-byte file
// could ask for 1.6 GB (fuzz findings, issue #18). An attribute larger than the bytes that follow,
// one whose content does not fill its declared size, or a data window of more than max_pixels is
// an InputError naming the byte offset.
void check_exr_headers(std::string_view bytes, const std::string& path, std::size_t max_pixels) {
  const auto fail = [&](std::size_t at, const std::string& problem) {
    throw InputError(path, "byte " + std::to_string(at), problem);
  };
  if (bytes.size() < 8 || load_int32(bytes, 0) != 20000630) {
    fail(0, "not an OpenEXR file (bad magic number)");
  }
  const bool multipart = (load_int32(bytes, 4) & 0x1000) != 0;
  // A NUL-terminated string of at most 255 bytes at pos; pos moves past it.
  const auto read_string = [&](std::size_t& pos, const char* what) {
    const std::size_t end = bytes.find('\0', pos);
    if (end == std::string_view::npos || end - pos > 255) fail(pos, std::string("bad ") + what);
    const std::string_view s = bytes.substr(pos, end - pos);
    pos = end + 1;
    return s;
  };
  // The bytes a channel list starting at pos takes (names and 16 bytes each, then a NUL).
  const auto channel_list_size = [&](std::size_t start) {
    std::size_t pos = start;
    for (;;) {
      if (pos >= bytes.size()) fail(pos, "file ends in the channel list");
      if (read_string(pos, "channel name").empty()) return pos - start;
      if (bytes.size() - pos < 16) fail(pos, "file ends in the channel list");
      pos += 16;
    }
  };
  std::size_t pos = 8;
  for (int part = 0;; ++part) {
    if (pos >= bytes.size()) fail(pos, "file ends in the header");
    if (part > 0 && bytes[pos] == '\0') return;  // the empty header after the last part
    std::uint64_t window_width = 0, tile_x = 0, tile_y = 0;
    std::size_t tiles_at = 0;
    while (bytes[pos] != '\0') {
      const std::string_view name = read_string(pos, "attribute name");
      const std::string_view type = read_string(pos, "attribute type");
      if (bytes.size() - pos < 4) fail(pos, "file ends in the header");
      const std::int32_t size = load_int32(bytes, pos);
      pos += 4;
      if (size < 0 || static_cast<std::size_t>(size) > bytes.size() - pos) {
        fail(pos - 4, "attribute '" + std::string(name) + "' (" + std::string(type) +
                          ") declares " + std::to_string(size) + " bytes, but only " +
                          std::to_string(bytes.size() - pos) + " follow");
      }
      // The size OpenEXR will actually read must be the declared one.
      const std::size_t fixed = fixed_size(type);
      std::size_t content = fixed;
      if (type == "chlist") content = channel_list_size(pos);
      if (type == "preview") {
        const std::uint64_t w = size >= 8 ? static_cast<std::uint32_t>(load_int32(bytes, pos)) : 0;
        const std::uint64_t h =
            size >= 8 ? static_cast<std::uint32_t>(load_int32(bytes, pos + 4)) : 0;
        content = w * h <= bytes.size() ? static_cast<std::size_t>(8 + 4 * w * h) : SIZE_MAX;
      }
      if (content != 0 && content != static_cast<std::size_t>(size)) {
        fail(pos - 4, "attribute '" + std::string(name) + "' (" + std::string(type) + ") holds " +
                          (content == SIZE_MAX ? std::string("more") : std::to_string(content)) +
                          " bytes but declares " + std::to_string(size));
      }
      if (name == "dataWindow" && type == "box2i") {
        const std::int64_t width =
            std::int64_t{load_int32(bytes, pos + 8)} - load_int32(bytes, pos) + 1;
        const std::int64_t height =
            std::int64_t{load_int32(bytes, pos + 12)} - load_int32(bytes, pos + 4) + 1;
        if (width <= 0 || height <= 0 ||
            static_cast<std::uint64_t>(width) > max_pixels / static_cast<std::uint64_t>(height)) {
          fail(pos, "data window of " + std::to_string(width) + " x " + std::to_string(height) +
                        " pixels is empty or larger than the limit of " +
                        std::to_string(max_pixels));
        }
        window_width = static_cast<std::uint64_t>(width);
      }
      if (name == "tiles" && type == "tiledesc") {
        tile_x = static_cast<std::uint32_t>(load_int32(bytes, pos));
        tile_y = static_cast<std::uint32_t>(load_int32(bytes, pos + 4));
        tiles_at = pos;
      }
      pos += static_cast<std::size_t>(size);
      if (pos >= bytes.size()) fail(pos, "file ends in the header");
    }
    // OpenEXR buffers a tile, and a row of tiles as wide as the data window, before reading.
    if (tiles_at != 0 && (tile_x == 0 || tile_y == 0 || tile_x > max_pixels / tile_y ||
                          window_width > max_pixels / tile_y)) {
      fail(tiles_at, "tiles of " + std::to_string(tile_x) + " x " + std::to_string(tile_y) +
                         " pixels are empty or too large for the limit of " +
                         std::to_string(max_pixels) + " pixels");
    }
    ++pos;  // the NUL that ends this header
    if (!multipart) return;
  }
}

}  // namespace

std::string encode_exr(const RgbImage& image) {
  if (image.empty()) throw Error("cannot encode an empty image as EXR");
  StringStream stream;
  try {
    Imf::Header header(image.width(), image.height());
    header.compression() = Imf::ZIP_COMPRESSION;
    static constexpr const char* kNames[3] = {"R", "G", "B"};
    Imf::FrameBuffer frame;
    for (int c = 0; c < 3; ++c) {
      header.channels().insert(kNames[c], Imf::Channel(Imf::FLOAT));
      frame.insert(kNames[c], rgb_slice(image.data(), c, header.dataWindow()));
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height());
  } catch (const std::exception& e) {
    throw Error(std::string("cannot encode EXR: ") + e.what());
  }
  return stream.take();
}

void write_exr(const RgbImage& image, const std::string& path) {
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  std::string bytes;
  try {
    bytes = encode_exr(image);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  write_output_file(path, bytes);
}

RgbImage read_exr(const std::string& path) {
  return decode_exr(read_input_file(path), path);
}

RgbImage decode_exr(std::string_view bytes, const std::string& path, std::size_t max_pixels) {
  if (bytes.empty()) throw InputError(path, "", "empty file (0 bytes), not an EXR");
  check_exr_headers(bytes, path, max_pixels);
  try {
    MemoryStream stream(bytes, path);
    Imf::InputFile file(stream);
    const Imath::Box2i window = file.header().dataWindow();
    const std::int64_t width = std::int64_t{window.max.x} - window.min.x + 1;
    const std::int64_t height = std::int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0 ||
        static_cast<std::uint64_t>(width) > max_pixels / static_cast<std::uint64_t>(height)) {
      throw InputError(path, "",
                       "data window of " + std::to_string(width) + " x " + std::to_string(height) +
                           " pixels is empty or too large");
    }

    // Choose the source channel for r, g, b: R/G/B, or Y for all three.
    const Imf::ChannelList& channels = file.header().channels();
    const bool has_rgb =
        channels.findChannel("R") || channels.findChannel("G") || channels.findChannel("B");
    if (!has_rgb && !channels.findChannel("Y")) {
      throw InputError(path, "", "no R, G, B or Y channel");
    }
    static constexpr const char* kRgb[3] = {"R", "G", "B"};

    RgbImage image(static_cast<int>(width), static_cast<int>(height));
    Imf::FrameBuffer frame;
    frame.insert(has_rgb ? kRgb[0] : "Y", rgb_slice(image.data(), 0, window));
    if (has_rgb) {
      frame.insert(kRgb[1], rgb_slice(image.data(), 1, window));
      frame.insert(kRgb[2], rgb_slice(image.data(), 2, window));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (!has_rgb) {
      for (std::size_t i = 0; i < image.size(); ++i) image.data()[i] = Rgb(image.data()[i].r);
    }
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace penumbra
