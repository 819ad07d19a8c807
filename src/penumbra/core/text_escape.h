#pragma once
/// Quoting outside text in messages: control bytes and bytes that are not UTF-8 are escaped, long
/// tokens are cut, and binary or UTF-16 data is recognised, so an error never prints raw bytes.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace penumbra {

/// `text` for a message: control bytes (and bytes that are not part of valid UTF-8) as `\xNN`;
/// at most `max_bytes` bytes of it are shown, then "... (N bytes)".
std::string escape_for_message(std::string_view text, std::size_t max_bytes = 40);

/// Why `data` is not text, if it is not: "UTF-16 text: convert to UTF-8" (a UTF-16 byte order
/// mark, or NUL bytes in every other position), "UTF-32 text: ...", or "binary data at byte N
/// (0xNN)" for the first control byte other than tab, newline, vertical tab, form feed and
/// carriage return. Nothing for text.
std::optional<std::string> describe_non_text(std::string_view data);

}  // namespace penumbra
