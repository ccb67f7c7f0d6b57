// A no-fly zone published far ahead of a flying vehicle, over DDS with a real skyrouted flying
// the demo mission (data/missions/demo_mission.json on the embedded terrain): the zone lies over
// the mission's last leg while the vehicle is on its first, minutes before the vehicle gets there
// and far beyond the replanning horizon (45 s). The daemon re-routes it in the first cycle that
// sees the zone, with a revision that reaches the end and is not a hold, long before the old
// trajectory would have come within the horizon of the zone; no revision published after the zone
// has a sample inside it (the test's own point-in-polygon on the samples' WGS84 positions). The
// heartbeat counts the audits of what was published (docs/dds.md, "Audit before publishing").
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "service/dds/typed_io.hpp"
#include "tests/daemon/daemon_fixture.hpp"

namespace skyroute::testing {
namespace {

// This file's DDS domain.
constexpr int kZoneAheadDomain = 90;
constexpr double kHorizonS = 45.0;  // replanning.horizon_s's default
constexpr double kHalfSideM = 300.0;

// Point in polygon (even-odd crossings) on (longitude, latitude), the ring as published.
bool insideRing(const std::vector<GeoPoint>& ring, const GeoPoint& p) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const GeoPoint& a = ring[i];
    const GeoPoint& b = ring[j];
    if ((a.lat_deg > p.lat_deg) != (b.lat_deg > p.lat_deg)) {
      const double lon = a.lon_deg + (p.lat_deg - a.lat_deg) * (b.lon_deg - a.lon_deg) / (b.lat_deg - a.lat_deg);
      if (p.lon_deg < lon) inside = !inside;
    }
  }
  return inside;
}

class ZoneAheadE2e : public DaemonFixture {
 protected:
  // Flies the demo mission; returns its first trajectory.
  TrajectoryData flyDemo(const std::string& request_id) {
    mission_ = demoMission();
    mission_.request_id = request_id;
    EXPECT_TRUE(station_->requests->write(mission_).ok());
    EXPECT_TRUE(station_->waitState(request_id, PlanState::kSucceeded, 120.0)) << daemon_.err();
    EXPECT_TRUE(station_->pumpUntil([&] { return station_->latest(mission_.vehicle_id) != nullptr; }, 20.0));
    const TrajectoryData* first = station_->latest(mission_.vehicle_id);
    return first ? *first : TrajectoryData{};
  }
  // A 600 m square round the middle of the trajectory's last leg, from the ground to above the
  // vehicle's ceiling (2500 m): the way is round it.
  NoFlyZoneData zoneOverLastLeg(const TrajectoryData& t) const {
    const LegBoundaryData& last = t.legs.back();
    const double middle_s = 0.5 * (last.start_s + last.end_s);
    const auto at = std::min_element(t.samples.begin(), t.samples.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.t_rel_s - middle_s) < std::abs(b.t_rel_s - middle_s);
    });
    const Eigen::Vector3d c = at->position_enu_m;
    NoFlyZoneData z;
    z.zone_id = "ahead";
    for (const auto& [de, dn] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, std::pair{-1.0, 1.0}}) {
      z.ring.push_back(terrain_->frame().toGeo(Eigen::Vector3d(c.x() + de * kHalfSideM, c.y() + dn * kHalfSideM, 0.0)));
    }
    z.floor_amsl_m = -1000.0;
    z.ceiling_amsl_m = 4000.0;
    return z;
  }
  // The first sample of t inside the zone's ring, if any.
  static const TrajectorySampleData* firstInside(const TrajectoryData& t, const NoFlyZoneData& zone) {
    for (const TrajectorySampleData& s : t.samples) {
      if (insideRing(zone.ring, s.geo)) return &s;
    }
    return nullptr;
  }
  std::size_t logCountFor(const std::string& event) const {
    const std::string log = daemon_.err();
    std::size_t n = 0;
    for (std::size_t at = log.find(event); at != std::string::npos; at = log.find(event, at + 1)) {
      const std::size_t end = log.find('\n', at);
      if (log.substr(at, end - at).find("vehicle=" + mission_.vehicle_id + " ") != std::string::npos) ++n;
    }
    return n;
  }

  MissionRequestData mission_;
};

