#include "service/gcs_http_head.hpp"

#include <algorithm>
#include <vector>

namespace skyroute {
namespace {

constexpr std::string_view kCrlf = "\r\n";
constexpr std::size_t kMaxRangeDigits = 18;  // below 2^63: httplib keeps positions in ssize_t

HttpRefusal refusal(int status, std::string message) { return {status, std::move(message)}; }

// RFC 9110 token characters (method, field names).
bool isTokenChar(unsigned char c) {
  if (c >= '0' && c <= '9') return true;
  if ((c | 0x20) >= 'a' && (c | 0x20) <= 'z') return true;
  return std::string_view("!#$%&'*+-.^_`|~").find(static_cast<char>(c)) != std::string_view::npos;
}
bool isToken(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return isTokenChar(static_cast<unsigned char>(c)); });
}
// Field values: visible ASCII, space, tab and obs-text; no other control character.
bool isFieldValueChar(unsigned char c) { return c == '\t' || (c >= 0x20 && c != 0x7F); }
bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isSpaceOrTab(char c) { return c == ' ' || c == '\t'; }

bool equalsIgnoringCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x >= 'A' && x <= 'Z' ? x | 0x20 : x) == (y >= 'A' && y <= 'Z' ? y | 0x20 : y);
         });
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && isSpaceOrTab(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpaceOrTab(s.back())) s.remove_suffix(1);
  return s;
}

// What a message may quote of the client's bytes: printable ASCII, at most 60 characters.
std::string quoted(std::string_view s) {
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < 60; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
  }
  return out + (s.size() > 60 ? "...'" : "'");
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if ((c | 0x20) >= 'a' && (c | 0x20) <= 'f') return (c | 0x20) - 'a' + 10;
  return -1;
}

// The path as httplib routes it (its decode_url without '+'), refusing what it would read
// another way: a '%' not followed by two hex digits (httplib keeps it, or reads "%uXXXX" as
// UTF-16) and an encoded NUL.
Result<std::string, HttpRefusal> decodePath(std::string_view raw) {
  std::string path;
  path.reserve(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '%') {
      path += raw[i];
      continue;
    }
    const int high = i + 1 < raw.size() ? hexValue(raw[i + 1]) : -1;
    const int low = i + 2 < raw.size() ? hexValue(raw[i + 2]) : -1;
    if (high < 0 || low < 0) return refusal(400, "the path has a '%' not followed by two hex digits");
    const int value = high * 16 + low;
    if (value == 0) return refusal(400, "the path has an encoded NUL (%00)");
    path += static_cast<char>(value);
    i += 2;
  }
  return path;
}

// "bytes=" and one or more comma-separated ranges; refuses more parts than the limit before
// reading them one by one.
Result<HttpByteRange, HttpRefusal> parseRange(std::string_view value, const HttpHeadLimits& limits) {
  constexpr std::string_view kUnit = "bytes=";
  if (value.substr(0, kUnit.size()) != kUnit) {
    return refusal(416, "Range must be 'bytes=FIRST-LAST', 'bytes=FIRST-' or 'bytes=-SUFFIX'; got " + quoted(value));
  }
  value.remove_prefix(kUnit.size());
  const std::size_t parts = static_cast<std::size_t>(std::count(value.begin(), value.end(), ',')) + 1;
  if (parts > limits.max_range_parts) {
    return refusal(416, "Range asks for " + std::to_string(parts) + " byte ranges; the live map serves at most " +
                            std::to_string(limits.max_range_parts) + " per request");
  }
  const std::size_t dash = value.find('-');
  if (dash == std::string_view::npos) return refusal(416, "Range " + quoted(value) + " has no '-'");
  const std::string_view first = value.substr(0, dash), last = value.substr(dash + 1);
  auto number = [](std::string_view digits) -> std::optional<std::uint64_t> {
    if (digits.empty() || digits.size() > kMaxRangeDigits || !std::all_of(digits.begin(), digits.end(), isDigit)) {
      return std::nullopt;
    }
    std::uint64_t n = 0;
    for (char c : digits) n = n * 10 + static_cast<std::uint64_t>(c - '0');
    return n;
  };
  HttpByteRange range;
  const std::string bad = "Range " + quoted(value) + " is not FIRST-LAST, FIRST- or -SUFFIX with at most " +
                          std::to_string(kMaxRangeDigits) + " digits each";
  if (!first.empty()) {
    range.first = number(first);
    if (!range.first) return refusal(416, bad);
  }
  if (!last.empty()) {
    range.last = number(last);
    if (!range.last) return refusal(416, bad);
  }
  if (!range.first && !range.last) return refusal(416, bad);
  if (range.first && range.last && *range.first > *range.last) {
    return refusal(416, "Range " + quoted(value) + " ends before it starts");
  }
  return range;
}

