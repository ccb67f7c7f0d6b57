// Fuzzes skyrouted's configuration file: TOML text -> parseDaemonConfig. A configuration it accepts
// must survive `skyrouted --print-config`: describeDaemonConfig's document parses again to the same
// values (it is the template operators edit). Anything else is a finding (abort).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>

#include "service/daemon_config.hpp"
#include "tests/fuzz/finding.hpp"

namespace {

[[noreturn]] void finding(const std::string& what) { skyroute::fuzz::reportFinding("daemon_config_fuzzer", what); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skyroute;
  const std::string text(reinterpret_cast<const char*>(data), size);
  auto config = parseDaemonConfig(text, "fuzz.toml");
  if (!config) {
    if (config.error().field.empty()) finding("a refused configuration names no key");
    return 0;
  }
  const std::string printed = describeDaemonConfig(*config);
  auto again = parseDaemonConfig(printed, "printed.toml");
  if (!again) finding("--print-config output does not load: " + again.error().describe() + "\n" + printed);
  if (describeDaemonConfig(*again) != printed) finding("--print-config output loads with other values:\n" + printed);
  return 0;
}