TEST_F(ZoneAheadE2e, ZoneOverTheLastLegIsAvoidedInTheFirstCycleWithoutAHold) {
  startDaemon(kZoneAheadDomain);
  const TrajectoryData first = flyDemo("zone-ahead");
  ASSERT_FALSE(first.samples.empty());
  ASSERT_GE(first.legs.size(), 2u);
  const NoFlyZoneData zone = zoneOverLastLeg(first);
  const TrajectorySampleData* entry = firstInside(first, zone);
  ASSERT_NE(entry, nullptr) << "the zone is not on the first trajectory";
  // The vehicle is on its first leg, and the zone is further ahead than the horizon.
  const std::int64_t published_utc_ns = utcNowNs();
  ASSERT_LT(published_utc_ns, first.samples.front().utc_ns + static_cast<std::int64_t>(first.legs.front().end_s * 1e9));
  ASSERT_GT(static_cast<double>(entry->utc_ns - published_utc_ns) * 1e-9, kHorizonS + 30.0);

  auto participant = dds::createParticipant(kZoneAheadDomain);
  ASSERT_TRUE(participant.ok());
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(writer->write(zone).ok());

  // The revision event: the next trajectory of the vehicle.
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return station_->latest(mission_.vehicle_id)->revision > first.revision || !daemon_.running(); }, 120.0))
      << daemon_.err();
  const TrajectoryData next = *station_->latest(mission_.vehicle_id);
  // Taken over long before the old trajectory came within the horizon of the zone: the daemon
  // saw the zone over the whole remaining trajectory, not 45 s ahead.
  ASSERT_FALSE(next.samples.empty());
  EXPECT_GT(static_cast<double>(entry->utc_ns - next.samples.front().utc_ns) * 1e-9, kHorizonS + 30.0)
      << "revision " << next.revision << " starts " << (entry->utc_ns - next.samples.front().utc_ns) * 1e-9
      << " s before the old trajectory entered the zone";
  // In the first cycle after the zone (the world change it took: one), a route to the end, not a hold.
  EXPECT_LT((next.samples.back().position_enu_m - enuOf(mission_.end)).norm(), 1.0) << "revision " << next.revision
                                                                                     << " does not reach the end";
  ASSERT_TRUE(waitForLog("updates_coalesced=", 20.0));
  const std::string log = daemon_.err();
  const std::size_t zone_at = log.find("event=nofly_zone zone=ahead");
  ASSERT_NE(zone_at, std::string::npos) << log;
  const std::size_t answer_at = log.find("vehicle=" + mission_.vehicle_id + " plan=", zone_at);
  ASSERT_NE(answer_at, std::string::npos) << log;
  const std::size_t line_at = log.rfind('\n', answer_at) + 1;
  const std::string answer = log.substr(line_at, log.find('\n', answer_at) - line_at);
  const bool rerouted =
      answer.find("event=replanned") != std::string::npos || answer.find("event=reordered") != std::string::npos;
  EXPECT_TRUE(rerouted) << answer;
  EXPECT_NE(answer.find("revision=" + std::to_string(next.revision) + " "), std::string::npos) << answer;
  EXPECT_NE(answer.find("updates_coalesced=1"), std::string::npos) << answer;
  EXPECT_EQ(logCountFor("event=replan_hold"), 0u) << log;
  EXPECT_EQ(logCountFor("event=audit_failed"), 0u) << log;
  for (const PlanStatusData& s : station_->status_log) {
    if (s.vehicle_id == mission_.vehicle_id) {
      EXPECT_NE(s.state, PlanState::kHolding) << s.message;
    }
  }

  // Every revision published after the zone, up to a heartbeat later, keeps every sample out of it.
  ASSERT_TRUE(station_->freshHeartbeat(20.0));
  std::size_t revisions = 0;
  for (const TrajectoryData& t : station_->trajectory_log) {
    if (t.vehicle_id != mission_.vehicle_id || t.revision <= first.revision) continue;
    ++revisions;
    const TrajectorySampleData* inside = firstInside(t, zone);
    EXPECT_EQ(inside, nullptr) << "revision " << t.revision << " is inside the zone at t = "
                               << (inside ? inside->t_rel_s : 0.0) << " s";
  }
  EXPECT_GE(revisions, 1u);
}

TEST_F(ZoneAheadE2e, HeartbeatCountsTheAudits) {
  startDaemon(kZoneAheadDomain + 1);
  const auto before = station_->freshHeartbeat(20.0);
  ASSERT_TRUE(before);
  EXPECT_EQ(before->audits, 0u);
  const TrajectoryData first = flyDemo("audited");
  ASSERT_FALSE(first.samples.empty());
  // The first plan was audited before it went out; a zone ahead makes a replan, audited too.
  const auto planned = station_->freshHeartbeat(20.0);
  ASSERT_TRUE(planned);
  EXPECT_GE(planned->audits, 1u);
  EXPECT_EQ(planned->audit_failures, 0u);
  auto participant = dds::createParticipant(kZoneAheadDomain + 1);
  ASSERT_TRUE(participant.ok());
  auto writer = dds::Writer<NoFlyZoneData>::create(participant->get());
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(writer->write(zoneOverLastLeg(first)).ok());
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return station_->latest(mission_.vehicle_id)->revision > first.revision || !daemon_.running(); }, 120.0))
      << daemon_.err();
  const auto replanned = station_->freshHeartbeat(20.0);
  ASSERT_TRUE(replanned);
  EXPECT_GT(replanned->audits, planned->audits);
  EXPECT_EQ(replanned->audit_failures, 0u);
}

}  // namespace
}  // namespace skyroute::testing
