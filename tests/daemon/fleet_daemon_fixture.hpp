// The fleet end-to-end tests' set-up: skyrouted as a separate process on its own DDS domain, and
// the test as the ground station, with a FleetRequest writer and a FleetStatus reader of its own
// next to the common station's topics (ground_station.hpp).
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "service/dds/loopback.hpp"
#include "service/dds/wait_loop.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute::testing {

class FleetDaemonTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dds::useLoopbackOnly();
    terrain_ = defaultTerrainHeightfield();
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
  }

  // Starts the daemon on `domain` (with extra arguments) and waits up to wait_s for its heartbeat
  // and for every topic the tests use to match.
  void startDaemon(int domain, const std::vector<std::string>& extra_args, const std::string& name, double wait_s) {
    std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(domain)};
    argv.insert(argv.end(), extra_args.begin(), extra_args.end());
    daemon_ = ChildProcess::spawn(argv, name);
    ASSERT_TRUE(daemon_.started());
    station_ = Station::open(domain);
    ASSERT_TRUE(station_);
    const dds_entity_t p = station_->participant.get();
    fleet_requests_.emplace(std::move(dds::Writer<FleetRequestData>::create(p).value()));
    fleet_statuses_.emplace(std::move(dds::Reader<FleetStatusData>::create(p).value()));
    ASSERT_TRUE(station_->loop
                    ->add(*fleet_statuses_, [this](FleetStatusData&& s) { fleet_log_.push_back(std::move(s)); },
                          [](const Error&) {})
                    .ok());
    ASSERT_TRUE(station_->pumpUntil([&] { return station_->heartbeats > 0 || !daemon_.running(); }, wait_s))
        << daemon_.err();
    ASSERT_TRUE(daemon_.running()) << daemon_.err();
    const double match_s = wait_s / 3.0;
    ASSERT_TRUE(fleet_requests_->waitForReaders(1, match_s).ok());
    ASSERT_TRUE(fleet_statuses_->waitForWriters(1, match_s).ok());
    ASSERT_TRUE(station_->trajectories->waitForWriters(1, match_s).ok());
    ASSERT_TRUE(station_->obstacles->waitForReaders(1, match_s).ok());
  }
  void TearDown() override {
    if (daemon_.running()) {
      daemon_.signal(SIGTERM);
      EXPECT_EQ(daemon_.wait(10.0), 0) << daemon_.err();
    }
    fleet_statuses_.reset();
    fleet_requests_.reset();
  }

  MissionPointData above(double e, double n, double agl_m) const {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain_->heightAt(e, n) + agl_m));
  }

  static inline std::shared_ptr<const Heightfield> terrain_;
  ChildProcess daemon_;
  std::unique_ptr<Station> station_;
  std::optional<dds::Writer<FleetRequestData>> fleet_requests_;
  std::optional<dds::Reader<FleetStatusData>> fleet_statuses_;
  std::vector<FleetStatusData> fleet_log_;
};

}  // namespace skyroute::testing