struct Field {
  std::string_view name, value;  // value without the surrounding spaces and tabs
};

Result<HttpRequestHead, HttpRefusal> parseRequestLine(std::string_view line) {
  const std::size_t first_space = line.find(' ');
  const std::size_t second_space = first_space == std::string_view::npos ? first_space : line.find(' ', first_space + 1);
  if (second_space == std::string_view::npos || line.find(' ', second_space + 1) != std::string_view::npos) {
    return refusal(400, "the request line must be 'METHOD TARGET HTTP/1.1' with single spaces; got " + quoted(line));
  }
  HttpRequestHead head;
  head.method = line.substr(0, first_space);
  const std::string_view target = line.substr(first_space + 1, second_space - first_space - 1);
  const std::string_view version = line.substr(second_space + 1);
  if (!isToken(head.method) || head.method.size() > 16) return refusal(400, "the method " + quoted(head.method) + " is not a token");
  if (version.substr(0, 5) != "HTTP/") return refusal(400, "the request line ends in " + quoted(version) + ", not HTTP/1.1");
  if (version != "HTTP/1.1" && version != "HTTP/1.0") {
    return refusal(505, "the live map speaks HTTP/1.1 and HTTP/1.0, not " + quoted(version));
  }
  if (target.empty() || target.front() != '/') {
    return refusal(400, "the target " + quoted(target) + " must be a path starting with '/'");
  }
  for (char c : target) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u >= 0x7F || c == '#') {
      return refusal(400, "the target " + quoted(target) + " has a character outside visible ASCII, or a '#'");
    }
  }
  const std::size_t question = target.find('?');
  const std::string_view raw_path = target.substr(0, question);
  if (question != std::string_view::npos) {
    head.query = target.substr(question + 1);
    if (head.query.find('?') != std::string::npos) return refusal(400, "the target has more than one '?'");
  }
  auto path = decodePath(raw_path);
  if (!path) return path.error();
  head.path = std::move(*path);
  return head;
}

}  // namespace

HttpHeadScan scanRequestHead(std::string_view received, const HttpHeadLimits& limits) {
  HttpHeadScan scan;
  const std::size_t line_end = received.find(kCrlf);
  const std::size_t line_limit = std::min(limits.max_request_line_bytes, limits.max_head_bytes);
  if ((line_end == std::string_view::npos && received.size() > line_limit) ||
      (line_end != std::string_view::npos && line_end + kCrlf.size() > line_limit)) {
    scan.state = HttpHeadScan::State::kRefused;
    scan.refusal = refusal(414, "the request line is longer than " + std::to_string(line_limit) + " bytes");
    return scan;
  }
  // A bare LF (or a CR before anything but LF) would end a line for some readers and not for others.
  const std::size_t end = received.find("\r\n\r\n");
  const std::size_t checked = end == std::string_view::npos ? received.size() : end + 4;
  for (std::size_t i = 0; i < checked; ++i) {
    const bool bare_lf = received[i] == '\n' && (i == 0 || received[i - 1] != '\r');
    const bool bare_cr = received[i] == '\r' && i + 1 < received.size() && received[i + 1] != '\n';
    if (bare_lf || bare_cr) {
      scan.state = HttpHeadScan::State::kRefused;
      scan.refusal = refusal(400, "every line of the request head must end in CRLF");
      return scan;
    }
  }
  if (end == std::string_view::npos) {
    if (received.size() >= limits.max_head_bytes) {
      scan.state = HttpHeadScan::State::kRefused;
      scan.refusal = refusal(431, "the request head is longer than " + std::to_string(limits.max_head_bytes) + " bytes");
    }
    return scan;
  }
  if (end + 4 > limits.max_head_bytes) {
    scan.state = HttpHeadScan::State::kRefused;
    scan.refusal = refusal(431, "the request head is longer than " + std::to_string(limits.max_head_bytes) + " bytes");
    return scan;
  }
  scan.state = HttpHeadScan::State::kComplete;
  scan.head_bytes = end + 4;
  return scan;
}

