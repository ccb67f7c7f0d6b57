#include "service/toml_precheck.hpp"

#include <cstdio>
#include <vector>

namespace skyroute {
namespace {

bool isNonAscii(char c) { return static_cast<unsigned char>(c) >= 0x80; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isBareKeyCharacter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || isDigit(c) || c == '_' || c == '-';
}
// What ends a bare value (a number, a boolean, a date) for the library's look-ahead.
bool endsBareValue(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ']' || c == '}' || c == ',' || c == '#';
}

// Where the walk is in TOML's grammar: what the next token may be.
enum class Place {
  kKey,         // a key (or a key segment after '.'), a table header at the start of a line
  kAfterKey,    // '.', '=' or a header's ']'
  kValue,       // a string, a bare value, '[' or '{'
  kAfterValue,  // ',' or a closing bracket, then the end of the line
};

class TomlWalk {
 public:
  TomlWalk(const std::string& text, const std::string& source_name) : text_(text), source_(source_name) {}

  std::optional<Error> run() {
    if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0) i_ = 3;  // a leading byte-order mark, which TOML allows
    while (i_ < text_.size()) {
      if (auto e = blockedCharacter()) return e;
      const char c = text_[i_];
      if (broken_) {
        // The library stops at the malformed place, but its look-ahead may read on from there.
        if (isNonAscii(c)) return broken_error_;
        advance(1);
      } else if (c == ' ' || c == '\t' || c == '\r') {
        advance(1);
      } else if (c == '\n') {
        advance(1);
        if (nesting_.empty()) {
          place_ = Place::kKey;
          header_allowed_ = true;
        }
      } else if (c == '#') {
        while (i_ < text_.size() && text_[i_] != '\n') {
          if (auto e = blockedCharacter()) return e;
          advance(1);
        }
      } else if (isNonAscii(c)) {
        return refuse("a character outside a string or a comment must be ASCII");
      } else {
        const bool header_allowed = header_allowed_;
        header_allowed_ = false;
        if (auto e = token(c, header_allowed)) return e;
      }
    }
    return std::nullopt;
  }

 private:
  std::optional<Error> token(char c, bool header_allowed) {
    const bool quote = c == '"' || c == '\'';
    const char open = nesting_.empty() ? '\0' : nesting_.back();
    switch (place_) {
      case Place::kKey:
        if (c == '[' && header_allowed) {
          advance(text_.compare(i_, 2, "[[") == 0 ? 2 : 1);
          in_header_ = true;
        } else if (c == '}' && open == '{') {  // an empty inline table
          closeNesting();
        } else if (quote) {
          place_ = Place::kAfterKey;
          return string(c);
        } else if (isBareKeyCharacter(c)) {
          while (i_ < text_.size() && isBareKeyCharacter(text_[i_])) advance(1);
          place_ = Place::kAfterKey;
        } else {
          breakHere();
        }
        return std::nullopt;
      case Place::kAfterKey:
        if (c == '.') {
          advance(1);
          place_ = Place::kKey;
        } else if (c == '=' && !in_header_) {
          advance(1);
          place_ = Place::kValue;
        } else if (c == ']' && in_header_) {
          advance(text_.compare(i_, 2, "]]") == 0 ? 2 : 1);
          in_header_ = false;
          place_ = Place::kAfterValue;
        } else {
          breakHere();
        }
        return std::nullopt;
      case Place::kValue:
        if (quote) {
          place_ = Place::kAfterValue;
          return string(c);
        }
        if (c == '[') {
          nesting_.push_back('[');
          advance(1);
        } else if (c == ']' && open == '[') {  // an empty array, or a trailing comma
          closeNesting();
        } else if (c == '{') {
          nesting_.push_back('{');
          advance(1);
          place_ = Place::kKey;
        } else if (!endsBareValue(c)) {
          return bareValue();
        } else {
          breakHere();
        }
        return std::nullopt;
      case Place::kAfterValue:
        if (c == ',' && open != '\0') {
          advance(1);
          place_ = open == '[' ? Place::kValue : Place::kKey;
        } else if ((c == ']' && open == '[') || (c == '}' && open == '{')) {
          closeNesting();
        } else {
          breakHere();
        }
        return std::nullopt;
    }
    return std::nullopt;
  }

  void closeNesting() {
    advance(1);
    nesting_.pop_back();
    place_ = Place::kAfterValue;
  }

  // A number, boolean, date or anything else unquoted: the library reads it up to a terminator and
  // asks of each character whether it is one.
  std::optional<Error> bareValue() {
    const std::size_t begin = i_;
    while (true) {
      while (i_ < text_.size() && !endsBareValue(text_[i_])) {
        if (auto e = blockedCharacter()) return e;
        if (isNonAscii(text_[i_])) return refuse("a character outside a string or a comment must be ASCII");
        advance(1);
      }
      // A date and a time may be separated by one space (1979-05-27 07:32:00).
      const bool date = i_ - begin == 10 && text_[begin + 4] == '-' && text_[begin + 7] == '-';
      if (!date || i_ + 1 >= text_.size() || text_[i_] != ' ' || !isDigit(text_[i_ + 1])) break;
      advance(1);
    }
    place_ = Place::kAfterValue;
    return std::nullopt;
  }

