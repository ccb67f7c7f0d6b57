// `skyroute gcs --serve` as a process: it serves the live map's state on the address it prints
// and stops cleanly; a malformed or foreign address is a usage error (2) naming --serve, a port in
// use exits 4 and says so, an unreadable --dem exits 3 naming it; --help documents the codes.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "service/dds/loopback.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/web_driver.hpp"  // eventually(); last: see its note on httplib and Eigen
#include "tests/tcp_ports.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;

constexpr const char* kDomain = "206";  // this file's DDS domain (nothing here publishes on it)

struct Outcome {
  int code = -1;
  std::string out, err;
};
Outcome gcs(std::vector<std::string> args, const std::string& name) {
  args.insert(args.begin(), {SKYROUTE_CLI, "gcs", "--domain", kDomain});
  ChildProcess p = ChildProcess::spawn(args, name);
  Outcome r;
  r.code = p.wait(60.0);
  r.out = p.out();
  r.err = p.err();
  return r;
}

class GcsServeCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::useLoopbackOnly(); }
};

TEST_F(GcsServeCli, ServesTheStateOnThePrintedAddressAndStopsCleanly) {
  ChildProcess p = ChildProcess::spawn({SKYROUTE_CLI, "gcs", "--domain", kDomain, "--serve", "127.0.0.1:0"}, "serve_ok");
  int port = 0;
  ASSERT_TRUE(testing::eventually(
      [&] {
        const std::string out = p.out();
        const std::string prefix = "live map on http://127.0.0.1:";
        if (const std::size_t at = out.find(prefix); at != std::string::npos) port = std::stoi(out.substr(at + prefix.size()));
        return port > 0 || !p.running();
      },
      30.0))
      << p.err();
  ASSERT_GT(port, 0) << p.out() << p.err();
  httplib::Client client("127.0.0.1", port);
  auto res = client.Get("/state.json");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
  const nlohmann::json state = nlohmann::json::parse(res->body);
  EXPECT_EQ(state["map"]["terrain"], "default_terrain.tif");  // the embedded terrain by default
  EXPECT_TRUE(state["vehicles"].empty());
  p.signal(SIGINT);
  EXPECT_EQ(p.wait(10.0), 0) << p.err();
  EXPECT_FALSE(client.Get("/state.json"));
}

TEST_F(GcsServeCli, BadAddressesAreUsageErrorsNamingServe) {
  for (const std::string address : {"8080", "127.0.0.1:70000", "example.com:8080", "192.0.2.1:8080"}) {
    const Outcome r = gcs({"--serve", address, "--timeout", "1"}, "serve_bad");
    EXPECT_EQ(r.code, 2) << address << ": " << r.err;
    EXPECT_NE(r.err.find("--serve"), std::string::npos) << r.err;
  }
}

TEST_F(GcsServeCli, APortInUseExitsFourAndSaysSo) {
  testing::HeldTcpPort busy;
  ASSERT_GT(busy.port(), 0);
  const Outcome r = gcs({"--serve", "127.0.0.1:" + std::to_string(busy.port()), "--timeout", "1"}, "serve_busy");
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("--serve"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("already in use"), std::string::npos) << r.err;
}

TEST_F(GcsServeCli, AnUnreadableDemExitsThreeNamingIt) {
  const Outcome r = gcs({"--serve", "127.0.0.1:0", "--dem", "/nonexistent/terrain.tif", "--timeout", "1"}, "serve_dem");
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("--dem"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/terrain.tif"), std::string::npos) << r.err;
}

TEST_F(GcsServeCli, HelpDocumentsServeAndItsExitCodes) {
  const Outcome r = gcs({"--help"}, "serve_help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--serve HOST:PORT"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("exits 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a port in use exits 4"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace skyroute
