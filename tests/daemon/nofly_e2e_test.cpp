// No-fly zones over DDS with a real skyrouted: a daemon that starts after a zone was published
// still learns it (transient-local) and refuses a mission point inside it naming the zone; a zone
// published under a flying vehicle's trajectory makes the daemon replan round it; a bad zone file
// in the configuration stops the daemon naming the file and the feature; a zone of 150,000
// vertices is refused at once and the daemon goes on answering (and stops at SIGTERM); zones off
// the DEM, with latitude and longitude swapped, or of zero area are refused naming the ring;
// `skyroute nofly` and `skyroute nofly --lift` exit by themselves once the daemon has the zone.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "service/dds/typed_io.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute::testing {
namespace {

// This file's DDS domains.
constexpr int kLateDomain = 166;
constexpr int kReplanDomain = 167;
constexpr int kHugeDomain = 40;
constexpr int kDeliveryDomain = 41;
constexpr int kPlacementDomain = 42;

// A rectangle in the terrain's ENU frame, as a published zone (WGS84 ring, heights AMSL).
struct Rect {
  double west_m, south_m, east_m, north_m;
  bool containsWithin(const Eigen::Vector3d& p, double margin_m) const {
    const double dx = std::max({west_m - p.x(), 0.0, p.x() - east_m});
    const double dy = std::max({south_m - p.y(), 0.0, p.y() - north_m});
    return std::hypot(dx, dy) <= margin_m;
  }
};

class NoFlyE2e : public DaemonFixture {
 protected:
  NoFlyZoneData zoneData(const std::string& id, const Rect& r) const {
    NoFlyZoneData z;
    z.zone_id = id;
    for (const auto& [e, n] : {std::pair{r.west_m, r.south_m}, {r.east_m, r.south_m}, {r.east_m, r.north_m},
                               std::pair{r.west_m, r.north_m}}) {
      z.ring.push_back(terrain_->frame().toGeo(Eigen::Vector3d(e, n, 0.0)));
    }
    z.floor_amsl_m = -1000.0;
    z.ceiling_amsl_m = 4900.0;  // under the vehicles' 5000 m ceiling only: the way is round
    return z;
  }
  // A circle of `vertices` vertices in the terrain's ENU frame, as a published zone.
  NoFlyZoneData circleData(const std::string& id, const Eigen::Vector2d& centre_m, double radius_m,
                           std::size_t vertices) const {
    NoFlyZoneData z;
    z.zone_id = id;
    for (std::size_t i = 0; i < vertices; ++i) {
      const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(vertices);
      z.ring.push_back(terrain_->frame().toGeo(
          Eigen::Vector3d(centre_m.x() + radius_m * std::cos(a), centre_m.y() + radius_m * std::sin(a), 0.0)));
    }
    z.floor_amsl_m = -1000.0;
    z.ceiling_amsl_m = 4900.0;
    return z;
  }
  // The zone as a GeoJSON file of one feature named `id`; returns its path.
  std::string geoJsonFile(const NoFlyZoneData& zone, const std::string& name) const {
    nlohmann::json ring = nlohmann::json::array();
    for (const GeoPoint& p : zone.ring) ring.push_back({p.lon_deg, p.lat_deg});
    ring.push_back(ring.front());
    const nlohmann::json doc = {
        {"type", "FeatureCollection"},
        {"features", {{{"type", "Feature"}, {"id", zone.zone_id},
                       {"properties", {{"floor_m", zone.floor_amsl_m}, {"ceiling_m", zone.ceiling_amsl_m}}},
                       {"geometry", {{"type", "Polygon"}, {"coordinates", {ring}}}}}}}};
    const std::string path = e2eTempPath(name);
    std::ofstream(path) << doc.dump();
    return path;
  }
  // The last lines of the daemon's log, for a failure message.
  std::string logTail() const {
    const std::string log = daemon_.err();
    return log.size() > 4000 ? log.substr(log.size() - 4000) : log;
  }
};

TEST_F(NoFlyE2e, LateDaemonGetsZonesPublishedBeforeItStarted) {
  // `skyroute nofly` publishes a GeoJSON zone round the mission's middle point (0, 200) and stays up
  // (--hold inf: until a signal; no daemon yet is no failure while it holds).
  const NoFlyZoneData stadium = zoneData("stadium", Rect{-400, -200, 400, 600});
  nlohmann::json ring = nlohmann::json::array();
  for (const GeoPoint& p : stadium.ring) ring.push_back({p.lon_deg, p.lat_deg});
  ring.push_back(ring.front());
  const nlohmann::json doc = {
      {"type", "FeatureCollection"},
      {"features", {{{"type", "Feature"}, {"id", "stadium"},
                     {"properties", {{"floor_m", stadium.floor_amsl_m}, {"ceiling_m", stadium.ceiling_amsl_m}}},
                     {"geometry", {{"type", "Polygon"}, {"coordinates", {ring}}}}}}}};
  const std::string zones_path = e2eTempPath("zones_" + std::to_string(kLateDomain) + ".geojson");
  std::ofstream(zones_path) << doc.dump();
  ChildProcess publisher = ChildProcess::spawn(
      {SKYROUTE_CLI, "nofly", zones_path, "--domain", std::to_string(kLateDomain), "--hold", "inf", "--wait", "0"},
      "nofly_" + std::to_string(kLateDomain));
  ASSERT_TRUE(publisher.started());
  // A zone with bad geometry straight from a writer of the test's own (the CLI would refuse it).
  auto participant = dds::createParticipant(kLateDomain);
  ASSERT_TRUE(participant.ok()) << participant.error().describe();
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok()) << writer.error().describe();
  NoFlyZoneData bad = zoneData("bow", Rect{-400, -200, 400, 600});
  std::swap(bad.ring[1], bad.ring[2]);  // a bow tie
  ASSERT_TRUE(writer->write(bad).ok());
  const auto published = [&] { return publisher.out().find("published zone stadium") != std::string::npos; };
  for (int i = 0; i < 200 && !published(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(published()) << publisher.out() << publisher.err();

  startDaemon(kLateDomain);
  ASSERT_TRUE(waitForLog("event=nofly_zone zone=stadium", 20.0)) << daemon_.err();
  ASSERT_TRUE(waitForLog("event=nofly_rejected zone=bow", 20.0)) << daemon_.err();
  EXPECT_NE(daemon_.err().find("self-intersection"), std::string::npos) << daemon_.err();

  const MissionRequestData m = simpleMission("inside", "uav-1", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitTerminal({"inside"}, 60.0));
  const auto status = station_->terminal("inside");
  ASSERT_TRUE(status);
  EXPECT_EQ(status->state, PlanState::kFailed);
  EXPECT_EQ(status->field, "points[0]");
  EXPECT_NE(status->message.find("is inside no-fly zone 'stadium'"), std::string::npos) << status->message;

  // Lifted: the same mission plans.
  NoFlyZoneData lift;
  lift.zone_id = "stadium";
  lift.remove = true;
  ASSERT_TRUE(writer->write(lift).ok());
  ASSERT_TRUE(waitForLog("event=nofly_zone zone=stadium remove=true", 20.0)) << daemon_.err();
  publisher.signal(SIGTERM);
  EXPECT_EQ(publisher.wait(10.0), 0) << publisher.err();
  std::filesystem::remove(zones_path);
  MissionRequestData again = m;
  again.request_id = "lifted";
  ASSERT_TRUE(station_->requests->write(again).ok());
  ASSERT_TRUE(station_->waitState("lifted", PlanState::kSucceeded, 120.0)) << daemon_.err();
}

TEST_F(NoFlyE2e, ZoneUnderAFlyingVehicleTriggersAReplanRoundIt) {
  startDaemon(kReplanDomain);
  const MissionRequestData m = simpleMission("flying", "uav-2", 2000.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitState("flying", PlanState::kSucceeded, 120.0)) << daemon_.err();
  ASSERT_TRUE(station_->pumpUntil([&] { return station_->latest("uav-2") != nullptr; }, 20.0));
  const std::uint32_t first_revision = station_->latest("uav-2")->revision;

  // Across the first leg (from (-5000, 2000) to (0, 2200)) 500 to 1000 m from its start: inside
  // the replanner's 45 s look-ahead, far enough ahead to go round.
  const Rect zone{-4500, 1500, -4000, 2600};
  auto participant = dds::createParticipant(kReplanDomain);
  ASSERT_TRUE(participant.ok());
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(writer->write(zoneData("closed", zone)).ok());
  // A replan that misses its cycle's budget (a loaded machine) answers with a hold first; the
  // route round the zone to the end follows at a later cycle. Every revision keeps out of it.
  auto reachesTheEnd = [&](const TrajectoryData& t) {
    return !t.samples.empty() && (t.samples.back().position_enu_m - enuOf(m.end)).norm() < 1.0;
  };
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        const TrajectoryData& t = *station_->latest("uav-2");
        return (t.revision > first_revision && reachesTheEnd(t)) || !daemon_.running();
      },
      60.0))
      << daemon_.err();
  std::size_t revisions = 0;
  for (const TrajectoryData& t : station_->trajectory_log) {
    if (t.vehicle_id != "uav-2" || t.revision <= first_revision) continue;
    ++revisions;
    ASSERT_FALSE(t.samples.empty());
    for (const TrajectorySampleData& s : t.samples) {
      ASSERT_FALSE(zone.containsWithin(s.position_enu_m, 5.0))
          << "revision " << t.revision << " enters the zone at t = " << s.t_rel_s << " s";
    }
  }
  EXPECT_GE(revisions, 1u);
  EXPECT_TRUE(reachesTheEnd(*station_->latest("uav-2")));
}

