/// PFM reading and writing; format as described by Paul Debevec's HDR Shop notes and Netpbm.
#include "penumbra/image/pfm.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include "penumbra/core/input_file.h"
#include "penumbra/core/output_file.h"

namespace penumbra {
namespace {

// Longest header accepted; real headers are about 20 bytes.
constexpr std::size_t kMaxHeaderBytes = 256;

struct PfmHeader {
  int channels = 3;
  int width = 0;
  int height = 0;
  bool little_endian = true;
  std::size_t data_offset = 0;  // first byte of pixel data
};

std::string byte_place(std::size_t offset) {
  return "byte " + std::to_string(offset);
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

std::uint32_t byte_swap(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

// Cuts the header bytes into whitespace-separated tokens, remembering where each starts.
class HeaderTokens {
 public:
  HeaderTokens(const std::string& path, const std::string& bytes, bool whole_file)
      : path_(path), bytes_(bytes), whole_file_(whole_file) {}

  // The next token; pos_ is left on the byte after it.
  std::string_view next(const char* what, std::size_t* start) {
    while (pos_ < bytes_.size() && is_space(bytes_[pos_])) ++pos_;
    *start = pos_;
    while (pos_ < bytes_.size() && !is_space(bytes_[pos_])) ++pos_;
    if (pos_ == bytes_.size()) fail_at_end(what);
    return std::string_view(bytes_).substr(*start, pos_ - *start);
  }

  // Offset of the byte just after the single whitespace byte that ends the header.
  std::size_t data_offset() const { return pos_ + 1; }

 private:
  [[noreturn]] void fail_at_end(const char* what) const {
    if (whole_file_) throw InputError(path_, byte_place(pos_), std::string("file ends in ") + what);
    throw InputError(path_, byte_place(pos_),
                     "header longer than " + std::to_string(kMaxHeaderBytes) + " bytes");
  }

  const std::string& path_;
  const std::string& bytes_;
  bool whole_file_;
  std::size_t pos_ = 0;
};

// A positive decimal integer that fits in an int, or InputError.
int parse_dimension(const std::string& path, std::string_view token, std::size_t offset,
                    const char* what) {
  std::uint64_t value = 0;
  const bool digits_only =
      !token.empty() && token.size() <= 10 && token.find_first_not_of("0123456789") == token.npos;
  if (digits_only) std::from_chars(token.data(), token.data() + token.size(), value);
  if (!digits_only || value == 0 || value > 0x7fffffffu) {
    throw InputError(path, byte_place(offset),
                     std::string(what) + " '" + std::string(token) + "' is not a positive integer");
  }
  return static_cast<int>(value);
}

PfmHeader parse_header(const std::string& path, const std::string& bytes, bool whole_file) {
  PfmHeader header;
  HeaderTokens tokens(path, bytes, whole_file);
  std::size_t at = 0;

  // Magic: "PF" (colour) or "Pf" (greyscale), checked before any tokenising.
  const std::string_view prefix = std::string_view(bytes).substr(0, 3);
  if (prefix.size() < 3 || (prefix.substr(0, 2) != "PF" && prefix.substr(0, 2) != "Pf") ||
      !is_space(prefix[2])) {
    throw InputError(path, byte_place(0), "not a PFM file (magic number must be \"PF\" or \"Pf\")");
  }
  const std::string_view magic = tokens.next("the magic number", &at);
  header.channels = magic == "PF" ? 3 : 1;

  // Dimensions, bounded before anything is allocated.
  std::size_t width_at = 0;
  const std::string_view width = tokens.next("the width", &width_at);
  header.width = parse_dimension(path, width, width_at, "width");
  const std::string_view height = tokens.next("the height", &at);
  header.height = parse_dimension(path, height, at, "height");
  if (static_cast<std::uint64_t>(header.width) * static_cast<std::uint64_t>(header.height) >
      kMaxImagePixels) {
    throw InputError(path, byte_place(width_at),
                     std::to_string(header.width) + " x " + std::to_string(header.height) +
                         " pixels is more than the limit of 2^28");
  }

  // Scale: its sign gives the byte order, its magnitude is ignored.
  const std::string_view scale_token = tokens.next("the scale", &at);
  float scale = 0.0f;
  const auto [end, ec] =
      std::from_chars(scale_token.data(), scale_token.data() + scale_token.size(), scale);
  if (ec != std::errc() || end != scale_token.data() + scale_token.size() ||
      !std::isfinite(scale) || scale == 0.0f) {
    throw InputError(path, byte_place(at),
                     "scale '" + std::string(scale_token) + "' is not a non-zero number");
  }
  header.little_endian = scale < 0.0f;
  header.data_offset = tokens.data_offset();
  return header;
}

}  // namespace

std::string encode_pfm(const RgbImage& image) {
  if (image.empty()) throw Error("cannot encode an empty image as PFM");
  std::string out =
      "PF\n" + std::to_string(image.width()) + ' ' + std::to_string(image.height()) + "\n-1.0\n";
  const std::size_t header = out.size();
  out.resize(header + std::size_t(image.width()) * std::size_t(image.height()) * 12);
  // Rows from the bottom of the picture up, each as little-endian floats.
  char* at = out.data() + header;
  for (int y = image.height() - 1; y >= 0; --y) {
    const Rgb* pixels = image.row(y);
    for (int x = 0; x < image.width(); ++x) {
      for (int c = 0; c < 3; ++c) {
        std::uint32_t bits = std::bit_cast<std::uint32_t>(pixels[x][c]);
        if constexpr (std::endian::native != std::endian::little) bits = byte_swap(bits);
        std::memcpy(at, &bits, 4);
        at += 4;
      }
    }
  }
  return out;
}

void write_pfm(const RgbImage& image, const std::string& path) {
  if (image.empty()) throw Error(path + ": cannot write an empty image");
  write_output_file(path, encode_pfm(image));
}

RgbImage read_pfm(const std::string& path) {
  return decode_pfm(read_input_file(path), path);
}

RgbImage decode_pfm(std::string_view bytes, const std::string& path, std::size_t max_pixels) {
  const std::size_t file_size = bytes.size();

  // Header: at most kMaxHeaderBytes are parsed.
  const std::string head(bytes.substr(0, std::min(file_size, kMaxHeaderBytes)));
  const PfmHeader header = parse_header(path, head, head.size() == file_size);
  if (std::uint64_t{static_cast<std::uint32_t>(header.width)} *
          static_cast<std::uint32_t>(header.height) >
      max_pixels) {
    throw InputError(path, byte_place(3),
                     std::to_string(header.width) + " x " + std::to_string(header.height) +
                         " pixels is more than the limit of " + std::to_string(max_pixels));
  }

  // Pixel data: the whole block must be present before the image is allocated.
  const std::size_t row_floats = static_cast<std::size_t>(header.width) * header.channels;
  const std::size_t data_bytes = row_floats * header.height * sizeof(float);
  const std::size_t available = file_size - std::min(file_size, header.data_offset);
  if (available < data_bytes) {
    throw InputError(path, byte_place(file_size),
                     "file ends after " + std::to_string(available) + " of " +
                         std::to_string(data_bytes) + " bytes of pixel data (which start at byte " +
                         std::to_string(header.data_offset) + ")");
  }

  if (available > data_bytes) {
    throw InputError(
        path, byte_place(header.data_offset + data_bytes),
        std::to_string(available - data_bytes) + " bytes of trailing data after the pixel data");
  }

  RgbImage image(header.width, header.height);
  const bool swap = header.little_endian != (std::endian::native == std::endian::little);
  const char* data = bytes.data() + header.data_offset;
  for (int y = header.height - 1; y >= 0; --y, data += row_floats * sizeof(float)) {
    Rgb* pixels = image.row(y);
    for (std::size_t i = 0; i < row_floats; ++i) {
      std::uint32_t bits = 0;
      std::memcpy(&bits, data + i * sizeof(float), sizeof(bits));
      const float value = std::bit_cast<float>(swap ? byte_swap(bits) : bits);
      if (header.channels == 1) {
        pixels[i] = Rgb(value);
      } else {
        pixels[i / 3][static_cast<int>(i % 3)] = value;
      }
    }
  }
  return image;
}

}  // namespace penumbra
