#include "service/gcs_allowed_hosts.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>

namespace skyroute {
namespace {

constexpr std::size_t kMaxNameBytes = 253;  // a DNS name's longest text form

std::string lowerCase(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c | 0x20);
  return out;
}

// "[::1]" for any spelling of an IPv6 address; empty when `text` is not one.
std::string bracketedIpv6(const std::string& text) {
  in6_addr address{};
  if (inet_pton(AF_INET6, text.c_str(), &address) != 1) return "";
  char buffer[INET6_ADDRSTRLEN] = {};
  if (inet_ntop(AF_INET6, &address, buffer, sizeof buffer) == nullptr) return "";
  return "[" + std::string(buffer) + "]";
}

bool isDnsName(std::string_view name) {
  if (name.empty() || name.size() > kMaxNameBytes || name.front() == '.' || name.back() == '.') return false;
  std::size_t label = 0;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '.') {
      if (label == 0 || name[i - 1] == '-') return false;
      label = 0;
      continue;
    }
    const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || (c == '-' && label > 0);
    if (!ok || ++label > 63) return false;
  }
  return name.back() != '-';
}

// The host part of a Host field in canonical form, and its port (-1 when none); false when the
// field is not host[:port].
bool splitHostField(std::string_view field, std::string* host, int* port) {
  std::string_view port_text;
  if (!field.empty() && field.front() == '[') {
    const std::size_t close = field.find(']');
    if (close == std::string_view::npos) return false;
    *host = bracketedIpv6(std::string(field.substr(1, close - 1)));
    if (host->empty()) return false;
    const std::string_view rest = field.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return false;
      port_text = rest.substr(1);
      if (port_text.empty()) return false;
    }
  } else {
    const std::size_t colon = field.find(':');
    *host = lowerCase(field.substr(0, colon));
    if (colon != std::string_view::npos) {
      port_text = field.substr(colon + 1);
      if (port_text.empty()) return false;
    }
  }
  *port = -1;
  if (!port_text.empty()) {
    if (port_text.size() > 5 || !std::all_of(port_text.begin(), port_text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return false;
    }
    *port = std::stoi(std::string(port_text));
  }
  return true;
}

}  // namespace

Result<std::string> canonicalHostName(std::string_view name, const std::string& field) {
  const std::string lower = lowerCase(name);
  std::string inner = lower;
  if (inner.size() >= 2 && inner.front() == '[' && inner.back() == ']') inner = inner.substr(1, inner.size() - 2);
  if (inner.find(':') != std::string::npos) {
    const std::string v6 = bracketedIpv6(inner);
    if (!v6.empty()) return v6;
    return make_error(ErrorCode::kInvalidArgument, field,
                      field + " '" + std::string(name) + "' is neither a host name nor an address; give the name alone, "
                      "without a port (the port is the one --serve listens on)");
  }
  if (!isDnsName(lower)) {
    return make_error(ErrorCode::kInvalidArgument, field,
                      field + " '" + std::string(name) + "' is not a host name (letters, digits, '-' and '.'), "
                      "an IPv4 address or an IPv6 address");
  }
  return lower;
}

AllowedHosts::AllowedHosts(const std::string& bind_host, int port, const std::vector<std::string>& extra_names)
    : port_(port) {
  names_ = {"localhost", "127.0.0.1", "[::1]"};
  const std::string bound = bracketedIpv6(bind_host);
  names_.push_back(bound.empty() ? lowerCase(bind_host) : bound);
  names_.insert(names_.end(), extra_names.begin(), extra_names.end());
  std::sort(names_.begin(), names_.end());
  names_.erase(std::unique(names_.begin(), names_.end()), names_.end());
}

bool AllowedHosts::allows(std::string_view host_field) const {
  std::string host;
  int port = -1;
  if (!splitHostField(host_field, &host, &port)) return false;
  if (port != port_ && !(port == -1 && port_ == 80)) return false;
  return std::find(names_.begin(), names_.end(), host) != names_.end();
}

std::string AllowedHosts::describe() const {
  std::string out;
  for (const std::string& name : names_) out += (out.empty() ? "" : ", ") + name + ":" + std::to_string(port_);
  return out;
}

}  // namespace skyroute