  // From an opening quote past the closing one (or to the end of the text); a basic string's
  // backslash escapes one character. A single-line string also ends at a newline, where the
  // library reports it, so the walk stops trusting its grammar there.
  std::optional<Error> string(char quote) {
    const std::string triple(3, quote);
    const bool multi_line = text_.compare(i_, 3, triple) == 0;
    const bool basic = quote == '"';
    advance(multi_line ? 3 : 1);
    while (i_ < text_.size()) {
      if (auto e = blockedCharacter()) return e;
      const char c = text_[i_];
      if (basic && c == '\\') {
        if (multi_line) {
          if (auto e = nonAsciiAfterBackslash()) return e;
        }
        advance(2);
      } else if (multi_line && text_.compare(i_, 3, triple) == 0) {
        advance(3);
        // Up to two more quotes belong to the string ("""a"""" is a followed by a quote).
        for (int extra = 0; extra < 2 && i_ < text_.size() && text_[i_] == quote; ++extra) advance(1);
        return std::nullopt;
      } else if (!multi_line && c == quote) {
        advance(1);
        return std::nullopt;
      } else if (!multi_line && c == '\n') {
        breakHere();
        return std::nullopt;
      } else {
        advance(1);
      }
    }
    return std::nullopt;
  }

  // In a multi-line basic string the library asks whether the character after a backslash is
  // whitespace, and on a line-ending backslash asks it of each one up to the next non-blank. Such
  // a character is never a valid escape; after a line-ending backslash it can be written \uXXXX.
  std::optional<Error> nonAsciiAfterBackslash() {
    std::size_t j = i_ + 1;
    while (j < text_.size() && (text_[j] == ' ' || text_[j] == '\t' || text_[j] == '\r' || text_[j] == '\n')) ++j;
    if (j >= text_.size() || !isNonAscii(text_[j])) return std::nullopt;
    advance(j - i_);
    return refuse("a non-ASCII character after a backslash in a multi-line string (write it as \\uXXXX)");
  }

  // Where the document stops following TOML's grammar the library reports an error, but only after
  // its look-ahead; from here on any non-ASCII character is refused, naming this place.
  void breakHere() {
    broken_ = true;
    broken_error_ = refuse("malformed TOML here, with non-ASCII text after it");
  }

  // U+FC06..U+FEFE are refused wherever they stand (inside strings too): no key or value of ours
  // needs Arabic presentation forms, and the library's tables mishandle them in several places.
  std::optional<Error> blockedCharacter() const {
    if (i_ + 2 >= text_.size() || static_cast<unsigned char>(text_[i_]) != 0xEF) return std::nullopt;
    const auto b1 = static_cast<unsigned char>(text_[i_ + 1]);
    const auto b2 = static_cast<unsigned char>(text_[i_ + 2]);
    const unsigned code = (0xFu << 12) | ((b1 & 0x3Fu) << 6) | (b2 & 0x3Fu);
    if ((b1 & 0xC0u) != 0x80u || (b2 & 0xC0u) != 0x80u || code < 0xFC06 || code > 0xFEFE) return std::nullopt;
    char hex[8];
    std::snprintf(hex, sizeof hex, "%04X", code);
    return refuse(std::string("character U+") + hex + " is not allowed in a configuration file");
  }

  Error refuse(const std::string& why) const {
    return make_error(ErrorCode::kParseError, source_,
                      source_ + ":" + std::to_string(line_) + ":" + std::to_string(column_) + ": " + why);
  }

  void advance(std::size_t bytes) {
    for (std::size_t k = 0; k < bytes && i_ < text_.size(); ++k, ++i_) {
      const auto byte = static_cast<unsigned char>(text_[i_]);
      if (byte == '\n') {
        ++line_;
        column_ = 1;
      } else if ((byte & 0xC0u) != 0x80u) {
        ++column_;  // characters, not UTF-8 continuation bytes
      }
    }
  }

  const std::string& text_;
  const std::string& source_;
  std::size_t i_ = 0, line_ = 1, column_ = 1;
  Place place_ = Place::kKey;
  bool header_allowed_ = true;  // at the first token of a top-level line
  bool in_header_ = false;      // between a table header's brackets
  std::vector<char> nesting_;   // the open '[' and '{' of the current value
  bool broken_ = false;
  Error broken_error_;
};

}  // namespace

std::optional<Error> findTomlHazard(const std::string& toml_text, const std::string& source_name) {
  return TomlWalk(toml_text, source_name).run();
}

}  // namespace skyroute
