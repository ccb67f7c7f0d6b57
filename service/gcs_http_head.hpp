// The web map's reading of an HTTP request head (the request line and the header fields, up to the
// blank line), before cpp-httplib sees it. httplib 0.11 bounds neither the number of header fields
// nor the parts of a Range, and reads any body a client declares; so the server
// (service/gcs_web_server.cpp) reads the head itself, refuses what is over a bound or malformed
// with its status and a message, and hands httplib only heads this decoder accepted. The grammar is
// strict (CRLF line ends, token field names, origin-form targets) so that httplib, which is more
// lenient, reads an accepted head the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "planning/core/result.hpp"

namespace skyroute {

// The bounds of a request head (docs/gcs.md lists them with their defaults).
struct HttpHeadLimits {
  std::size_t max_head_bytes = 16 * 1024;         // request line + fields + blank line (431)
  std::size_t max_request_line_bytes = 8 * 1024;  // CRLF included (414; httplib's own limit)
  std::size_t max_field_line_bytes = 8 * 1024;    // one header line, CRLF included (431; httplib's own)
  std::size_t max_header_fields = 64;             // (431)
  std::uint64_t max_body_bytes = 0;               // the map takes no request body (413)
  std::size_t max_range_parts = 1;                // byte ranges in one Range field (416)
};

// Why a request is not served: the HTTP status and a message for whoever sent it.
struct HttpRefusal {
  int status = 400;
  std::string message;
};

// How far the head has arrived in the bytes received so far.
struct HttpHeadScan {
  enum class State { kIncomplete, kComplete, kRefused };
  State state = State::kIncomplete;
  std::size_t head_bytes = 0;  // kComplete: the head's length, its blank line included
  HttpRefusal refusal;         // kRefused: over a bound, or a line not ending in CRLF
};
HttpHeadScan scanRequestHead(std::string_view received, const HttpHeadLimits& limits);

// One byte range: "first-last", "first-" (last absent) or "-suffix" (first absent, last = the
// suffix length), as RFC 9110 section 14.1.2 writes them.
struct HttpByteRange {
  std::optional<std::uint64_t> first;
  std::optional<std::uint64_t> last;
};

struct HttpRequestHead {
  std::string method;
  std::string path;    // percent-decoded, without the query
  std::string query;   // as sent, after '?' (the map reads no query)
  std::string host;    // the Host field
  std::optional<HttpByteRange> range;
};

// Parses a complete head (what scanRequestHead measured) and applies the limits that need it read:
// 400 malformed, 505 not HTTP/1.0 or 1.1, 431 too many fields or one too long, 413 a body declared (or chunked),
// 405 a method other than GET and HEAD, 416 a Range other than one well-formed byte range. The
// Host field is required; whether its value is served here is AllowedHosts' question.
Result<HttpRequestHead, HttpRefusal> parseRequestHead(std::string_view head, const HttpHeadLimits& limits);

// "Bad Request" for 400, and so on for every status the web map answers with ("" for others).
std::string_view httpReasonPhrase(int status);

}  // namespace skyroute
