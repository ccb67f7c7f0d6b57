// Every message type goes through a real Cyclone DDS writer and reader (serialised by the
// generated descriptors) on loopback and comes back equal; a late-joining reader gets the current
// trajectory of every vehicle. Each test has its own domain id (ctest runs tests in parallel).
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "service/dds/loopback.hpp"
#include "service/dds/typed_io.hpp"
#include "service/dds/wait_loop.hpp"
#include "tests/dds/named_trajectory.hpp"

namespace skyroute {
namespace {

using dds::Entity;

class LoopbackEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { dds::useLoopbackOnly(); }
};
const auto* const kLoopback = ::testing::AddGlobalTestEnvironment(new LoopbackEnvironment);

// Domain ids 110..119 belong to this file.
Entity participantOn(dds_domainid_t domain) {
  auto p = dds::createParticipant(domain);
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().describe());
  return p.ok() ? std::move(*p) : Entity();
}

// Writes one message and returns what a reader in another participant receives.
template <class Plain>
std::optional<Plain> roundTrip(dds_domainid_t domain, const Plain& message) {
  Entity pub = participantOn(domain);
  Entity sub = participantOn(domain);
  auto writer = dds::Writer<Plain>::create(pub.get());
  auto reader = dds::Reader<Plain>::create(sub.get());
  if (!writer || !reader) {
    ADD_FAILURE() << "create: " << (!writer ? writer.error().describe() : reader.error().describe());
    return std::nullopt;
  }
  Status matched = writer->waitForReaders(1, 10.0);
  EXPECT_TRUE(matched.ok()) << (matched.ok() ? "" : matched.error().describe());
  Status written = writer->write(message);
  EXPECT_TRUE(written.ok()) << (written.ok() ? "" : written.error().describe());

  auto loop = dds::WaitLoop::create(sub.get());
  if (!loop) {
    ADD_FAILURE() << loop.error().describe();
    return std::nullopt;
  }
  std::optional<Plain> received;
  Status added = loop->add<Plain>(
      *reader,
      [&](Plain&& m) {
        received = std::move(m);
        loop->stop();
      },
      [](const Error& e) { ADD_FAILURE() << "conversion failed: " << e.describe(); });
  EXPECT_TRUE(added.ok());
  auto outcome = loop->run(10.0);
  EXPECT_TRUE(outcome.ok());
  EXPECT_TRUE(received.has_value()) << "nothing received on " << dds::TopicTraits<Plain>::kName;
  return received;
}

void expectSamePoint(const MissionPointData& a, const MissionPointData& b) {
  EXPECT_EQ(a.frame, b.frame);
  if (a.frame == MissionPointData::Frame::kWgs84) {
    EXPECT_EQ(a.geo.lat_deg, b.geo.lat_deg);
    EXPECT_EQ(a.geo.lon_deg, b.geo.lon_deg);
    EXPECT_EQ(a.geo.alt_amsl_m, b.geo.alt_amsl_m);
  } else {
    EXPECT_EQ(a.enu_m, b.enu_m);
  }
}

void expectSameLimits(const VehicleLimitsData& a, const VehicleLimitsData& b) {
  EXPECT_EQ(a.v_ref_mps, b.v_ref_mps);
  EXPECT_EQ(a.max_speed_mps, b.max_speed_mps);
  EXPECT_EQ(a.max_accel_mps2, b.max_accel_mps2);
  EXPECT_EQ(a.max_climb_rate_mps, b.max_climb_rate_mps);
  EXPECT_EQ(a.max_descent_rate_mps, b.max_descent_rate_mps);
  EXPECT_EQ(a.min_turn_radius_m, b.min_turn_radius_m);
  EXPECT_EQ(a.min_clearance_agl_m, b.min_clearance_agl_m);
  EXPECT_EQ(a.ceiling_amsl_m, b.ceiling_amsl_m);
}

MissionRequestData sampleMission() {
  MissionRequestData m;
  m.request_id = "req-42";
  m.vehicle_id = "uav-7";
  m.begin = MissionPointData::wgs84(44.27, -71.30, 1200.5);
  m.points = {MissionPointData::wgs84(44.28, -71.31, 1300.0), MissionPointData::enu({120.5, -300.25, 950.0}),
              MissionPointData::wgs84(44.29, -71.29, 1250.0)};
  m.end = MissionPointData::enu({-5.0, 7.5, 1100.0});
  m.limits = VehicleLimitsData{18.0, 25.0, 3.5, 4.0, 3.0, 60.0, 40.0, 2500.0};
  m.planner = "rrtstar_lospo";
  m.fixed_order = true;
  return m;
}

