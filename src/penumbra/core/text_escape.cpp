#include "penumbra/core/text_escape.h"

#include <cstdint>

namespace penumbra {
namespace {

// Length of the valid UTF-8 sequence starting at text[i] (1 to 4), or 0 if there is none.
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<std::uint8_t>(text[k]); };
  const std::uint8_t b = byte(i);
  std::size_t n = 0;
  if (b >= 0xc2 && b <= 0xdf) {
    n = 2;
  } else if (b >= 0xe0 && b <= 0xef) {
    n = 3;
  } else if (b >= 0xf0 && b <= 0xf4) {
    n = 4;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xc0) != 0x80) return 0;
  }
  // Overlong forms, surrogates and values above U+10FFFF.
  const std::uint8_t c = byte(i + 1);
  if ((b == 0xe0 && c < 0xa0) || (b == 0xed && c > 0x9f) || (b == 0xf0 && c < 0x90) ||
      (b == 0xf4 && c > 0x8f)) {
    return 0;
  }
  // C1 control characters (U+0080 to U+009F) are control bytes too.
  if (b == 0xc2 && c < 0xa0) return 0;
  return n;
}

bool is_text_control(std::uint8_t b) {
  return (b < 0x20 && b != '\t' && b != '\n' && b != '\v' && b != '\f' && b != '\r') || b == 0x7f;
}

std::string hex_byte(std::uint8_t b) {
  constexpr char kDigits[] = "0123456789abcdef";
  return {'0', 'x', kDigits[b >> 4], kDigits[b & 15]};
}

}  // namespace

std::string escape_for_message(std::string_view text, std::size_t max_bytes) {
  const std::string_view shown = text.substr(0, max_bytes);
  std::string out;
  out.reserve(shown.size() + 16);
  for (std::size_t i = 0; i < shown.size();) {
    const auto b = static_cast<std::uint8_t>(shown[i]);
    if (b >= 0x20 && b < 0x7f) {
      out += shown[i++];
      continue;
    }
    const std::size_t n = b >= 0x80 ? utf8_length(shown, i) : 0;
    if (n > 0) {
      out.append(shown.substr(i, n));
      i += n;
    } else {
      out += "\\x" + hex_byte(b).substr(2);
      ++i;
    }
  }
  if (text.size() > max_bytes) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

std::optional<std::string> describe_non_text(std::string_view data) {
  const auto byte = [&](std::size_t k) { return static_cast<std::uint8_t>(data[k]); };
  // Byte order marks, then the NUL pattern of BOM-less UTF-16 / UTF-32 ASCII text.
  if (data.size() >= 4 && ((byte(0) == 0xff && byte(1) == 0xfe && byte(2) == 0 && byte(3) == 0) ||
                           (byte(0) == 0 && byte(1) == 0 && byte(2) == 0xfe && byte(3) == 0xff))) {
    return "UTF-32 text: convert to UTF-8";
  }
  if (data.size() >= 2 &&
      ((byte(0) == 0xff && byte(1) == 0xfe) || (byte(0) == 0xfe && byte(1) == 0xff))) {
    return "UTF-16 text: convert to UTF-8";
  }
  if (data.size() >= 4 && byte(0) != 0 && byte(1) == 0 && byte(2) != 0 && byte(3) == 0) {
    return "UTF-16 text: convert to UTF-8";
  }
  if (data.size() >= 4 && byte(0) == 0 && byte(1) != 0 && byte(2) == 0 && byte(3) != 0) {
    return "UTF-16 text: convert to UTF-8";
  }
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (is_text_control(byte(i))) {
      return "binary data at byte " + std::to_string(i) + " (" + hex_byte(byte(i)) +
             "): expected text";
    }
  }
  return std::nullopt;
}

}  // namespace penumbra
