// skyrouted's ROS 2 mirror from outside, with a real daemon process: a reader set up the way ROS
// 2's Cyclone RMW sets one up receives the path and its poses are the trajectory's samples; a
// packet capture decoded by tshark shows the writer announced with the ROS type name and without
// type information; ros2.enabled = false mirrors nothing. Domain ids 197 to 199 belong to this file.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "service/dds/loopback.hpp"
#include "terrain/heightfield.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/dds/ros2_reader.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::RmwLikeReader;
using testing::Station;

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_ros2_" + std::to_string(::getpid()) + "_" + name)).string();
}

class Ros2E2E : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::useLoopbackOnly(); }  // the daemon inherits it

  // Starts skyrouted and plans one short mission for "uav-1" (ROS name uav_1); returns its trajectory.
  std::optional<TrajectoryData> planWithDaemon(int domain, std::vector<std::string> extra = {}) {
    std::vector<std::string> argv{SKYROUTED, "--domain", std::to_string(domain)};
    argv.insert(argv.end(), extra.begin(), extra.end());
    daemon_ = ChildProcess::spawn(argv, "skyrouted_ros2_" + std::to_string(domain));
    station_ = Station::open(domain);
    if (!station_ || !station_->pumpUntil([&] { return station_->heartbeats > 0 || !daemon_.running(); }, 60.0) ||
        !daemon_.running() || !station_->requests->waitForReaders(1, 20.0).ok()) {
      ADD_FAILURE() << "skyrouted did not come up: " << daemon_.err();
      return std::nullopt;
    }
    auto terrain = testing::defaultTerrainHeightfield();
    auto above = [&](double e, double n) {
      return MissionPointData::enu(Eigen::Vector3d(e, n, terrain->heightAt(e, n) + 400.0));
    };
    MissionRequestData m;
    m.request_id = "ros2-" + std::to_string(domain);
    m.vehicle_id = "uav-1";
    m.begin = above(-2000, 300);
    m.end = above(2000, 300);
    if (!station_->requests->write(m).ok() || !station_->waitTerminal({m.request_id}, 120.0) ||
        station_->terminal(m.request_id)->state != PlanState::kSucceeded ||
        !station_->pumpUntil([&] { return station_->latest("uav-1") != nullptr; }, 10.0)) {
      ADD_FAILURE() << "no trajectory: " << daemon_.err();
      return std::nullopt;
    }
    return *station_->latest("uav-1");
  }

  void TearDown() override {
    if (daemon_.running()) {
      daemon_.signal(SIGTERM);
      EXPECT_EQ(daemon_.wait(10.0), 0) << daemon_.err();
    }
  }

  ChildProcess daemon_;
  std::unique_ptr<Station> station_;
};