TrajectoryData sampleTrajectory(const std::string& vehicle, std::uint32_t revision, std::size_t n_samples) {
  TrajectoryData t = testing::namedTrajectory(vehicle, revision);
  t.created_utc_ns = 1'790'000'000'123'456'789LL;
  t.visiting_order = {0, 2, 1, 3};
  t.legs = {{0, 2, 0.0, 10.5}, {2, 1, 10.5, 20.0}, {1, 3, 20.0, 31.25}};
  for (std::size_t i = 0; i < n_samples; ++i) {
    const double t_s = 0.1 * static_cast<double>(i);
    TrajectorySampleData s;
    s.t_rel_s = t_s;
    s.utc_ns = t.created_utc_ns + static_cast<std::int64_t>(i) * 100'000'000LL;
    s.position_enu_m = {10.0 * t_s, std::sin(t_s) * 50.0, 900.0 + t_s};
    s.velocity_enu_mps = {10.0, std::cos(t_s) * 50.0, 1.0};
    s.acceleration_enu_mps2 = {0.0, -std::sin(t_s) * 50.0, 0.0};
    s.heading_deg = std::fmod(90.0 + 3.0 * t_s, 360.0);
    s.geo = GeoPoint{44.27 + 1e-5 * t_s, -71.30 - 1e-5 * t_s, 900.0 + t_s};
    t.samples.push_back(s);
  }
  return t;
}

TEST(DdsRoundTrip, MissionRequest) {
  const MissionRequestData sent = sampleMission();
  auto got = roundTrip(110, sent);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->request_id, sent.request_id);
  EXPECT_EQ(got->vehicle_id, sent.vehicle_id);
  expectSamePoint(got->begin, sent.begin);
  ASSERT_EQ(got->points.size(), sent.points.size());
  for (std::size_t i = 0; i < sent.points.size(); ++i) expectSamePoint(got->points[i], sent.points[i]);
  expectSamePoint(got->end, sent.end);
  expectSameLimits(got->limits, sent.limits);
  EXPECT_EQ(got->planner, sent.planner);
  EXPECT_EQ(got->fixed_order, sent.fixed_order);
}

TEST(DdsRoundTrip, TrajectoryWithManySamples) {
  const TrajectoryData sent = sampleTrajectory("uav-1", 3, 2500);
  auto got = roundTrip(111, sent);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->vehicle_id, sent.vehicle_id);
  EXPECT_EQ(got->plan_id, sent.plan_id);
  EXPECT_EQ(got->revision, sent.revision);
  EXPECT_EQ(got->request_id, sent.request_id);
  EXPECT_EQ(got->created_utc_ns, sent.created_utc_ns);
  EXPECT_EQ(got->visiting_order, sent.visiting_order);
  ASSERT_EQ(got->legs.size(), sent.legs.size());
  for (std::size_t i = 0; i < sent.legs.size(); ++i) {
    EXPECT_EQ(got->legs[i].from_point, sent.legs[i].from_point);
    EXPECT_EQ(got->legs[i].to_point, sent.legs[i].to_point);
    EXPECT_EQ(got->legs[i].start_s, sent.legs[i].start_s);
    EXPECT_EQ(got->legs[i].end_s, sent.legs[i].end_s);
  }
  ASSERT_EQ(got->samples.size(), sent.samples.size());
  for (std::size_t i = 0; i < sent.samples.size(); ++i) {
    const auto& a = got->samples[i];
    const auto& b = sent.samples[i];
    ASSERT_EQ(a.t_rel_s, b.t_rel_s) << i;
    ASSERT_EQ(a.utc_ns, b.utc_ns) << i;
    ASSERT_EQ(a.position_enu_m, b.position_enu_m) << i;
    ASSERT_EQ(a.velocity_enu_mps, b.velocity_enu_mps) << i;
    ASSERT_EQ(a.acceleration_enu_mps2, b.acceleration_enu_mps2) << i;
    ASSERT_EQ(a.heading_deg, b.heading_deg) << i;
    ASSERT_EQ(a.geo.lat_deg, b.geo.lat_deg) << i;
    ASSERT_EQ(a.geo.lon_deg, b.geo.lon_deg) << i;
    ASSERT_EQ(a.geo.alt_amsl_m, b.geo.alt_amsl_m) << i;
  }
}

