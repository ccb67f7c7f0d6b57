// The web map's request head decoder (service/gcs_http_head.hpp): where a head ends, each bound
// with its status, the strict grammar that keeps it in step with httplib, byte ranges and paths.
#include <gtest/gtest.h>

#include <string>

#include "service/gcs_http_head.hpp"

namespace skyroute {
namespace {

using State = HttpHeadScan::State;

std::string head(const std::string& request_line, const std::string& fields = "Host: localhost:8080\r\n") {
  return request_line + "\r\n" + fields + "\r\n";
}

int refusedWith(const std::string& text, const HttpHeadLimits& limits = {}) {
  auto parsed = parseRequestHead(text, limits);
  return parsed ? 0 : parsed.error().status;
}

TEST(HttpHeadScan, FindsTheEndOfTheHeadAndWaitsForIt) {
  const HttpHeadLimits limits;
  const std::string complete = head("GET / HTTP/1.1");
  for (std::size_t n = 0; n < complete.size(); ++n) {
    EXPECT_EQ(scanRequestHead(complete.substr(0, n), limits).state, State::kIncomplete) << n;
  }
  const HttpHeadScan scan = scanRequestHead(complete + "GET /next", limits);
  EXPECT_EQ(scan.state, State::kComplete);
  EXPECT_EQ(scan.head_bytes, complete.size());
}

TEST(HttpHeadScan, RefusesOverlongHeadsAndRequestLinesBeforeTheyEnd) {
  HttpHeadLimits limits;
  limits.max_head_bytes = 100;
  limits.max_request_line_bytes = 50;
  HttpHeadScan scan = scanRequestHead("GET /" + std::string(60, 'a'), limits);
  EXPECT_EQ(scan.state, State::kRefused);
  EXPECT_EQ(scan.refusal.status, 414);
  scan = scanRequestHead("GET / HTTP/1.1\r\nX: " + std::string(100, 'a'), limits);
  EXPECT_EQ(scan.state, State::kRefused);
  EXPECT_EQ(scan.refusal.status, 431);
  EXPECT_NE(scan.refusal.message.find("longer than 100 bytes"), std::string::npos) << scan.refusal.message;
  // Exactly at the bound is accepted.
  const std::string at_bound = head("GET / HTTP/1.1", "X: " + std::string(100 - 16 - 5 - 2, 'a') + "\r\n");
  ASSERT_EQ(at_bound.size(), 100u);
  EXPECT_EQ(scanRequestHead(at_bound, limits).state, State::kComplete);
}

TEST(HttpHeadScan, RefusesLinesThatDoNotEndInCrlf) {
  for (const std::string text : {"GET / HTTP/1.1\nHost: a\n\n", "GET / HTTP/1.1\r\nHost: a\rb\r\n\r\n", "\n"}) {
    const HttpHeadScan scan = scanRequestHead(text, {});
    EXPECT_EQ(scan.state, State::kRefused) << text;
    EXPECT_EQ(scan.refusal.status, 400) << text;
  }
  // A CR at the end of what arrived may be followed by its LF.
  EXPECT_EQ(scanRequestHead("GET / HTTP/1.1\r", {}).state, State::kIncomplete);
}

TEST(HttpRequestHead, ReadsMethodPathQueryHostAndRange) {
  auto parsed = parseRequestHead(head("GET /ev%65nts?x=1 HTTP/1.1", "host:  localhost:8080 \r\nRange: bytes=5-9\r\n"), {});
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed->method, "GET");
  EXPECT_EQ(parsed->path, "/events");
  EXPECT_EQ(parsed->query, "x=1");
  EXPECT_EQ(parsed->host, "localhost:8080");
  ASSERT_TRUE(parsed->range);
  EXPECT_EQ(parsed->range->first, 5u);
  EXPECT_EQ(parsed->range->last, 9u);
  parsed = parseRequestHead(head("HEAD / HTTP/1.0", "Host: a\r\nRange: bytes=-500\r\n"), {});
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_FALSE(parsed->range->first);
  EXPECT_EQ(parsed->range->last, 500u);
  parsed = parseRequestHead(head("GET / HTTP/1.1", "Host: a\r\nRange: bytes=7-\r\n"), {});
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed->range->first, 7u);
  EXPECT_FALSE(parsed->range->last);
}

TEST(HttpRequestHead, RefusesMoreRangePartsThanTheLimitAndMalformedRanges) {
  std::string many = "bytes=0-";
  for (int i = 1; i < 2700; ++i) many += ",0-";
  auto parsed = parseRequestHead(head("GET / HTTP/1.1", "Host: a\r\nRange: " + many + "\r\n"), {});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().status, 416);
  EXPECT_NE(parsed.error().message.find("2700 byte ranges"), std::string::npos) << parsed.error().message;
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nRange: bytes=0-1, 2-3\r\n")), 416);
  HttpHeadLimits two;
  two.max_range_parts = 2;
  // Two parts pass the count and meet the rest of the grammar, which reads one range.
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nRange: bytes=0-1,2-3\r\n"), two), 416);
  for (const std::string range : {"bytes=-", "bytes=9-5", "bytes=a-b", "items=0-5", "bytes=0-1%2C2-3", "bytes=1-2-3",
                                  "bytes=0-1234567890123456789", "bytes= 0-5"}) {
    EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nRange: " + range + "\r\n")), 416) << range;
  }
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nRange: bytes=0-1\r\nRange: bytes=2-3\r\n")), 416);
}