TEST_F(NoFlyE2e, BadZoneFileInTheConfigurationStopsTheDaemonNamingIt) {
  // The zones load with the terrain, before any DDS entity exists: no domain is touched.
  const std::string zones_path = e2eTempPath("bad_zones.geojson");
  std::ofstream(zones_path) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": "thin",
      "properties": {"ceiling_m": 900}, "geometry": {"type": "Polygon",
      "coordinates": [[[15.07, 46.93], [15.08, 46.93], [15.07, 46.93]]]}}]})";
  const std::string config_path = e2eTempPath("bad_zones.toml");
  std::ofstream(config_path) << "[terrain]\nnofly = \"" << zones_path << "\"\n";
  ChildProcess daemon = ChildProcess::spawn({SKYROUTED, "--config", config_path}, "skyrouted_bad_zones");
  ASSERT_TRUE(daemon.started());
  EXPECT_EQ(daemon.wait(60.0), 3) << daemon.err();
  EXPECT_NE(daemon.err().find("terrain.nofly"), std::string::npos) << daemon.err();
  EXPECT_NE(daemon.err().find(zones_path + ": features[0] 'thin': has 2 distinct vertices"), std::string::npos)
      << daemon.err();
  std::filesystem::remove(zones_path);
  std::filesystem::remove(config_path);
}

