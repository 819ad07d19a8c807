#pragma once
/// The lexical layer of the pbrt-v4 scene format (https://pbrt.org/fileformat-v4): words
/// (directive names, numbers, bare `true`/`false`), quoted strings, `[` and `]`. A `#` starts a
/// comment that runs to the end of the line wherever it appears outside a string, so comments may
/// sit between a directive and its parameters or inside a bracketed list.
#include <string>

namespace penumbra {

/// A place in a pbrt file: file name, 1-based line and column (the column counts bytes).
struct PbrtLoc {
  std::string file;
  int line = 0, column = 0;
  /// "FILE:LINE:COLUMN".
  std::string str() const;
  /// Throws InputError "FILE:LINE:COLUMN: problem".
  [[noreturn]] void fail(const std::string& problem) const;
};

/// One token with the place of its first character.
struct PbrtToken {
  enum class Kind { kWord, kString, kOpen, kClose, kEnd };
  Kind kind = Kind::kEnd;
  std::string text;  ///< a word, or a string's contents with escapes resolved
  PbrtLoc loc;
  /// The token as it would be quoted in a message: `"text"`, `word`, `[`, `]`, "end of file".
  std::string describe() const;
};

/// Splits one file's text into tokens, one at a time.
class PbrtTokenizer {
 public:
  /// Tokenizes `text`, which `file` names in messages.
  PbrtTokenizer(std::string text, std::string file);

  /// The next token (kind kEnd at the end, repeatedly), consumed.
  PbrtToken next();
  /// The next token, not consumed.
  const PbrtToken& peek();
  const std::string& file() const { return file_; }

 private:
  PbrtToken scan();
  void skip_space_and_comments();
  PbrtLoc here() const { return {file_, line_, int(pos_ - line_start_) + 1}; }

  std::string text_, file_;
  size_t pos_ = 0, line_start_ = 0;
  int line_ = 1;
  bool peeked_ = false;
  PbrtToken lookahead_;
};

}  // namespace penumbra