TEST(HttpRequestHead, RefusesBodiesMethodsAndTooManyFields) {
  EXPECT_EQ(refusedWith(head("POST / HTTP/1.1", "Host: a\r\nContent-Length: 1073741824\r\n")), 413);
  EXPECT_EQ(refusedWith(head("POST / HTTP/1.1", "Host: a\r\nContent-Length: 99999999999999999999999\r\n")), 413);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 1\r\n")), 413);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nTransfer-Encoding: chunked\r\n")), 413);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 0\r\n")), 0);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 000\r\n")), 0);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: -1\r\n")), 400);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 0\r\nContent-Length: 0\r\n")), 400);
  HttpHeadLimits small_body;
  small_body.max_body_bytes = 10;
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 10\r\n"), small_body), 0);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nContent-Length: 11\r\n"), small_body), 413);
  for (const char* method : {"POST", "PUT", "DELETE", "OPTIONS", "PATCH", "BREW"}) {
    EXPECT_EQ(refusedWith(head(std::string(method) + " / HTTP/1.1")), 405) << method;
  }

  // One field line at httplib's own limit passes, one byte more does not.
  const std::string at_line_limit = "X: " + std::string(8192 - 5, 'a') + "\r\n";
  ASSERT_EQ(at_line_limit.size(), 8192u);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\n" + at_line_limit)), 0);
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nX: a" + at_line_limit.substr(3))), 431);

  std::string fields = "Host: a\r\n";
  for (int i = 1; i < 64; ++i) fields += "X-" + std::to_string(i) + ": v\r\n";
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", fields)), 0);  // 64 fields
  auto parsed = parseRequestHead(head("GET / HTTP/1.1", fields + "X-65: v\r\n"), {});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().status, 431);
  EXPECT_NE(parsed.error().message.find("more than 64 header fields"), std::string::npos);
}

TEST(HttpRequestHead, RefusesWhatHttplibWouldReadAnotherWay) {
  for (const std::string line : {"GET  / HTTP/1.1", "GET / HTTP/1.1 ", "GET /", "GET http://evil.example/ HTTP/1.1",
                                 "GET * HTTP/1.1", "GET /a#b HTTP/1.1", "GET /a?b?c HTTP/1.1", "GET /%zz HTTP/1.1",
                                 "GET /%u0041 HTTP/1.1", "GET /%00 HTTP/1.1", "GET /%4 HTTP/1.1", "G@T / HTTP/1.1",
                                 "GET / http/1.1", "GET /\x7f HTTP/1.1"}) {
    EXPECT_EQ(refusedWith(head(line)), 400) << line;
  }
  EXPECT_EQ(refusedWith(head("GET / HTTP/2.0")), 505);
  for (const std::string field : {"Host : a\r\n", " Host: a\r\n", "Host: a\r\n folded\r\n", "Host: a\x01\r\n", ": a\r\n",
                                  "Host\r\n"}) {
    EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", field)), 400) << field;
  }
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "")), 400);                       // no Host
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nHost: b\r\n")), 400);  // two
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host:\r\n")), 400);               // empty
  EXPECT_EQ(refusedWith("GET / HTTP/1.1\r\nHost: a\r\n\r\nextra"), 400);          // more than the head
  EXPECT_EQ(refusedWith(head("GET / HTTP/1.1", "Host: a\r\nX-Obs: caf\xc3\xa9\r\n")), 0);  // obs-text is a value
}

TEST(HttpRequestHead, MessagesQuoteOnlyPrintableText) {
  auto parsed = parseRequestHead(head("GET / HTTP/9.9"), {});
  ASSERT_FALSE(parsed.ok());
  EXPECT_NE(parsed.error().message.find("'HTTP/9.9'"), std::string::npos) << parsed.error().message;
  parsed = parseRequestHead(head("GET / HTTP/1.1", "Host: a\r\nRange: bytes=\xff" + std::string(100, 'x') + "\r\n"), {});
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().message.find('\xff'), std::string::npos);
  EXPECT_LT(parsed.error().message.size(), 200u);
}

TEST(HttpReasonPhrase, NamesEveryStatusTheMapAnswers) {
  for (int status : {400, 403, 405, 408, 413, 414, 416, 421, 431, 503, 505}) EXPECT_NE(httpReasonPhrase(status), "") << status;
}

}  // namespace
}  // namespace skyroute
