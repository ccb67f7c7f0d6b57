// The end-to-end tests' fixture: skyrouted as a separate process on loopback, on a DDS domain of
// each test's own, with the test as its ground station (tests/daemon/ground_station.hpp), and the
// missions the tests send over the embedded default terrain.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/dds/loopback.hpp"
#include "service/mission_json.hpp"
#include "terrain/heightfield.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute::testing {

inline std::string e2eTempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_e2e_" + std::to_string(::getpid()) + "_" + name)).string();
}

class DaemonFixture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dds::useLoopbackOnly();  // the daemon and tools inherit it
    terrain_ = defaultTerrainHeightfield();
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
  }

  // Starts skyrouted on `domain` and waits until it serves (heartbeat heard, topics matched).
  void startDaemon(int domain, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(domain)};
    argv.insert(argv.end(), extra.begin(), extra.end());
    daemon_ = ChildProcess::spawn(argv, "skyrouted_" + std::to_string(domain));
    ASSERT_TRUE(daemon_.started());
    station_ = Station::open(domain);
    ASSERT_TRUE(station_);
    ASSERT_TRUE(station_->pumpUntil([&] { return station_->heartbeats > 0 || !daemon_.running(); }, 60.0))
        << daemon_.err();
    ASSERT_TRUE(daemon_.running()) << daemon_.err();
    ASSERT_TRUE(station_->requests->waitForReaders(1, 20.0).ok());
    ASSERT_TRUE(station_->statuses->waitForWriters(1, 20.0).ok());
    ASSERT_TRUE(station_->trajectories->waitForWriters(1, 20.0).ok());
  }
  // Another ground station on `domain`, once the daemon reads its requests and answers it.
  std::unique_ptr<Station> openMatchedStation(int domain) const {
    auto station = Station::open(domain);
    if (!station || !station->requests->waitForReaders(1, 20.0).ok() ||
        !station->statuses->waitForWriters(1, 20.0).ok()) {
      return nullptr;
    }
    return station;
  }
  // The same with a configuration file (written to a temporary path, kept for SIGHUP tests).
  void startDaemonWithConfig(int domain, const std::string& toml, std::vector<std::string> extra = {}) {
    config_path_ = e2eTempPath("skyrouted_" + std::to_string(domain) + ".toml");
    writeConfig(toml);
    extra.insert(extra.begin(), {"--config", config_path_});
    startDaemon(domain, extra);
  }
  void writeConfig(const std::string& toml) const { std::ofstream(config_path_) << toml; }

  void TearDown() override {
    if (daemon_.running()) {
      daemon_.signal(SIGTERM);
      EXPECT_EQ(daemon_.wait(10.0), 0) << daemon_.err();
    }
    if (!config_path_.empty()) std::filesystem::remove(config_path_);
  }

  // Pumps the station until the daemon's log holds `text` (or the daemon exits).
  bool waitForLog(const std::string& text, double timeout_s) {
    return station_->pumpUntil([&] { return daemon_.err().find(text) != std::string::npos || !daemon_.running(); },
                               timeout_s) &&
           daemon_.err().find(text) != std::string::npos;
  }
  std::size_t logCount(const std::string& text) const {
    const std::string log = daemon_.err();
    std::size_t n = 0;
    for (std::size_t at = log.find(text); at != std::string::npos; at = log.find(text, at + 1)) ++n;
    return n;
  }

  MissionRequestData demoMission() const {
    std::ifstream in(projectDataPath("missions/demo_mission.json"));
    auto mission = missionFromJson(nlohmann::json::parse(in));
    EXPECT_TRUE(mission.ok());
    return *mission;
  }
  MissionPointData above(double e, double n, double agl_m) const {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain_->heightAt(e, n) + agl_m));
  }
  // Ten kilometres west to east, through one point, 400 m above the ground.
  MissionRequestData simpleMission(const std::string& id, const std::string& vehicle, double lane_m) const {
    MissionRequestData m;
    m.request_id = id;
    m.vehicle_id = vehicle;
    m.begin = above(-5000, lane_m, 400);
    m.points = {above(0, lane_m + 200, 400)};
    m.end = above(5000, lane_m, 400);
    return m;
  }
  // Forty points low over the hills: RRT* must search on most legs, so with a large iteration
  // budget (planning.leg_max_iterations = 2000000) planning it takes many seconds.
  MissionRequestData slowMission(const std::string& id, const std::string& vehicle) const {
    MissionRequestData m = simpleMission(id, vehicle, 0.0);
    m.points.clear();
    for (int i = 0; i < 40; ++i) m.points.push_back(above(-5000 + 250 * i, 3000.0 * std::sin(0.7 * i), 200));
    return m;
  }
  static Eigen::Vector3d enuOf(const MissionPointData& p) { return p.enu_m; }

  static inline std::shared_ptr<const Heightfield> terrain_;
  ChildProcess daemon_;
  std::unique_ptr<Station> station_;
  std::string config_path_;
};

}  // namespace skyroute::testing
