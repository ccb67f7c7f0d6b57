// Fuzzes the web map's reading of a request (`skyroute gcs --serve`): the input is what a client
// sends. As the server does, the head is looked for in what has arrived (scanRequestHead, over
// growing prefixes, which must agree with the whole), parsed (parseRequestHead) and its Host
// checked (AllowedHosts). Then a head the map accepts is given to cpp-httplib's own parser
// (Server::process_request, as GuardedHttpServer hands it over), which must read the same method,
// path, Host and byte range, and must not refuse it: the map's checks are only worth what httplib
// reads. A Host field read as an --allow-host name must be served once allowed.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "service/gcs_allowed_hosts.hpp"
#include "service/gcs_http_head.hpp"
#include "tests/fuzz/finding.hpp"

#include <httplib.h>

namespace {

using namespace skyroute;

constexpr const char* kHarness = "gcs_http_head";
constexpr int kPort = 8080;

[[noreturn]] void finding(const std::string& what, std::string_view input) {
  fuzz::reportFinding(kHarness, what + " (head of " + std::to_string(input.size()) + " bytes)");
}

// The head as httplib reads it, from memory; what httplib writes back is kept.
class MemoryStream final : public httplib::Stream {
 public:
  explicit MemoryStream(std::string_view input) : input_(input) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t n = std::min(size, input_.size() - read_);
    std::memcpy(ptr, input_.data() + read_, n);
    read_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    written_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 40000;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = kPort;
  }
  socket_t socket() const override { return 0; }  // below FD_SETSIZE, never used
  const std::string& written() const { return written_; }

 private:
  std::string_view input_;
  std::size_t read_ = 0;
  std::string written_;
};

// What httplib made of a request.
struct HttplibRead {
  std::string method, path, host;
  httplib::Ranges ranges;
};

class ParsingServer final : public httplib::Server {
 public:
  ParsingServer() {
    set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      read_ = HttplibRead{req.method, req.path, req.get_header_value("Host"), req.ranges};
      res.status = 204;
      return HandlerResponse::Handled;
    });
  }
  // Nothing when httplib refused the head before routing.
  std::optional<HttplibRead> parse(std::string_view head) {
    read_.reset();
    MemoryStream stream(head);
    bool closed = false;
    process_request(stream, true, closed, nullptr);
    return read_;
  }

 private:
  std::optional<HttplibRead> read_;
};

void checkScans(std::string_view input, const HttpHeadLimits& limits) {
  const HttpHeadScan whole = scanRequestHead(input, limits);
  if (whole.state == HttpHeadScan::State::kComplete &&
      (whole.head_bytes < 4 || whole.head_bytes > input.size() || whole.head_bytes > limits.max_head_bytes)) {
    finding("a complete head of " + std::to_string(whole.head_bytes) + " bytes", input);
  }
  if (whole.state == HttpHeadScan::State::kRefused && whole.refusal.message.empty()) finding("a refusal without a message", input);
  // As the bytes arrive: a prefix never sees a head the whole does not see, nor ends it elsewhere;
  // a prefix refused stays refused.
  for (std::size_t cut : {input.size() / 4, input.size() / 2, input.size() - input.size() / 8}) {
    const HttpHeadScan part = scanRequestHead(input.substr(0, cut), limits);
    if (part.state == HttpHeadScan::State::kComplete &&
        (whole.state != HttpHeadScan::State::kComplete || whole.head_bytes != part.head_bytes)) {
      finding("a prefix of " + std::to_string(cut) + " bytes ends the head elsewhere than the whole", input);
    }
    if (part.state == HttpHeadScan::State::kRefused && whole.state != HttpHeadScan::State::kRefused) {
      finding("a prefix of " + std::to_string(cut) + " bytes is refused and the whole is not", input);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const HttpHeadLimits limits;  // the server's defaults
  checkScans(input, limits);
  const HttpHeadScan scan = scanRequestHead(input, limits);
  if (scan.state != HttpHeadScan::State::kComplete) return 0;
  const std::string_view head = input.substr(0, scan.head_bytes);
  auto parsed = parseRequestHead(head, limits);
  if (!parsed) {
    if (parsed.error().message.empty() || httpReasonPhrase(parsed.error().status).empty()) {
      finding("a refusal (" + std::to_string(parsed.error().status) + ") without a message or a known status", input);
    }
    return 0;
  }
  const HttpRequestHead& request = *parsed;
  if ((request.method != "GET" && request.method != "HEAD") || request.host.empty() || request.path.empty() ||
      request.path.front() != '/' || request.path.find('\0') != std::string::npos) {
    finding("an accepted head with method '" + request.method + "' and path '" + request.path + "'", input);
  }

  // What httplib reads of the same head.
  static ParsingServer server;
  const std::optional<HttplibRead> read = server.parse(head);
  if (!read) finding("httplib refused a head the map accepted", input);
  if (read->method != request.method || read->path != request.path) {
    finding("httplib reads '" + read->method + " " + read->path + "', the map '" + request.method + " " + request.path + "'",
            input);
  }
  // httplib percent-decodes field values; a Host with a '%' is no name the map answers to anyway.
  if (request.host.find('%') == std::string::npos && read->host != request.host) {
    finding("httplib reads Host '" + read->host + "', the map '" + request.host + "'", input);
  }
  if (request.range.has_value() != !read->ranges.empty() || read->ranges.size() > 1) {
    finding("httplib reads " + std::to_string(read->ranges.size()) + " byte ranges", input);
  }
  if (request.range) {
    const auto [first, last] = read->ranges.front();
    const auto expected_first = request.range->first ? static_cast<ssize_t>(*request.range->first) : ssize_t{-1};
    const auto expected_last = request.range->last ? static_cast<ssize_t>(*request.range->last) : ssize_t{-1};
    if (first != expected_first || last != expected_last) {
      finding("httplib reads the range " + std::to_string(first) + "-" + std::to_string(last), input);
    }
  }

  // The Host check, and the Host read as an --allow-host name.
  const AllowedHosts defaults("127.0.0.1", kPort, {});
  (void)defaults.allows(request.host);
  const std::size_t port_at = request.host.rfind(':');
  const std::string name = request.host.substr(0, request.host.back() == ']' ? std::string::npos : port_at);
  auto canonical = canonicalHostName(name, "--allow-host");
  if (canonical) {
    const AllowedHosts with_name("127.0.0.1", kPort, {*canonical});
    if (!with_name.allows(*canonical + ":" + std::to_string(kPort))) {
      finding("--allow-host " + name + " (" + *canonical + ") is not served", input);
    }
  } else if (canonical.error().message.empty()) {
    finding("an --allow-host refusal without a message", input);
  }
  return 0;
}
