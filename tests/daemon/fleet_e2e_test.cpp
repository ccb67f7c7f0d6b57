// A fleet over DDS, end to end: skyrouted as a separate process; the test is the
// ground station, with a FleetRequest writer and a FleetStatus reader of its own next to the
// common station's topics.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "service/dds/loopback.hpp"
#include "service/dds/wait_loop.hpp"
#include "terrain/terrain_world.hpp"
#include "tests/daemon/fleet_daemon_fixture.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::Station;

constexpr int kDomain = 160;

// Vehicle position at utc_ns from its published samples (linear between samples, held outside).
Eigen::Vector3d positionAt(const TrajectoryData& t, std::int64_t utc_ns) {
  const auto& s = t.samples;
  if (utc_ns <= s.front().utc_ns) return s.front().position_enu_m;
  if (utc_ns >= s.back().utc_ns) return s.back().position_enu_m;
  const auto after = std::lower_bound(s.begin(), s.end(), utc_ns,
                                      [](const TrajectorySampleData& x, std::int64_t u) { return x.utc_ns < u; });
  const auto before = after - 1;
  const double w = static_cast<double>(utc_ns - before->utc_ns) / static_cast<double>(after->utc_ns - before->utc_ns);
  return (1.0 - w) * before->position_enu_m + w * after->position_enu_m;
}

class FleetE2E : public testing::FleetDaemonTest {
 protected:
  void SetUp() override { startDaemon(kDomain, {}, "skyrouted_fleet", 60.0); }

  std::optional<FleetStatusData> terminal(const std::string& id) const {
    for (const auto& s : fleet_log_)
      if (s.request_id == id && isTerminal(s.state)) return s;
    return std::nullopt;
  }
};

