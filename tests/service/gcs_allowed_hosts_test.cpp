// The host names the web map answers to (service/gcs_allowed_hosts.hpp): the defaults, the bound
// address, --allow-host names, ports, and the spellings a DNS rebinding attack would use.
#include <gtest/gtest.h>

#include "service/gcs_allowed_hosts.hpp"

namespace skyroute {
namespace {

TEST(AllowedHosts, AnswersLocalNamesAndTheBoundAddressWithThePort) {
  const AllowedHosts hosts("127.0.0.1", 8080, {});
  for (const char* field : {"localhost:8080", "LOCALHOST:8080", "127.0.0.1:8080", "[::1]:8080", "[0:0::1]:8080"}) {
    EXPECT_TRUE(hosts.allows(field)) << field;
  }
  for (const char* field : {"localhost", "localhost:8081", "localhost:080800", "localhost:", "evil.example:8080",
                            "localhost.:8080", "127.0.0.1.evil.example:8080", "localhost:8080:8080", "[::1]",
                            "[::1]8080", "[::2]:8080", "[evil]:8080", "::1:8080", "", "localhost :8080",
                            "127.0.0.2:8080", "0.0.0.0:8080"}) {
    EXPECT_FALSE(hosts.allows(field)) << field;
  }
  EXPECT_EQ(hosts.describe(), "127.0.0.1:8080, [::1]:8080, localhost:8080");
}

TEST(AllowedHosts, AddsTheBoundAddressAndNamesGiven) {
  const AllowedHosts lan("192.168.1.20", 80, {"map.example", "[fd00::7]"});
  for (const char* field : {"192.168.1.20", "192.168.1.20:80", "map.example", "Map.Example:80", "[fd00::7]",
                            "[FD00:0::7]:80", "localhost"}) {
    EXPECT_TRUE(lan.allows(field)) << field;  // on port 80 the port may be left out
  }
  EXPECT_FALSE(lan.allows("map.example:8080"));
  const AllowedHosts any_v6("::", 9000, {});
  EXPECT_TRUE(any_v6.allows("[::]:9000"));
  EXPECT_FALSE(any_v6.allows("[::2]:9000"));
}

TEST(CanonicalHostName, LowerCasesNamesAndWritesIpv6InBrackets) {
  EXPECT_EQ(*canonicalHostName("Map.Example", "--allow-host"), "map.example");
  EXPECT_EQ(*canonicalHostName("192.168.1.20", "--allow-host"), "192.168.1.20");
  EXPECT_EQ(*canonicalHostName("0:0:0:0:0:0:0:1", "--allow-host"), "[::1]");
  EXPECT_EQ(*canonicalHostName("[FD00::7]", "--allow-host"), "[fd00::7]");
  EXPECT_EQ(*canonicalHostName("a-b.c1", "--allow-host"), "a-b.c1");
}

TEST(CanonicalHostName, RefusesPortsAndWhatIsNoName) {
  for (const char* name : {"", "map.example:8080", "[::1]:8080", "evil example", "-x.example", "x-.example", "a..b",
                           ".a", "a.", "a_b", "caf\xc3\xa9", "[::1", "::g"}) {
    auto canonical = canonicalHostName(name, "--allow-host");
    ASSERT_FALSE(canonical.ok()) << name;
    EXPECT_EQ(canonical.error().field, "--allow-host");
    EXPECT_NE(canonical.error().message.find("--allow-host"), std::string::npos) << canonical.error().message;
  }
  EXPECT_FALSE(canonicalHostName(std::string(64, 'a') + ".example", "--allow-host").ok());  // a label over 63
  EXPECT_TRUE(canonicalHostName(std::string(63, 'a') + ".example", "--allow-host").ok());
}

}  // namespace
}  // namespace skyroute
