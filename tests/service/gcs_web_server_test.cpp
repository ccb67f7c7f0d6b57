// The web map's server, in process, through httplib's client: the address rules, the page and its
// assets served from the binary with nothing fetched from elsewhere, the JSON state endpoint and
// the event stream following the state, a port in use told apart from a bad address, binding only
// the address given, and a prompt stop with a browser still listening; the event streams' budget
// and the life of a connection, through raw sockets (tests/dds/gcs_serve_guard_cli_test.cpp
// attacks the command's server with the rest).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <regex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/gcs_web_server.hpp"
#include "tests/raw_http_socket.hpp"
#include "tests/service/gcs_fixtures.hpp"
#include "tests/tcp_ports.hpp"

// After Eigen (through the headers above): httplib brings <resolv.h>, whose _res macro breaks
// Eigen's declarations.
#include <httplib.h>

namespace skyroute {
namespace {

using nlohmann::json;

class GcsWebServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    state_ = testing::embeddedTerrainMapState();
    ASSERT_TRUE(state_);
    auto server = GcsWebServer::start({"127.0.0.1", 0}, state_);
    ASSERT_TRUE(server.ok()) << server.error().message;
    server_ = std::move(*server);
    ASSERT_GT(server_->port(), 0);
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(10, 0);
  }
  void addTrajectory(const std::string& vehicle, std::uint32_t revision) {
    state_->onTrajectory(testing::trajectoryThrough(state_terrain().frame(), vehicle, revision,
                                                    {{-2000, 0, 1000}, {2000, 500, 1100}}, utcNowNs()));
  }
  const Heightfield& state_terrain() {
    if (!terrain_) terrain_ = testing::defaultTerrainHeightfield();
    return *terrain_;
  }

  std::shared_ptr<GcsMapState> state_;
  std::shared_ptr<const Heightfield> terrain_;
  std::unique_ptr<GcsWebServer> server_;
  std::unique_ptr<httplib::Client> client_;
};

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

TEST(ServeAddress, AcceptsNumericAddressesAndLocalhostWithAPort) {
  auto a = parseServeAddress("127.0.0.1:8080");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 8080);
  a = parseServeAddress("[::1]:0");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "::1");
  EXPECT_EQ(a->port, 0);
  a = parseServeAddress("localhost:65535");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->host, "127.0.0.1");
  EXPECT_EQ(a->port, 65535);
}

TEST(ServeAddress, RejectsAnythingElseAsABadAddress) {
  for (const char* text : {"", "8080", "127.0.0.1", "127.0.0.1:", ":8080", "127.0.0.1:65536", "127.0.0.1:-1",
                           "127.0.0.1:80x", "::1:8080", "example.com:8080", "300.1.1.1:80", "[]:80"}) {
    auto a = parseServeAddress(text);
    ASSERT_FALSE(a.ok()) << text;
    EXPECT_EQ(a.error().kind, ServeError::Kind::kBadAddress) << text;
    EXPECT_NE(a.error().message.find("HOST:PORT"), std::string::npos) << a.error().message;
  }
}

