// The ROS 2 mirror as a ROS 2 node would see it: a reader set up like ROS 2's Cyclone RMW's (type
// name, rt/ topic, XCDR1, no type information) that joins after the trajectory was written gets
// the path, pose by pose, and the frame origin; a retraction empties the path; vehicle ids that
// sanitise alike get topics of their own. Domain ids 195 and 196 belong to this file.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "service/dds/loopback.hpp"
#include "service/dds/ros2_mirror.hpp"
#include "service/height_datum.hpp"
#include "tests/dds/ros2_reader.hpp"

namespace skyroute {
namespace {

using dds::Entity;
using testing::RmwLikeReader;

class LoopbackEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { dds::useLoopbackOnly(); }
};
const auto* const kLoopback = ::testing::AddGlobalTestEnvironment(new LoopbackEnvironment);

constexpr GeoPoint kFrameOrigin{46.94, 15.12, 0.0};

Entity participantOn(dds_domainid_t domain) {
  auto p = dds::createParticipant(domain);
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().describe());
  return p.ok() ? std::move(*p) : Entity();
}

// A short trajectory whose samples differ in every field the path carries.
TrajectoryData trajectoryOf(const std::string& vehicle, double offset_m) {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = vehicle + "-plan";
  t.revision = 3;
  t.created_utc_ns = 1'700'000'000'123'456'789;
  for (int i = 0; i < 5; ++i) {
    TrajectorySampleData s;
    s.t_rel_s = 0.5 * i;
    s.utc_ns = t.created_utc_ns + 500'000'000LL * i + 7;
    s.position_enu_m = Eigen::Vector3d(offset_m + 10.0 * i, -3.0 * i, 600.0 + i);
    s.heading_deg = 350.0 + 10.0 * i;  // crosses north
    if (s.heading_deg >= 360.0) s.heading_deg -= 360.0;
    t.samples.push_back(s);
  }
  return t;
}

void expectPathShows(const testing::RosPathCopy& path, const TrajectoryData& t) {
  EXPECT_EQ(path.frame_id, "map");
  EXPECT_EQ(static_cast<std::int64_t>(path.sec) * 1'000'000'000 + path.nanosec, t.created_utc_ns);
  ASSERT_EQ(path.poses.size(), t.samples.size());
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const auto& pose = path.poses[i];
    const auto& s = t.samples[i];
    EXPECT_EQ(pose.frame_id, "map");
    EXPECT_EQ(static_cast<std::int64_t>(pose.sec) * 1'000'000'000 + pose.nanosec, s.utc_ns) << "pose " << i;
    EXPECT_EQ(pose.position, s.position_enu_m) << "pose " << i;
    EXPECT_NEAR(pose.orientation.norm(), 1.0, 1e-12);
    // The heading (clockwise from north) as an ENU yaw (counter-clockwise from east).
    const double expected_yaw = M_PI / 2.0 - s.heading_deg * M_PI / 180.0;
    EXPECT_NEAR(std::remainder(testing::yawOf(pose.orientation) - expected_yaw, 2.0 * M_PI), 0.0, 1e-9) << "pose " << i;
  }
}

TEST(Ros2Mirror, ARmwLikeReaderThatJoinsLateGetsThePathAndTheOrigin) {
  Entity daemon = participantOn(195);
  Entity ros_node = participantOn(195);
  auto mirror = dds::Ros2Mirror::create(daemon.get(), kFrameOrigin);
  const TrajectoryData t = trajectoryOf("uav-1", 0.0);  // "uav-1" is no ROS name: uav_1
  mirror->publish(t);

  RmwLikeReader<nav_msgs_msg_dds__Path_> path(ros_node.get(), &nav_msgs_msg_dds__Path__desc, "rt/skyroute/uav_1/path");
  ASSERT_TRUE(path.ok());
  // Like ROS 2's types, ours carry no type information: Cyclone matches them by type name alone.
  dds_typeinfo_t* info = nullptr;
  EXPECT_NE(dds_get_typeinfo(path.topic(), &info), DDS_RETCODE_OK);
  auto received = path.waitLatest(10.0);
  ASSERT_TRUE(received) << "no path on rt/skyroute/uav_1/path";
  expectPathShows(*received, t);

  RmwLikeReader<geographic_msgs_msg_dds__GeoPoint_> origin(ros_node.get(), &geographic_msgs_msg_dds__GeoPoint__desc,
                                                           "rt/skyroute/uav_1/origin");
  auto where = origin.waitLatest(10.0);
  ASSERT_TRUE(where);
  EXPECT_EQ(where->latitude, kFrameOrigin.lat_deg);
  EXPECT_EQ(where->longitude, kFrameOrigin.lon_deg);
  // GeoPoint's altitude is above the ellipsoid: the origin's AMSL altitude plus the geoid's.
  auto geoid = Egm96Geoid::load();
  if (geoid.ok()) {
    EXPECT_NEAR(where->altitude, *geoid->ellipsoidFromAmslM(kFrameOrigin.lat_deg, kFrameOrigin.lon_deg, 0.0), 1e-9);
    EXPECT_GT(where->altitude, 40.0);  // the geoid is about 47 m above the ellipsoid in Styria
  } else {
    EXPECT_TRUE(std::isnan(where->altitude)) << "without the EGM96 grid the altitude must say unknown";
  }

  mirror->retract("uav-1");
  auto emptied = path.waitLatest(10.0);
  ASSERT_TRUE(emptied);
  EXPECT_TRUE(emptied->poses.empty());
  EXPECT_EQ(emptied->frame_id, "map");
}

TEST(Ros2Mirror, IdsThatSanitiseAlikeGetTopicsOfTheirOwn) {
  Entity daemon = participantOn(196);
  Entity ros_node = participantOn(196);
  auto mirror = dds::Ros2Mirror::create(daemon.get(), kFrameOrigin);
  const TrajectoryData dashed = trajectoryOf("uav-1", 0.0);
  const TrajectoryData own = trajectoryOf("uav_1", 5000.0);
  mirror->publish(dashed);
  mirror->publish(own);  // "uav_1" is a valid name: it takes it, "uav-1" moves to a suffixed one

  RosNameRegistry names;
  (void)names.assign("uav-1");
  const std::string moved = names.assign("uav_1").displaced_name;
  ASSERT_NE(moved, "uav_1");

  RmwLikeReader<nav_msgs_msg_dds__Path_> own_path(ros_node.get(), &nav_msgs_msg_dds__Path__desc,
                                                  "rt/skyroute/uav_1/path");
  RmwLikeReader<nav_msgs_msg_dds__Path_> moved_path(ros_node.get(), &nav_msgs_msg_dds__Path__desc,
                                                    dds::Ros2Mirror::pathTopic(moved));
  auto a = own_path.waitLatest(10.0);
  auto b = moved_path.waitLatest(10.0);
  ASSERT_TRUE(a);
  ASSERT_TRUE(b) << "no path on " << dds::Ros2Mirror::pathTopic(moved);
  expectPathShows(*a, own);
  expectPathShows(*b, dashed);

  // Later revisions keep to the names given.
  TrajectoryData next = dashed;
  next.revision = 4;
  next.samples.pop_back();
  mirror->publish(next);
  auto c = moved_path.waitLatest(10.0);
  ASSERT_TRUE(c);
  expectPathShows(*c, next);
}

}  // namespace
}  // namespace skyroute