TEST_F(NoFlyE2e, HugeZoneIsRefusedAtOnceAndTheDaemonGoesOnServing) {
  // 150,000 vertices from a writer of the test's own (the CLI refuses such a file): the daemon
  // counts them before anything else and refuses the sample, instead of checking the ring on its
  // DDS thread for minutes (it did: 140 s, and SIGTERM then waited for it).
  startDaemon(kHugeDomain);
  auto participant = dds::createParticipant(kHugeDomain);
  ASSERT_TRUE(participant.ok()) << participant.error().describe();
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok()) << writer.error().describe();
  ASSERT_TRUE(writer->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(writer->write(circleData("huge", Eigen::Vector2d(2000, -3000), 1500.0, 150000)).ok());
  ASSERT_TRUE(waitForLog("event=bad_nofly_zone field=ring", 60.0)) << logTail();
  EXPECT_NE(daemon_.err().find("ring has 150000 vertices, more than the 10000 a zone may have (zone 'huge')"),
            std::string::npos)
      << logTail();
  EXPECT_EQ(daemon_.err().find("event=nofly_zone zone=huge"), std::string::npos) << logTail();

  // It goes on serving: a mission plans, and SIGTERM stops it within the fixture's wait.
  const MissionRequestData m = simpleMission("after-huge", "uav-h", 0.0);
  ASSERT_TRUE(station_->requests->write(m).ok());
  ASSERT_TRUE(station_->waitState("after-huge", PlanState::kSucceeded, 120.0)) << logTail();
  const auto asked = std::chrono::steady_clock::now();
  daemon_.signal(SIGTERM);
  EXPECT_EQ(daemon_.wait(10.0), 0) << logTail();
  std::printf("SIGTERM to exit: %.2f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count());
}

TEST_F(NoFlyE2e, NoflyAndItsLiftExitOnceTheDaemonHasThem) {
  // A zone at the vertex bound, through the CLI as a user runs it (no --hold): it publishes, waits
  // until the daemon on the domain acknowledged the zone, and exits; so does the lift.
  startDaemon(kDeliveryDomain);
  const std::string path = geoJsonFile(circleData("round", Eigen::Vector2d(2000, -3000), 1500.0, 10000),
                                       "round_" + std::to_string(kDeliveryDomain) + ".geojson");
  const Ran published =
      runToEnd({SKYROUTE_CLI, "nofly", path, "--domain", std::to_string(kDeliveryDomain)}, "nofly_round", 120.0);
  std::filesystem::remove(path);
  EXPECT_EQ(published.code, 0) << published.out << published.err;
  EXPECT_NE(published.out.find("published zone round"), std::string::npos) << published.out;
  EXPECT_NE(published.out.find("acknowledged by 1 daemon on domain " + std::to_string(kDeliveryDomain)),
            std::string::npos)
      << published.out << published.err;
  ASSERT_TRUE(waitForLog("event=nofly_zone zone=round remove=false vertices=10000", 20.0)) << logTail();

  const Ran lifted = runToEnd({SKYROUTE_CLI, "nofly", "--lift", "round", "--domain", std::to_string(kDeliveryDomain)},
                              "nofly_lift_round", 120.0);
  EXPECT_EQ(lifted.code, 0) << lifted.out << lifted.err;
  EXPECT_NE(lifted.out.find("acknowledged by 1 daemon"), std::string::npos) << lifted.out << lifted.err;
  ASSERT_TRUE(waitForLog("event=nofly_zone zone=round remove=true", 20.0)) << logTail();
}

TEST_F(NoFlyE2e, ZonesOffTheDemSwappedOrFlatAreRefusedNamingTheRing) {
  startDaemon(kPlacementDomain);
  auto participant = dds::createParticipant(kPlacementDomain);
  ASSERT_TRUE(participant.ok()) << participant.error().describe();
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok()) << writer.error().describe();
  ASSERT_TRUE(writer->waitForReaders(1, 20.0).ok());
  // Written [lat, lon] where [lon, lat] was meant: on the DEM only with the two exchanged.
  NoFlyZoneData swapped = zoneData("swapped", Rect{-400, -200, 400, 600});
  for (GeoPoint& p : swapped.ring) std::swap(p.lat_deg, p.lon_deg);
  // 200 km east of the DEM's centre: nothing of it over the terrain.
  const NoFlyZoneData off = zoneData("off", Rect{200000, 0, 201000, 1000});
  // Three vertices on one parallel (collinear in latitude and longitude).
  NoFlyZoneData flat = zoneData("flat", Rect{-400, -200, 400, 600});
  const double lat = flat.ring[0].lat_deg, lon = flat.ring[0].lon_deg;
  flat.ring = {GeoPoint{lat, lon, 0.0}, GeoPoint{lat, lon + 0.01, 0.0}, GeoPoint{lat, lon + 0.02, 0.0}};
  for (const NoFlyZoneData& z : {swapped, off, flat}) ASSERT_TRUE(writer->write(z).ok());
  ASSERT_TRUE(waitForLog("event=nofly_rejected zone=swapped field=ring", 20.0)) << logTail();
  ASSERT_TRUE(waitForLog("event=nofly_rejected zone=off field=ring", 20.0)) << logTail();
  ASSERT_TRUE(waitForLog("event=nofly_rejected zone=flat field=ring", 20.0)) << logTail();
  const std::string log = daemon_.err();
  EXPECT_NE(log.find("zone 'swapped': lies outside the DEM, but on it with latitude and longitude exchanged"),
            std::string::npos)
      << logTail();
  EXPECT_NE(log.find("zone 'off': lies entirely outside the DEM (lat "), std::string::npos) << logTail();
  EXPECT_NE(log.find("zone 'flat': has (nearly) zero area"), std::string::npos) << logTail();
  EXPECT_EQ(log.find("event=nofly_zone zone="), std::string::npos) << logTail();  // none was taken
}

}  // namespace
}  // namespace skyroute::testing