TEST_F(Ros2E2E, ARmwLikeReaderGetsTheDaemonsPathAndItsPosesAreTheTrajectory) {
  const auto trajectory = planWithDaemon(197);
  ASSERT_TRUE(trajectory);
  auto node = dds::createParticipant(197);
  ASSERT_TRUE(node.ok());
  // Joins after the path was written: latched, it still gets it.
  RmwLikeReader<nav_msgs_msg_dds__Path_> path(node->get(), &nav_msgs_msg_dds__Path__desc, "rt/skyroute/uav_1/path");
  ASSERT_TRUE(path.ok());
  auto received = path.waitLatest(20.0);
  ASSERT_TRUE(received) << "nothing on rt/skyroute/uav_1/path; daemon log:\n" << daemon_.err();
  EXPECT_EQ(received->frame_id, "map");
  EXPECT_EQ(static_cast<std::int64_t>(received->sec) * 1'000'000'000 + received->nanosec, trajectory->created_utc_ns);
  ASSERT_EQ(received->poses.size(), trajectory->samples.size());
  for (std::size_t i = 0; i < trajectory->samples.size(); ++i) {
    const auto& pose = received->poses[i];
    const auto& s = trajectory->samples[i];
    ASSERT_EQ(pose.position, s.position_enu_m) << "pose " << i;
    ASSERT_EQ(static_cast<std::int64_t>(pose.sec) * 1'000'000'000 + pose.nanosec, s.utc_ns) << "pose " << i;
    ASSERT_EQ(pose.frame_id, "map");
    const double expected_yaw = M_PI / 2.0 - s.heading_deg * M_PI / 180.0;
    ASSERT_NEAR(std::remainder(testing::yawOf(pose.orientation) - expected_yaw, 2 * M_PI), 0.0, 1e-9) << "pose " << i;
  }

  RmwLikeReader<geographic_msgs_msg_dds__GeoPoint_> origin(node->get(), &geographic_msgs_msg_dds__GeoPoint__desc,
                                                           "rt/skyroute/uav_1/origin");
  auto where = origin.waitLatest(10.0);
  ASSERT_TRUE(where);
  const GeoPoint anchor = testing::defaultTerrainHeightfield()->frame().anchor();
  EXPECT_EQ(where->latitude, anchor.lat_deg);
  EXPECT_EQ(where->longitude, anchor.lon_deg);
  EXPECT_NE(daemon_.err().find("event=ros2_topics vehicle=uav-1 path=rt/skyroute/uav_1/path"), std::string::npos)
      << daemon_.err();
}

// The writers' discovery data (SEDP DATA(w) submessages), one text block each, as tshark prints them.
std::vector<std::string> writerAnnouncements(const std::string& tshark_text) {
  std::vector<std::string> blocks;
  std::size_t at = tshark_text.find("submessageId: DATA");
  while (at != std::string::npos) {
    const std::size_t next = tshark_text.find("submessageId:", at + 1);
    std::string block = tshark_text.substr(at, next == std::string::npos ? std::string::npos : next - at);
    if (block.find("writerEntityId: ENTITYID_BUILTIN_PUBLICATIONS_WRITER") != std::string::npos) blocks.push_back(block);
    at = tshark_text.find("submessageId: DATA", at + 1);
  }
  return blocks;
}

TEST_F(Ros2E2E, TsharkSeesThePathWriterWithTheRosTypeNameAndNoTypeInformation) {
  const std::string dumpcap = "/usr/bin/dumpcap", tshark = "/usr/bin/tshark";
  if (!std::filesystem::exists(dumpcap) || !std::filesystem::exists(tshark)) {
    GTEST_SKIP() << "tshark is not installed (Debian: apt-get install tshark; scripts/setup.sh installs it)";
  }
  const std::string pcap = tempPath("ros2.pcapng");
  std::filesystem::remove(pcap);
  ChildProcess capture = ChildProcess::spawn({dumpcap, "-q", "-i", "lo", "-f", "udp", "-w", pcap}, "dumpcap");
  // dumpcap writes the file's header once it captures; it exits at once when it may not.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (capture.running() && (!std::filesystem::exists(pcap) || std::filesystem::file_size(pcap) == 0) &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!capture.running() || !std::filesystem::exists(pcap)) {
    GTEST_SKIP() << "dumpcap cannot capture on lo here (it needs root or CAP_NET_RAW/CAP_NET_ADMIN): " << capture.err();
  }

  ASSERT_TRUE(planWithDaemon(198));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  capture.signal(SIGINT);
  ASSERT_EQ(capture.wait(10.0), 0) << capture.err();

  ChildProcess decode = ChildProcess::spawn({tshark, "-r", pcap, "-O", "rtps", "-V", "-Y", "rtps.param.typeName"}, "tshark");
  ASSERT_EQ(decode.wait(60.0), 0) << decode.err();
  const std::string text = decode.out();
  std::filesystem::remove(pcap);
  const auto blocks = writerAnnouncements(text);
  ASSERT_FALSE(blocks.empty()) << "no writer announcements decoded";

  bool path_writer = false, trajectory_writer = false;
  for (const std::string& b : blocks) {
    if (b.find("topic: rt/skyroute/uav_1/path") != std::string::npos) {
      path_writer = true;
      EXPECT_NE(b.find("typeName: nav_msgs::msg::dds_::Path_"), std::string::npos) << b;
      // Type information is parameter 0x0075 (PID_TYPE_INFORMATION); ROS 2 types send none.
      EXPECT_EQ(b.find("(0x0075)"), std::string::npos) << b;
      // XCDR1 only: the default, so either no data representation at all, or XCDR alone.
      EXPECT_EQ(b.find("XCDR2_DATA_REPRESENTATION"), std::string::npos) << b;
      EXPECT_NE(b.find("TRANSIENT_LOCAL_DURABILITY_QOS"), std::string::npos) << b;
      EXPECT_NE(b.find("RELIABLE_RELIABILITY_QOS"), std::string::npos) << b;
      EXPECT_NE(b.find("writer (no key)"), std::string::npos) << b;  // ROS 2 types are keyless
    }
    if (b.find("typeName: skyroute_msgs::Trajectory") != std::string::npos) {
      trajectory_writer = true;
      // The check above can fail: our own types do announce their type information.
      EXPECT_NE(b.find("(0x0075)"), std::string::npos) << b;
    }
  }
  EXPECT_TRUE(path_writer) << "no writer of rt/skyroute/uav_1/path in the capture";
  EXPECT_TRUE(trajectory_writer);
}

TEST_F(Ros2E2E, Ros2EnabledFalseMirrorsNothing) {
  const std::string config = tempPath("ros2_off.toml");
  std::ofstream(config) << "[ros2]\nenabled = false\n";
  ASSERT_TRUE(planWithDaemon(199, {"--config", config}));
  auto node = dds::createParticipant(199);
  ASSERT_TRUE(node.ok());
  RmwLikeReader<nav_msgs_msg_dds__Path_> path(node->get(), &nav_msgs_msg_dds__Path__desc, "rt/skyroute/uav_1/path");
  EXPECT_FALSE(path.waitLatest(3.0));
  dds_subscription_matched_status_t matched{};
  ASSERT_EQ(dds_get_subscription_matched_status(path.reader(), &matched), DDS_RETCODE_OK);
  EXPECT_EQ(matched.total_count, 0u);
  EXPECT_EQ(daemon_.err().find("event=ros2_topics"), std::string::npos);
  std::filesystem::remove(config);
}

}  // namespace
}  // namespace skyroute