Result<HttpRequestHead, HttpRefusal> parseRequestHead(std::string_view head, const HttpHeadLimits& limits) {
  const HttpHeadScan scan = scanRequestHead(head, limits);
  if (scan.state == HttpHeadScan::State::kRefused) return scan.refusal;
  if (scan.state != HttpHeadScan::State::kComplete || scan.head_bytes != head.size()) {
    return refusal(400, "the request head must end with one blank line");
  }
  const std::size_t line_end = head.find(kCrlf);
  auto parsed = parseRequestLine(head.substr(0, line_end));
  if (!parsed) return parsed.error();
  HttpRequestHead request = std::move(*parsed);

  std::vector<Field> fields;
  for (std::size_t at = line_end + kCrlf.size(); at + kCrlf.size() < head.size();) {
    const std::size_t next = head.find(kCrlf, at);
    const std::string_view line = head.substr(at, next - at);
    at = next + kCrlf.size();
    if (fields.size() == limits.max_header_fields) {
      return refusal(431, "the request has more than " + std::to_string(limits.max_header_fields) + " header fields");
    }
    if (line.size() + kCrlf.size() > limits.max_field_line_bytes) {
      return refusal(431, "the header line " + quoted(line) + " is longer than " +
                              std::to_string(limits.max_field_line_bytes) + " bytes");
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos || !isToken(line.substr(0, colon))) {
      return refusal(400, "the header line " + quoted(line) + " is not 'Name: value'");
    }
    const std::string_view value = line.substr(colon + 1);
    if (!std::all_of(value.begin(), value.end(), [](char c) { return isFieldValueChar(static_cast<unsigned char>(c)); })) {
      return refusal(400, "the header " + quoted(line.substr(0, colon)) + " has a control character in its value");
    }
    fields.push_back({line.substr(0, colon), trimmed(value)});
  }
  auto all = [&](std::string_view name) {
    std::vector<std::string_view> values;
    for (const Field& f : fields)
      if (equalsIgnoringCase(f.name, name)) values.push_back(f.value);
    return values;
  };

  // A body first: what a client sends after the head must not be read, whatever the method.
  if (!all("Transfer-Encoding").empty()) {
    return refusal(413, "the live map takes no request body (Transfer-Encoding)");
  }
  const std::vector<std::string_view> lengths = all("Content-Length");
  if (lengths.size() > 1) return refusal(400, "the request has more than one Content-Length");
  if (lengths.size() == 1) {
    const std::string_view length = lengths.front();
    if (length.empty() || !std::all_of(length.begin(), length.end(), isDigit)) {
      return refusal(400, "Content-Length " + quoted(length) + " is not a number");
    }
    const std::string_view significant = length.substr(std::min(length.find_first_not_of('0'), length.size()));
    std::uint64_t declared = 0;
    bool over = significant.size() > 19;
    for (std::size_t i = 0; !over && i < significant.size(); ++i) {
      const auto digit = static_cast<std::uint64_t>(significant[i] - '0');
      over = declared > (UINT64_MAX - digit) / 10;
      declared = declared * 10 + digit;
    }
    if (over || declared > limits.max_body_bytes) {
      const std::string declared_text = "the request declares a body of " + std::string(length) + " bytes";
      return refusal(413, limits.max_body_bytes == 0
                              ? "the live map takes no request body; " + declared_text
                              : declared_text + "; the live map takes at most " + std::to_string(limits.max_body_bytes));
    }
  }
  if (request.method != "GET" && request.method != "HEAD") {
    return refusal(405, "the live map answers GET and HEAD only, not " + quoted(request.method));
  }
  const std::vector<std::string_view> hosts = all("Host");
  if (hosts.size() != 1 || hosts.front().empty()) {
    return refusal(400, hosts.empty() ? "the request has no Host header" : "the request needs exactly one non-empty Host header");
  }
  request.host = hosts.front();
  const std::vector<std::string_view> ranges = all("Range");
  if (ranges.size() > 1) return refusal(416, "the request has more than one Range header");
  if (ranges.size() == 1) {
    auto range = parseRange(ranges.front(), limits);
    if (!range) return range.error();
    request.range = *range;
  }
  return request;
}

std::string_view httpReasonPhrase(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 403: return "Forbidden";
    case 405: return "Method Not Allowed";
    case 408: return "Request Timeout";
    case 413: return "Content Too Large";
    case 414: return "URI Too Long";
    case 416: return "Range Not Satisfiable";
    case 421: return "Misdirected Request";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    case 505: return "HTTP Version Not Supported";
    default: return "";
  }
}

}  // namespace skyroute
