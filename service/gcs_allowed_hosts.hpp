// The host names the web map answers to. A page on any web site can make a browser send requests
// to 127.0.0.1 under a name of the attacker's that resolves there (DNS rebinding); the browser
// then treats the map as that site's and lets its script read the fleet. Such a request names the
// attacker's host in its Host field, so only the names the map is served under are answered:
// localhost, 127.0.0.1 and [::1], the address it is bound to, and the names given with
// --allow-host, each with the port it listens on (without it only on port 80).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "planning/core/result.hpp"

namespace skyroute {

// A name --allow-host takes, in the form a Host field carries it: a DNS name (letters, digits,
// '-' and '.', lower-cased), an IPv4 address, or an IPv6 address (brackets optional; written back
// compressed and in brackets, as browsers send it). No port: the port is the one served. Errors
// name `field`.
Result<std::string> canonicalHostName(std::string_view name, const std::string& field);

class AllowedHosts {
 public:
  // bind_host: the numeric address the server binds (IPv6 without brackets); port: the port it
  // listens on; extra_names: canonical names (canonicalHostName).
  AllowedHosts(const std::string& bind_host, int port, const std::vector<std::string>& extra_names);

  // Whether a request whose Host field is `host_field` is served.
  bool allows(std::string_view host_field) const;
  // "localhost:8080, 127.0.0.1:8080, [::1]:8080", for messages.
  std::string describe() const;

 private:
  std::vector<std::string> names_;  // canonical, without the port
  int port_ = 0;
};

}  // namespace skyroute