TEST_F(GcsWebServerTest, ServesThePageAndItsAssetsWithNothingFromElsewhere) {
  std::string everything;
  for (const auto& [path, type] : {std::pair{"/", "text/html"}, {"/gcs.js", "text/javascript"}, {"/gcs.css", "text/css"}}) {
    auto res = client_->Get(path);
    ASSERT_TRUE(res) << path << ": " << httplib::to_string(res.error());
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->get_header_value("Content-Type").rfind(type, 0), 0u) << path;
    everything += res->body;
  }
  auto page = client_->Get("/");
  EXPECT_NE(page->body.find("<script src=\"gcs.js\">"), std::string::npos);
  EXPECT_NE(page->body.find("href=\"gcs.css\""), std::string::npos);
  // The only absolute URL is the SVG namespace name, which browsers never fetch.
  const std::regex url(R"(https?://[^"'\s)]*)");
  for (auto it = std::sregex_iterator(everything.begin(), everything.end(), url); it != std::sregex_iterator(); ++it) {
    EXPECT_EQ(it->str(), "http://www.w3.org/2000/svg") << "the page would fetch " << it->str();
  }
  EXPECT_EQ(everything.find("@import"), std::string::npos);

  auto png = client_->Get("/hillshade.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->status, 200);
  EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(png->body, state_->image().png);

  auto missing = client_->Get("/nothing-here");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
}

TEST_F(GcsWebServerTest, StateEndpointGivesTheCurrentVersionAndFollowsNewRevisions) {
  auto res = client_->Get("/state.json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(res->get_header_value("Cache-Control"), "no-store");
  json s = json::parse(res->body);
  EXPECT_EQ(s["version"], 1);
  EXPECT_EQ(res->get_header_value("X-State-Version"), "1");
  EXPECT_TRUE(s["vehicles"].empty());
  EXPECT_TRUE(s["no_fly_zones"].empty());

  addTrajectory("uav-7", 0);
  addTrajectory("uav-7", 1);
  res = client_->Get("/state.json");
  ASSERT_TRUE(res);
  s = json::parse(res->body);
  EXPECT_EQ(s["version"], 3);
  EXPECT_EQ(res->get_header_value("X-State-Version"), "3");
  ASSERT_EQ(s["vehicles"].size(), 1u);
  EXPECT_EQ(s["vehicles"][0]["vehicle_id"], "uav-7");
  EXPECT_EQ(s["vehicles"][0]["trajectory"]["revision"], 1);
}

TEST_F(GcsWebServerTest, EventStreamSendsTheStateAtOnceThenEachNewVersion) {
  std::mutex mutex;
  std::string received;
  std::atomic<int> events{0};
  std::thread browser([&] {
    httplib::Client events_client("127.0.0.1", server_->port());
    events_client.set_read_timeout(20, 0);
    events_client.Get("/events", [&](const char* data, std::size_t length) {
      std::lock_guard lock(mutex);
      received.append(data, length);
      std::size_t count = 0;
      for (std::size_t at = received.find("\n\n"); at != std::string::npos; at = received.find("\n\n", at + 2)) ++count;
      events = static_cast<int>(count);
      return count < 2;  // disconnect after the second event
    });
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (events < 1 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (events != 1) {
    server_->stop();  // ends the stream, so the browser thread can be joined
    browser.join();
    FAIL() << "the stream did not send the state at once";
  }
  addTrajectory("uav-8", 5);
  browser.join();

  std::lock_guard lock(mutex);
  const std::string first = received.substr(0, received.find("\n\n"));
  const std::string second = received.substr(first.size() + 2);
  EXPECT_EQ(first.rfind("id: 1\ndata: {", 0), 0u) << first.substr(0, 40);
  EXPECT_EQ(second.rfind("id: 2\ndata: {", 0), 0u) << second.substr(0, 40);
  const json s = json::parse(second.substr(second.find('{'), second.find("\n\n") - second.find('{')));
  EXPECT_EQ(s["version"], 2);
  EXPECT_EQ(s["vehicles"][0]["vehicle_id"], "uav-8");
  EXPECT_EQ(s["vehicles"][0]["trajectory"]["revision"], 5);
}

TEST_F(GcsWebServerTest, StopsPromptlyWithABrowserStillListening) {
  std::atomic<bool> connected{false};
  std::thread browser([&] {
    httplib::Client events_client("127.0.0.1", server_->port());
    events_client.set_read_timeout(30, 0);
    events_client.Get("/events", [&](const char*, std::size_t) {
      connected = true;
      return true;
    });
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!connected && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_TRUE(connected) << "the stream did not start";
  const auto started = std::chrono::steady_clock::now();
  server_->stop();
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(3));
  browser.join();
  EXPECT_FALSE(client_->Get("/state.json"));  // nobody listens any more
}

TEST_F(GcsWebServerTest, StoppingRightAfterStartingNeverHangs) {
  for (int i = 0; i < 20; ++i) {
    auto server = GcsWebServer::start({"127.0.0.1", 0}, state_);
    ASSERT_TRUE(server.ok()) << server.error().message;
    const auto started = std::chrono::steady_clock::now();
    (*server)->stop();
    ASSERT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(2)) << "round " << i;
  }
}

TEST_F(GcsWebServerTest, BindsOnlyTheAddressGiven) {
  // All of 127/8 reaches this machine on Linux; a server bound to 127.0.0.1 must not answer on
  // 127.0.0.2.
  httplib::Client other("127.0.0.2", server_->port());
  other.set_connection_timeout(2, 0);
  EXPECT_FALSE(other.Get("/state.json"));
  EXPECT_TRUE(client_->Get("/state.json"));
}

TEST_F(GcsWebServerTest, APortInUseIsToldApartFromABadAddress) {
  testing::HeldTcpPort busy;
  ASSERT_GT(busy.port(), 0);
  auto in_use = GcsWebServer::start({"127.0.0.1", busy.port()}, state_);
  ASSERT_FALSE(in_use.ok());
  EXPECT_EQ(in_use.error().kind, ServeError::Kind::kPortInUse);
  EXPECT_NE(in_use.error().message.find("in use"), std::string::npos) << in_use.error().message;
  EXPECT_NE(in_use.error().message.find(std::to_string(busy.port())), std::string::npos) << in_use.error().message;

  // The port this test's server holds is in use too, for a second server.
  auto second = GcsWebServer::start({"127.0.0.1", server_->port()}, state_);
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().kind, ServeError::Kind::kPortInUse);

  // 192.0.2.1 (a documentation address) is not an address of this machine.
  auto foreign = GcsWebServer::start({"192.0.2.1", 0}, state_);
  ASSERT_FALSE(foreign.ok());
  EXPECT_EQ(foreign.error().kind, ServeError::Kind::kBadAddress);
  EXPECT_NE(foreign.error().message.find("not an address of this machine"), std::string::npos) << foreign.error().message;
}

TEST_F(GcsWebServerTest, EventStreamsHaveABudgetAndAClosedPageGivesItsSlotBack) {
  GcsWebLimits limits;
  limits.max_event_streams = 2;
  auto started = GcsWebServer::start({"127.0.0.1", 0}, state_, limits);
  ASSERT_TRUE(started.ok()) << started.error().message;
  const int port = (*started)->port();
  std::vector<testing::RawHttpSocket> streams;
  for (int i = 0; i < 2; ++i) {
    streams.emplace_back(port);
    ASSERT_TRUE(streams.back().send(testing::requestHead("GET /events", port)));
    ASSERT_TRUE(streams.back().readUntil("}\n\n", 30.0)) << "stream " << i;
  }
  testing::RawHttpSocket third(port);
  ASSERT_TRUE(third.send(testing::requestHead("GET /events", port)));
  ASSERT_TRUE(third.readUntilEnd(30.0)) << third.received().substr(0, 300);
  EXPECT_EQ(third.status(), 503) << third.received().substr(0, 300);
  EXPECT_NE(third.body().find("has 2 event streams open"), std::string::npos) << third.body();

  // The server notices a closed page within a second (not at the next keep-alive, 15 s on).
  streams.front().close();
  const auto closed = std::chrono::steady_clock::now();
  bool served = false;
  while (!served && secondsSince(closed) < 30.0) {
    testing::RawHttpSocket again(port);
    served = again.send(testing::requestHead("GET /events", port)) && again.readUntil("\r\n\r\n", 30.0) &&
             again.status() == 200;
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(100));  // asks again in a moment
  }
  EXPECT_TRUE(served) << "the slot of a closed page never came back";
  EXPECT_LT(secondsSince(closed), 10.0) << "a closed page held its slot until the next keep-alive";
}

TEST_F(GcsWebServerTest, AConnectionEndsWhenItsLifeIsOverWhileAnEventStreamLivesOn) {
  GcsWebLimits limits;
  limits.connection_life_s = 1.0;
  limits.write_timeout_s = 60.0;  // so that the life ends the slow reader, not a write's timeout
  auto started = GcsWebServer::start({"127.0.0.1", 0}, state_, limits);
  ASSERT_TRUE(started.ok()) << started.error().message;
  const int port = (*started)->port();
  testing::RawHttpSocket stream(port);
  ASSERT_TRUE(stream.send(testing::requestHead("GET /events", port)));
  ASSERT_TRUE(stream.readUntil("}\n\n", 30.0));

  // A state of 80 vehicles of 2000 samples: more than the kernel's buffers hold, so that the
  // server must wait for a slow reader to take it.
  for (int i = 0; i < 80; ++i) {
    state_->onTrajectory(testing::trajectoryThrough(state_terrain().frame(), "uav-" + std::to_string(i), 0,
                                                    {{-2000, 0, 1000}, {2000, 500, 1100}}, utcNowNs(), 2000));
  }
  const std::size_t state_bytes = state_->snapshot().json->size();
  ASSERT_GT(state_bytes, 6'000'000u);
  // The client reads 128 KB at 25 KB/s through a 4 KB window (five seconds, five lives), then
  // as fast as it can: it gets what the server had written before the life ended, not the rest.
  testing::RawHttpSocket reader(port, 4096);
  ASSERT_TRUE(reader.send(testing::requestHead("GET /state.json", port)));
  const auto asked = std::chrono::steady_clock::now();
  while (!reader.ended() && reader.received().size() < 128'000 && secondsSince(asked) < 60.0) {
    reader.readSome(512, 5.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the client's pace, not a wait for the server
  }
  EXPECT_TRUE(reader.readUntilEnd(60.0)) << "the server did not end the connection";
  EXPECT_EQ(reader.status(), 200);
  EXPECT_LT(reader.body().size(), state_bytes) << "the slow reader got the whole state in " << secondsSince(asked) << " s";

  // The stream, older than a connection's life by now, still follows the state.
  EXPECT_TRUE(stream.readUntil("id: 81\n", 30.0)) << "the event stream ended with the connections' life";
}

}  // namespace
}  // namespace skyroute