TEST_F(FleetE2E, FleetRequestGetsOneSeparatedTrajectoryPerVehicleAndAStatusWithTheAllocation) {
  FleetRequestData r;
  r.request_id = "fleet-e2e";
  r.vehicle_ids = {"f-1", "f-2", "f-3"};
  r.begins = {above(-4000, -4000, 100), above(4000, -4000, 100), above(-4000, 4000, 100)};
  r.ends = r.begins;
  r.tasks = {above(-2500, -1500, 150), above(-1000, -3000, 150), above(1500, -2500, 150),
             above(3000, -1000, 150),  above(2500, 1500, 150),   above(-3000, 1000, 150),
             above(-1500, 3000, 150),  above(0, 0, 150),         above(1500, 3500, 150)};
  ASSERT_TRUE(fleet_requests_->write(r).ok());

  // A bad one too: its status names the field.
  FleetRequestData bad = r;
  bad.request_id = "fleet-bad";
  bad.vehicle_ids[1] = "f-1";
  ASSERT_TRUE(fleet_requests_->write(bad).ok());

  ASSERT_TRUE(station_->pumpUntil([&] { return terminal("fleet-e2e") && terminal("fleet-bad"); }, 120.0)) << daemon_.err();
  const FleetStatusData failed = *terminal("fleet-bad");
  EXPECT_EQ(failed.state, PlanState::kFailed);
  EXPECT_EQ(failed.error_code, PlanErrorCode::kInvalidArgument);
  EXPECT_EQ(failed.field, "vehicle_ids[1]");

  const FleetStatusData status = *terminal("fleet-e2e");
  ASSERT_EQ(status.state, PlanState::kSucceeded) << status.message;
  EXPECT_GT(status.makespan_steps, 0);
  EXPECT_GT(status.min_separation_m, 0.0);
  EXPECT_GE(status.achieved_separation_m, status.min_separation_m);
  ASSERT_EQ(status.allocation.size(), 3u);
  std::multiset<std::uint32_t> done;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(status.allocation[i].vehicle_id, r.vehicle_ids[i]);
    done.insert(status.allocation[i].tasks.begin(), status.allocation[i].tasks.end());
  }
  EXPECT_EQ(done, (std::multiset<std::uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));

  // One trajectory per vehicle, from this request, visiting its allocated tasks.
  auto fleetTrajectory = [&](const std::string& vehicle) -> const TrajectoryData* {
    const TrajectoryData* t = station_->latest(vehicle);
    return t && t->request_id == r.request_id ? t : nullptr;
  };
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return fleetTrajectory("f-1") && fleetTrajectory("f-2") && fleetTrajectory("f-3"); }, 10.0));
  std::vector<const TrajectoryData*> flown;
  for (std::size_t i = 0; i < 3; ++i) {
    const TrajectoryData* t = fleetTrajectory(r.vehicle_ids[i]);
    flown.push_back(t);
    ASSERT_GE(t->samples.size(), 2u);
    ASSERT_EQ(t->visiting_order.size(), status.allocation[i].tasks.size() + 2);
    for (std::size_t k = 0; k < status.allocation[i].tasks.size(); ++k) {
      EXPECT_EQ(t->visiting_order[k + 1], status.allocation[i].tasks[k] + 1);
    }
    EXPECT_LT((t->samples.front().position_enu_m - r.begins[i].enu_m).norm(), 0.01);
    EXPECT_LT((t->samples.back().position_enu_m - r.ends[i].enu_m).norm(), 0.01);
    for (const TrajectorySampleData& s : t->samples) {
      EXPECT_GE(s.position_enu_m.z() - terrain_->heightAt(s.position_enu_m.x(), s.position_enu_m.y()),
                r.limits.min_clearance_agl_m - 1.0);
    }
  }
  // Separation on the published samples (interpolated to common instants every 0.1 s); a linear
  // interpolation between 0.2 s samples is within a metre of the curve.
  std::int64_t first = std::numeric_limits<std::int64_t>::max();
  std::int64_t last = 0;
  for (const TrajectoryData* t : flown) {
    first = std::min(first, t->samples.front().utc_ns);
    last = std::max(last, t->samples.back().utc_ns);
  }
  double closest = std::numeric_limits<double>::infinity();
  for (std::int64_t u = first; u <= last; u += 100'000'000) {
    for (std::size_t a = 0; a < 3; ++a) {
      for (std::size_t b = a + 1; b < 3; ++b) {
        closest = std::min(closest, (positionAt(*flown[a], u) - positionAt(*flown[b], u)).norm());
      }
    }
  }
  EXPECT_GE(closest, status.min_separation_m - 1.0);
  // Each vehicle's trajectory passed the audit before the fleet was published (docs/dds.md).
  const auto heartbeat = station_->freshHeartbeat(20.0);
  ASSERT_TRUE(heartbeat);
  EXPECT_GE(heartbeat->audits, 3u);
  EXPECT_EQ(heartbeat->audit_failures, 0u);
  std::printf("fleet over DDS: planning %.3f s, makespan %d steps / %.1f s, separation %.0f m (min %.0f), "
              "repairs %u\n",
              status.planning_time_s, status.makespan_steps, status.makespan_s, closest, status.min_separation_m,
              status.separation_repairs);
}