TEST(DdsRoundTrip, PlanStatus) {
  PlanStatusData sent;
  sent.request_id = "req-9";
  sent.vehicle_id = "uav-3";
  sent.state = PlanState::kFailed;
  sent.error_code = PlanErrorCode::kUnderGround;
  sent.field = "points[1].alt_amsl_m";
  sent.message = "points[1].alt_amsl_m is 12 m below the ground";
  sent.planning_time_s = 0.0375;
  auto got = roundTrip(112, sent);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->request_id, sent.request_id);
  EXPECT_EQ(got->vehicle_id, sent.vehicle_id);
  EXPECT_EQ(got->state, sent.state);
  EXPECT_EQ(got->error_code, sent.error_code);
  EXPECT_EQ(got->field, sent.field);
  EXPECT_EQ(got->message, sent.message);
  EXPECT_EQ(got->planning_time_s, sent.planning_time_s);
}

TEST(DdsRoundTrip, ObstacleUpdatesOfEveryMotion) {
  ObstacleUpdateData bounce;  // obstacle A of seed 003's Table 1
  bounce.obstacle.id = 1;
  bounce.obstacle.shape = ObstacleShape::kEllipsoid;
  bounce.obstacle.size_m = {600.0, 600.0, 300.0};
  bounce.obstacle.center_m = {4900.0, 5400.0, 400.0};
  bounce.obstacle.motion = BackAndForth{{4900.0, 5400.0, 400.0}, {10400.0, 5400.0, 400.0}, 60.0, 1'790'000'000.5};
  bounce.valid_from_utc_ns = 1'790'000'000'500'000'000LL;
  bounce.valid_until_utc_ns = 1'790'000'600'000'000'000LL;
  auto got = roundTrip(113, bounce);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->obstacle.id, 1u);
  EXPECT_EQ(got->obstacle.shape, ObstacleShape::kEllipsoid);
  EXPECT_EQ(got->obstacle.size_m, bounce.obstacle.size_m);
  EXPECT_EQ(got->obstacle.center_m, bounce.obstacle.center_m);
  ASSERT_TRUE(got->obstacle.motion.has_value());
  EXPECT_EQ(got->obstacle.motion->from_m, bounce.obstacle.motion->from_m);
  EXPECT_EQ(got->obstacle.motion->to_m, bounce.obstacle.motion->to_m);
  EXPECT_EQ(got->obstacle.motion->speed_mps, 60.0);
  // The motion's world clock is UTC seconds at valid_from.
  EXPECT_DOUBLE_EQ(got->obstacle.motion->start_time_s, 1'790'000'000.5);
  EXPECT_FALSE(got->constant_velocity_enu_mps.has_value());
  EXPECT_EQ(got->valid_from_utc_ns, bounce.valid_from_utc_ns);
  EXPECT_EQ(got->valid_until_utc_ns, bounce.valid_until_utc_ns);
  EXPECT_FALSE(got->remove);

  ObstacleUpdateData drifting;
  drifting.obstacle.id = 77;
  drifting.obstacle.shape = ObstacleShape::kCylinder;
  drifting.obstacle.size_m = {50.0, 0.0, 200.0};
  drifting.obstacle.center_m = {100.0, 200.0, 300.0};
  drifting.constant_velocity_enu_mps = Eigen::Vector3d(3.0, -4.0, 0.5);
  drifting.valid_from_utc_ns = 1'790'000'000'000'000'000LL;
  auto got2 = roundTrip(114, drifting);
  ASSERT_TRUE(got2.has_value());
  EXPECT_EQ(got2->obstacle.shape, ObstacleShape::kCylinder);
  EXPECT_EQ(got2->motionKind(), ObstacleMotionKind::kConstantVelocity);
  ASSERT_TRUE(got2->constant_velocity_enu_mps.has_value());
  EXPECT_EQ(*got2->constant_velocity_enu_mps, *drifting.constant_velocity_enu_mps);

  ObstacleUpdateData removal;
  removal.obstacle.id = 77;
  removal.remove = true;
  removal.valid_from_utc_ns = 1'790'000'001'000'000'000LL;
  auto got3 = roundTrip(115, removal);
  ASSERT_TRUE(got3.has_value());
  EXPECT_TRUE(got3->remove);
  EXPECT_EQ(got3->obstacle.id, 77u);
}

TEST(DdsRoundTrip, CancelHeartbeatAndFleet) {
  auto cancel = roundTrip(116, CancelRequestData{"req-5", "uav-2"});
  ASSERT_TRUE(cancel.has_value());
  EXPECT_EQ(cancel->request_id, "req-5");
  EXPECT_EQ(cancel->vehicle_id, "uav-2");

  ServiceStatusData heartbeat{"skyrouted-1", 1'790'000'000'000'000'001LL, true, "N44W072", 20, 31, 4, "0.1.0", "1"};
  heartbeat.life_started_utc_ns = 1'789'999'999'000'000'007LL;
  // Best effort on loopback: a lost sample would show as nothing received.
  auto hb = roundTrip(117, heartbeat);
  ASSERT_TRUE(hb.has_value());
  EXPECT_EQ(hb->service_id, heartbeat.service_id);
  EXPECT_EQ(hb->stamp_utc_ns, heartbeat.stamp_utc_ns);
  EXPECT_TRUE(hb->terrain_loaded);
  EXPECT_EQ(hb->terrain_name, "N44W072");
  EXPECT_EQ(hb->vehicles, 20u);
  EXPECT_EQ(hb->replans, 31u);
  EXPECT_EQ(hb->queue_length, 4u);
  EXPECT_EQ(hb->service_version, "0.1.0");
  EXPECT_EQ(hb->idl_version, "1");
  EXPECT_EQ(hb->life_started_utc_ns, heartbeat.life_started_utc_ns);

  FleetRequestData fleet;
  fleet.request_id = "fleet-1";
  fleet.vehicle_ids = {"a", "b"};
  fleet.begins = {MissionPointData::enu({0, 0, 900}), MissionPointData::enu({10, 0, 900})};
  fleet.tasks = {MissionPointData::wgs84(44.1, -71.2, 1000), MissionPointData::wgs84(44.2, -71.1, 1100),
                 MissionPointData::enu({500, 500, 950})};
  fleet.ends = {MissionPointData::enu({0, 5, 900}), MissionPointData::enu({10, 5, 900})};
  fleet.limits.v_ref_mps = 12.0;
  fleet.planner = "rrtstar_lospo";
  auto f = roundTrip(118, fleet);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->request_id, "fleet-1");
  EXPECT_EQ(f->vehicle_ids, fleet.vehicle_ids);
  ASSERT_EQ(f->tasks.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) expectSamePoint(f->tasks[i], fleet.tasks[i]);
  ASSERT_EQ(f->begins.size(), 2u);
  expectSamePoint(f->begins[1], fleet.begins[1]);
  expectSamePoint(f->ends[0], fleet.ends[0]);
  expectSameLimits(f->limits, fleet.limits);
  EXPECT_EQ(f->planner, fleet.planner);
}

