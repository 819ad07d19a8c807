#pragma once
// Writes PLY test data in any of the three formats (ascii, binary little- and big-endian), so one
// description gives byte-exact variants. Shared by the PLY reader's tests.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace penumbra::test {

enum class Format { kAscii, kLittle, kBig };

/// Writes PLY data in any of the three formats, so one description gives byte-exact variants.
class PlyWriter {
 public:
  explicit PlyWriter(Format format) : format_(format) {}

  /// Header lines after the magic and format lines, ending the header.
  void header(const std::string& lines) {
    static const char* kNames[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    out_ = "ply\nformat " + std::string(kNames[static_cast<int>(format_)]) + " 1.0\n" + lines +
           "end_header\n";
  }

  /// Appends one value of the PLY scalar type `type`.
  void put(std::string type, double value) {
    const std::string sized[] = {"int8", "uint8", "int16", "uint16", "int32", "uint32", "float32"};
    const std::string classic[] = {"char", "uchar", "short", "ushort", "int", "uint", "float"};
    for (int i = 0; i < 7; ++i) {
      if (type == sized[i]) type = classic[i];
    }
    if (format_ == Format::kAscii) {
      char text[64];
      std::snprintf(text, sizeof(text), "%.17g ", value);
      out_ += text;
    } else if (type == "char") {
      bytes(static_cast<int8_t>(value));
    } else if (type == "uchar") {
      bytes(static_cast<uint8_t>(value));
    } else if (type == "short") {
      bytes(static_cast<int16_t>(value));
    } else if (type == "ushort") {
      bytes(static_cast<uint16_t>(value));
    } else if (type == "int") {
      bytes(static_cast<int32_t>(value));
    } else if (type == "uint") {
      bytes(static_cast<uint32_t>(value));
    } else if (type == "float") {
      bytes(static_cast<float>(value));
    } else {
      bytes(value);
    }
  }

  /// Appends a list: its count, then its items.
  void list(const std::string& count_type, const std::string& type, std::vector<double> items) {
    put(count_type, static_cast<double>(items.size()));
    for (double v : items) put(type, v);
  }

  /// Ends one element item (a newline in ascii).
  void end_item() {
    if (format_ == Format::kAscii) out_.back() = '\n';
  }

  const std::string& data() const { return out_; }

 private:
  template <class T>
  void bytes(T value) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (format_ == Format::kBig) std::reverse(b, b + sizeof(T));  // the tests run little-endian
    out_.append(b, sizeof(T));
  }

  Format format_;
  std::string out_;
};

}  // namespace penumbra::test
