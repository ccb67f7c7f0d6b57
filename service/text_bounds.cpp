#include "service/text_bounds.hpp"

#include <algorithm>
#include <cstdio>

namespace skyroute {

namespace {

bool isIdChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
}

bool isIdStart(char c) { return isIdChar(c) && c != '-' && c != '.'; }

Error invalid(std::string_view field, const std::string& reason) {
  std::string name(field);
  return make_error(ErrorCode::kInvalidArgument, name, name + " " + reason);
}

// Where the first character outside the id set is, for the message.
std::string firstBadCharacter(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (i == 0 ? isIdStart(c) : isIdChar(c)) continue;
    const auto byte = static_cast<unsigned char>(c);
    const bool printable = byte >= 0x21 && byte < 0x7f;
    char code[8];
    std::snprintf(code, sizeof code, "0x%02x", byte);
    return (printable ? "'" + std::string(1, c) + "' (" + code + ")" : std::string(code)) + " at position " +
           std::to_string(i);
  }
  return {};
}

}  // namespace

bool isValidId(std::string_view text, std::size_t max_chars) {
  if (text.empty() || text.size() > max_chars || !isIdStart(text.front())) return false;
  for (char c : text)
    if (!isIdChar(c)) return false;
  return true;
}

std::optional<Error> checkId(std::string_view text, std::string_view field, std::size_t max_chars) {
  if (text.empty()) return invalid(field, "is missing (empty)");
  if (text.size() > max_chars)
    return invalid(field, "has " + std::to_string(text.size()) + " characters, more than the limit of " +
                              std::to_string(max_chars) + " (" + echoOfUntrusted(text) + ")");
  if (isValidId(text, max_chars)) return std::nullopt;
  return invalid(field, "may hold only A-Z a-z 0-9 _ - . and must start with a letter, a digit or _ (" +
                            firstBadCharacter(text) + " in \"" + echoOfUntrusted(text) + "\")");
}

std::optional<Error> checkOptionalId(std::string_view text, std::string_view field, std::size_t max_chars) {
  if (text.empty()) return std::nullopt;
  return checkId(text, field, max_chars);
}

std::optional<Error> checkName(std::string_view text, std::string_view field, std::size_t max_chars) {
  if (text.size() > max_chars)
    return invalid(field, "has " + std::to_string(text.size()) + " characters, more than the limit of " +
                              std::to_string(max_chars) + " (" + echoOfUntrusted(text) + ")");
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x20 || byte >= 0x7f)
      return invalid(field, "may hold only printable ASCII characters (byte " + std::to_string(byte) + " at position " +
                                std::to_string(i) + ")");
  }
  return std::nullopt;
}

std::optional<Error> checkFreeText(std::string_view text, std::string_view field, std::size_t max_bytes) {
  if (text.size() > max_bytes)
    return invalid(field, "has " + std::to_string(text.size()) + " bytes, more than the limit of " +
                              std::to_string(max_bytes));
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if ((byte < 0x20 && byte != '\t') || byte == 0x7f)
      return invalid(field, "holds a control character (byte " + std::to_string(byte) + " at position " +
                                std::to_string(i) + ")");
  }
  return std::nullopt;
}

std::string echoOfUntrusted(std::string_view text) {
  constexpr std::size_t kShown = 64;
  std::string echo;
  echo.reserve(std::min(text.size(), kShown) + 32);
  for (std::size_t i = 0; i < text.size() && i < kShown; ++i) echo += isIdChar(text[i]) ? text[i] : '?';
  if (text.size() > kShown) echo += "...(" + std::to_string(text.size()) + " characters)";
  return echo;
}

std::string boundedFreeText(std::string_view text, std::size_t max_bytes) {
  std::size_t end = std::min(text.size(), max_bytes);
  // Back to the start of a UTF-8 character (continuation bytes are 10xxxxxx).
  if (end < text.size())
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xc0) == 0x80) --end;
  std::string out(text.substr(0, end));
  for (char& c : out) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && byte != '\t') || byte == 0x7f) c = '?';
  }
  return out;
}

}  // namespace skyroute