// The FleetStatus message carries the allocation and timing unchanged; a NaN is refused by name.
TEST(FleetStatusWire, RoundTripsAndRejectsNonFiniteNumbers) {
  FleetStatusData in;
  in.request_id = "fleet-7";
  in.state = PlanState::kSucceeded;
  in.allocation = {{"a", {2, 0, 5}, 0.0}, {"b", {}, 12.5}};
  in.makespan_steps = 42;
  in.makespan_s = 321.5;
  in.min_separation_m = 99.0;
  in.achieved_separation_m = 101.25;
  in.separation_repairs = 1;
  in.planning_time_s = 0.25;
  dds::WireSample<skyroute_msgs_FleetStatus> wire(&skyroute_msgs_FleetStatus_desc);
  dds::toWire(in, wire.msg());
  auto out = dds::fromWire(wire.msg());
  ASSERT_TRUE(out.ok()) << out.error().describe();
  EXPECT_EQ(out->request_id, "fleet-7");
  EXPECT_EQ(out->state, PlanState::kSucceeded);
  ASSERT_EQ(out->allocation.size(), 2u);
  EXPECT_EQ(out->allocation[0].vehicle_id, "a");
  EXPECT_EQ(out->allocation[0].tasks, (std::vector<std::uint32_t>{2, 0, 5}));
  EXPECT_TRUE(out->allocation[1].tasks.empty());
  EXPECT_DOUBLE_EQ(out->allocation[1].delay_s, 12.5);
  EXPECT_EQ(out->makespan_steps, 42);
  EXPECT_DOUBLE_EQ(out->makespan_s, 321.5);
  EXPECT_DOUBLE_EQ(out->achieved_separation_m, 101.25);
  EXPECT_EQ(out->separation_repairs, 1u);
  wire.msg().allocation._buffer[1].delay_s = std::nan("");
  auto rejected = dds::fromWire(wire.msg());
  ASSERT_FALSE(rejected.ok());
  EXPECT_EQ(rejected.error().field, "allocation[1].delay_s");
}

// SIGTERM while a 32-vehicle, 96-task fleet builds its trajectories: the daemon exits 0 within the
// second docs/dds.md promises (the engine's stop and the flush share dds.flush_timeout_s), and
// the fleet is answered.
class FleetStopE2E : public testing::FleetDaemonTest {};

TEST_F(FleetStopE2E, SigtermWhileA32VehicleFleetIsPlannedStopsWithinASecond) {
  constexpr int kStopDomain = 218;
  startDaemon(kStopDomain, {"--log-level", "debug"}, "skyrouted_fleet_stop", 60.0);
  FleetRequestData r;
  r.request_id = "fleet-32";
  for (int i = 0; i < 32; ++i) {
    r.vehicle_ids.push_back("v-" + std::to_string(i));
    r.begins.push_back(above(-4200.0 + 270.0 * (i % 8), -4200.0 + 270.0 * (i / 8), 100));
  }
  r.ends = r.begins;
  for (int k = 0; k < 96; ++k) r.tasks.push_back(above(-3000.0 + 560.0 * (k % 12), -1500.0 + 700.0 * (k / 12), 150));
  ASSERT_TRUE(fleet_requests_->write(r).ok());
  // The trajectories stage has begun (its first vehicle is built).
  ASSERT_TRUE(station_->pumpUntil(
      [&] { return daemon_.err().find("event=fleet_trajectory") != std::string::npos || !daemon_.running(); }, 60.0))
      << daemon_.err();
  ASSERT_TRUE(daemon_.running()) << daemon_.err();
  const bool finished_before = daemon_.err().find("event=fleet_succeeded") != std::string::npos;
  const auto sent = std::chrono::steady_clock::now();
  daemon_.signal(SIGTERM);
  const int code = daemon_.wait(5.0);
  const double stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  std::printf("SIGTERM during a 32-vehicle fleet plan: stopped in %.3f s (plan finished before: %d)\n", stop_s,
              finished_before);
  EXPECT_EQ(code, 0) << daemon_.err();
  EXPECT_LT(stop_s, 1.0) << daemon_.err();
  ASSERT_TRUE(station_->pumpUntil(
      [&] {
        return std::any_of(fleet_log_.begin(), fleet_log_.end(),
                           [&](const FleetStatusData& s) { return s.request_id == r.request_id && isTerminal(s.state); });
      },
      5.0));
  // Cancelled, unless its plan was decided before the engine's stop took effect (published
  // before the stop's answer: both are answered, never failed).
  for (const FleetStatusData& s : fleet_log_) {
    if (s.request_id != r.request_id || !isTerminal(s.state)) continue;
    EXPECT_TRUE(s.state == PlanState::kCancelled || s.state == PlanState::kSucceeded) << s.message;
  }
}

}  // namespace
}  // namespace skyroute
