#include "penumbra/scene/pbrt_tokenizer.h"

#include <utility>

#include "penumbra/core/error.h"

namespace penumbra {

std::string PbrtLoc::str() const {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

void PbrtLoc::fail(const std::string& problem) const {
  throw InputError(file, std::to_string(line) + ":" + std::to_string(column), problem);
}

std::string PbrtToken::describe() const {
  switch (kind) {
    case Kind::kWord:
      return text;
    case Kind::kString:
      return "\"" + text + "\"";
    case Kind::kOpen:
      return "'['";
    case Kind::kClose:
      return "']'";
    case Kind::kEnd:
      break;
  }
  return "end of file";
}

PbrtTokenizer::PbrtTokenizer(std::string text, std::string file)
    : text_(std::move(text)), file_(std::move(file)) {}

PbrtToken PbrtTokenizer::next() {
  if (peeked_) {
    peeked_ = false;
    return std::move(lookahead_);
  }
  return scan();
}

const PbrtToken& PbrtTokenizer::peek() {
  if (!peeked_) {
    lookahead_ = scan();
    peeked_ = true;
  }
  return lookahead_;
}

void PbrtTokenizer::skip_space_and_comments() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      line_start_ = ++pos_;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++pos_;
    } else if (c == '#') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      return;
    }
  }
}

PbrtToken PbrtTokenizer::scan() {
  skip_space_and_comments();
  PbrtToken t;
  t.loc = here();
  if (pos_ >= text_.size()) return t;  // kEnd
  const char c = text_[pos_];
  if (c == '[' || c == ']') {
    t.kind = c == '[' ? PbrtToken::Kind::kOpen : PbrtToken::Kind::kClose;
    ++pos_;
    return t;
  }
  if (c == '"') {
    // A quoted string on one line, with pbrt's escapes \b \f \n \r \t \\ \' \".
    t.kind = PbrtToken::Kind::kString;
    ++pos_;
    while (true) {
      if (pos_ >= text_.size() || text_[pos_] == '\n')
        t.loc.fail("unterminated string (a string must close on the line it opens)");
      char d = text_[pos_++];
      if (d == '"') break;
      if (d == '\\') {
        if (pos_ >= text_.size()) t.loc.fail("unterminated string");
        const PbrtLoc at = here();
        switch (const char e = text_[pos_++]) {
          case 'b':
            d = '\b';
            break;
          case 'f':
            d = '\f';
            break;
          case 'n':
            d = '\n';
            break;
          case 'r':
            d = '\r';
            break;
          case 't':
            d = '\t';
            break;
          case '\\':
          case '\'':
          case '"':
            d = e;
            break;
          default:
            at.fail(std::string("unknown escape sequence '\\") + e + "' in a string");
        }
      }
      t.text += d;
    }
    return t;
  }
  // A word runs to the next space, quote, bracket or comment.
  t.kind = PbrtToken::Kind::kWord;
  const size_t start = pos_;
  while (pos_ < text_.size()) {
    const char d = text_[pos_];
    if (d == ' ' || d == '\t' || d == '\r' || d == '\n' || d == '\f' || d == '\v' || d == '"' ||
        d == '[' || d == ']' || d == '#')
      break;
    ++pos_;
  }
  t.text = text_.substr(start, pos_ - start);
  return t;
}

}  // namespace penumbra