// The writer publishes three vehicles (one of them twice) before any reader exists; a reader
// that joins afterwards receives exactly the last trajectory of each vehicle.
TEST(DdsLateJoiner, ReceivesCurrentTrajectoryOfEveryVehicle) {
  const dds_domainid_t domain = 119;
  Entity pub = participantOn(domain);
  auto writer = dds::Writer<TrajectoryData>::create(pub.get());
  ASSERT_TRUE(writer.ok()) << writer.error().describe();
  ASSERT_TRUE(writer->write(sampleTrajectory("uav-a", 1, 50)).ok());
  ASSERT_TRUE(writer->write(sampleTrajectory("uav-b", 1, 60)).ok());
  ASSERT_TRUE(writer->write(sampleTrajectory("uav-a", 2, 70)).ok());
  ASSERT_TRUE(writer->write(sampleTrajectory("uav-c", 5, 80)).ok());

  Entity sub = participantOn(domain);
  auto reader = dds::Reader<TrajectoryData>::create(sub.get());
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  auto loop = dds::WaitLoop::create(sub.get());
  ASSERT_TRUE(loop.ok());
  std::multimap<std::string, TrajectoryData> received;
  ASSERT_TRUE(loop->add<TrajectoryData>(
                      *reader,
                      [&](TrajectoryData&& t) {
                        const std::string id = t.vehicle_id;
                        received.emplace(id, std::move(t));
                      },
                      [](const Error& e) { ADD_FAILURE() << e.describe(); })
                  .ok());
  // Collect for a while after the three arrive, so a stale revision would be seen too.
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(10)) {
    ASSERT_TRUE(loop->runOnce(0.2).ok());
    if (received.size() >= 3) {
      ASSERT_TRUE(loop->runOnce(0.5).ok());
      break;
    }
  }
  ASSERT_EQ(received.size(), 3u);
  ASSERT_EQ(received.count("uav-a"), 1u);
  EXPECT_EQ(received.find("uav-a")->second.revision, 2u);
  EXPECT_EQ(received.find("uav-a")->second.samples.size(), 70u);
  ASSERT_EQ(received.count("uav-b"), 1u);
  EXPECT_EQ(received.find("uav-b")->second.samples.size(), 60u);
  ASSERT_EQ(received.count("uav-c"), 1u);
  EXPECT_EQ(received.find("uav-c")->second.revision, 5u);
}

}  // namespace
}  // namespace skyroute
