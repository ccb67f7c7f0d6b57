// `skyroute px4` as a separate process between skyroute and a PX4 seen over DDS (PX4 v1.16's
// layouts): setpoints at the rate asked, with increasing timestamps, whose positions map back onto
// the trajectory within 1 cm and whose yaw is the heading; a new revision taken over at its start;
// holds after the end, when the daemon falls silent, and when it retracts the trajectory; the EKF
// origin from PX4's VehicleLocalPosition, and the timeout exit without it; bad options exit 2
// naming the option. Domain ids 200 to 204 belong to this file.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>

#include "service/dds/loopback.hpp"
#include "service/dds/typed_io.hpp"
#include "service/px4_projection.hpp"
#include "terrain/heightfield.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/fake_px4.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/service/synthetic_trajectory.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::FakePx4;
using testing::ReceivedSetpoint;

using Clock = std::chrono::steady_clock;

class LoopbackEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { dds::useLoopbackOnly(); }  // skyrouted and skyroute px4 inherit it
};
const auto* const kLoopback = ::testing::AddGlobalTestEnvironment(new LoopbackEnvironment);

std::string geoArg(const GeoPoint& g) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9f,%.9f,%.3f", g.lat_deg, g.lon_deg, g.alt_amsl_m);
  return buf;
}

// Polls PX4's side every millisecond until done() or the timeout.
bool collectUntil(FakePx4& px4, const std::function<bool()>& done, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    px4.poll();
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  px4.poll();
  return done();
}

bool waitForLine(ChildProcess& p, const std::string& text, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    if (p.out().find(text) != std::string::npos) return true;
    if (!p.running()) return p.out().find(text) != std::string::npos;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// The trajectory's state at utc_ns from the nearest sample, to second order: an estimate that
// shares nothing with the follower's interpolation (its error, jerk * dt^3 / 6 with dt <= half a
// sample step, is well under a millimetre).
Eigen::Vector3d trajectoryPositionAt(const TrajectoryData& t, std::int64_t utc_ns) {
  const TrajectorySampleData* nearest = &t.samples.front();
  for (const auto& s : t.samples) {
    if (std::llabs(s.utc_ns - utc_ns) < std::llabs(nearest->utc_ns - utc_ns)) nearest = &s;
  }
  const double dt = static_cast<double>(utc_ns - nearest->utc_ns) * 1e-9;
  return nearest->position_enu_m + nearest->velocity_enu_mps * dt + 0.5 * nearest->acceleration_enu_mps2 * dt * dt;
}

double headingAtRad(const TrajectoryData& t, std::int64_t utc_ns) {
  const auto& s = t.samples;
  std::size_t hi = 0;
  while (hi < s.size() && s[hi].utc_ns <= utc_ns) ++hi;
  if (hi == 0) return s.front().heading_deg * M_PI / 180.0;
  if (hi == s.size()) return s.back().heading_deg * M_PI / 180.0;
  const double a = s[hi - 1].heading_deg * M_PI / 180.0, b = s[hi].heading_deg * M_PI / 180.0;
  const double f = static_cast<double>(utc_ns - s[hi - 1].utc_ns) / static_cast<double>(s[hi].utc_ns - s[hi - 1].utc_ns);
  return a + f * std::remainder(b - a, 2 * M_PI);
}

struct RateStats {
  double mean_hz = 0, interval_std_ms = 0, interval_p95_dev_ms = 0, interval_max_dev_ms = 0;
};

RateStats rateOf(const std::vector<ReceivedSetpoint>& s, double period_s) {
  std::vector<double> intervals_ms;
  for (std::size_t i = 1; i < s.size(); ++i) intervals_ms.push_back((s[i].timestamp_us - s[i - 1].timestamp_us) * 1e-3);
  RateStats r;
  if (intervals_ms.empty()) return r;
  const double mean = std::accumulate(intervals_ms.begin(), intervals_ms.end(), 0.0) / intervals_ms.size();
  double var = 0;
  for (double x : intervals_ms) {
    var += (x - mean) * (x - mean);
    r.interval_max_dev_ms = std::max(r.interval_max_dev_ms, std::abs(x - period_s * 1e3));
  }
  r.mean_hz = 1e3 / mean;
  r.interval_std_ms = std::sqrt(var / intervals_ms.size());
  std::vector<double> deviations;
  for (double x : intervals_ms) deviations.push_back(std::abs(x - period_s * 1e3));
  std::sort(deviations.begin(), deviations.end());
  r.interval_p95_dev_ms = deviations[deviations.size() * 95 / 100];
  return r;
}

void printRate(const std::vector<ReceivedSetpoint>& s, const RateStats& r) {
  std::printf("[ measured ] %zu setpoints at %.2f Hz; interval std %.3f ms, |deviation| p95 %.3f ms, max %.3f ms\n",
              s.size(), r.mean_hz, r.interval_std_ms, r.interval_p95_dev_ms, r.interval_max_dev_ms);
}

void expectStrictlyIncreasingStamps(const std::vector<ReceivedSetpoint>& s) {
  for (std::size_t i = 1; i < s.size(); ++i) ASSERT_GT(s[i].timestamp_us, s[i - 1].timestamp_us) << "setpoint " << i;
}

// A stand-in skyrouted: a trajectory writer and a ServiceStatus heartbeat at 5 Hz while beating.
class FakeDaemon {
 public:
  explicit FakeDaemon(int domain) {
    participant_ = std::move(dds::createParticipant(domain).value());
    trajectories.emplace(std::move(dds::Writer<TrajectoryData>::create(participant_.get()).value()));
    heartbeat_.emplace(std::move(dds::Writer<ServiceStatusData>::create(participant_.get()).value()));
    thread_ = std::thread([this] {
      while (!quit_) {
        if (beating) {
          ServiceStatusData s;
          s.service_id = "fake-skyrouted";
          s.stamp_utc_ns = utcNowNs();
          (void)heartbeat_->write(s);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    });
  }
  ~FakeDaemon() {
    quit_ = true;
    thread_.join();
  }
  std::atomic<bool> beating{true};
  std::optional<dds::Writer<TrajectoryData>> trajectories;

 private:
  dds::Entity participant_;
  std::optional<dds::Writer<ServiceStatusData>> heartbeat_;
  std::atomic<bool> quit_{false};
  std::thread thread_;
};

// The daemon's kind of frame, at the default terrain's anchor.
LocalFrame daemonFrame() { return testing::defaultTerrainHeightfield()->frame(); }

TEST(Px4E2E, FollowsARealSkyroutedTrajectoryAtTheRateWithinACentimetre) {
  const int domain = 200;
  auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  ChildProcess daemon = ChildProcess::spawn({SKYROUTED, "--domain", std::to_string(domain)}, "skyrouted_px4");
  ASSERT_TRUE(daemon.started());
  auto station = testing::Station::open(domain);
  ASSERT_TRUE(station);
  ASSERT_TRUE(station->pumpUntil([&] { return station->heartbeats > 0 || !daemon.running(); }, 60.0)) << daemon.err();
  ASSERT_TRUE(station->requests->waitForReaders(1, 20.0).ok());
  ASSERT_TRUE(station->trajectories->waitForWriters(1, 20.0).ok());
  auto above = [&](double e, double n) {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain->heightAt(e, n) + 400.0));
  };
  MissionRequestData m;
  m.request_id = "px4-1";
  m.vehicle_id = "uav-px4";
  m.begin = above(-3000, 500);
  m.points = {above(0, 900)};
  m.end = above(3000, 500);
  ASSERT_TRUE(station->requests->write(m).ok());
  ASSERT_TRUE(station->waitTerminal({m.request_id}, 120.0)) << daemon.err();
  ASSERT_EQ(station->terminal(m.request_id)->state, PlanState::kSucceeded);
  ASSERT_TRUE(station->pumpUntil([&] { return station->latest(m.vehicle_id) != nullptr; }, 10.0));
  const TrajectoryData trajectory = *station->latest(m.vehicle_id);

  // PX4's EKF origin 1.5 km away from the daemon's anchor, at another altitude.
  const LocalFrame frame = terrain->frame();
  const GeoPoint origin{frame.anchor().lat_deg + 0.01, frame.anchor().lon_deg - 0.01, 250.0};
  auto px4 = FakePx4::open(domain, "uav_1");
  ASSERT_TRUE(px4);
  ChildProcess bridge = ChildProcess::spawn({SKYROUTE_CLI, "px4", "--vehicle", m.vehicle_id, "--namespace", "uav_1",
                                             "--origin", geoArg(origin), "--rate-hz", "50", "--domain",
                                             std::to_string(domain), "--duration", "8"},
                                            "px4_real");
  ASSERT_TRUE(bridge.started());
  ASSERT_TRUE(collectUntil(*px4, [&] { return !bridge.running(); }, 40.0)) << bridge.err();
  EXPECT_EQ(bridge.wait(1.0), 0) << bridge.err();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(10.0), 0) << daemon.err();

  const auto& s = px4->setpoints;
  ASSERT_GT(s.size(), 250u) << bridge.out() << bridge.err();  // about 7 s of the 8 at 50 Hz
  expectStrictlyIncreasingStamps(s);
  const RateStats rate = rateOf(s, 0.02);
  printRate(s, rate);
  EXPECT_NEAR(rate.mean_hz, 50.0, 2.5);

  const Px4Projection px4_frame(origin);
  double worst_m = 0, worst_yaw = 0;
  for (const auto& x : s) {
    const std::int64_t utc_ns = static_cast<std::int64_t>(x.timestamp_us) * 1000;
    ASSERT_GE(utc_ns, trajectory.samples.front().utc_ns);  // planned to start when planned: no wait
    const Eigen::Vector3d enu = frame.toEnu(px4_frame.toGeo(x.position));
    worst_m = std::max(worst_m, (enu - trajectoryPositionAt(trajectory, utc_ns)).norm());
    worst_yaw = std::max(worst_yaw, std::abs(std::remainder(x.yaw - headingAtRad(trajectory, utc_ns), 2 * M_PI)));
    EXPECT_LE(std::abs(x.yaw), M_PI);
  }
  std::printf("[ measured ] worst position error %.4f m, worst yaw error %.2e rad\n", worst_m, worst_yaw);
  EXPECT_LT(worst_m, 0.01);
  EXPECT_LT(worst_yaw, 1e-5);  // float32

  // OffboardControlMode alongside, position + velocity + acceleration.
  ASSERT_GE(px4->modes.size(), s.size());
  for (const auto& mode : px4->modes) {
    EXPECT_TRUE(mode.position && mode.velocity && mode.acceleration);
    EXPECT_FALSE(mode.attitude || mode.body_rate || mode.thrust_and_torque || mode.direct_actuator);
  }
  EXPECT_NE(bridge.out().find("following plan"), std::string::npos) << bridge.out();
}

TEST(Px4E2E, SwitchesToANewRevisionAtItsStartAndHoldsAfterTheEnd) {
  const int domain = 201;
  const LocalFrame frame = daemonFrame();
  FakeDaemon daemon(domain);
  const testing::Motion turn = testing::climbingTurn(Eigen::Vector3d(500, 200, 900), 250.0, 0.08, 2.0);
  const double switch_s = 3.0;
  const testing::Motion replanned = testing::divergingAt(turn, switch_s, Eigen::Vector3d(3.0, -2.0, 0.5));
  const std::int64_t t0 = utcNowNs() + 2'500'000'000;  // starts 2.5 s from now: the bridge waits at its start
  const TrajectoryData rev0 = testing::sample(turn, frame, {.vehicle = "uav-7", .motion_start_utc_ns = t0, .to_s = 6.0});
  const TrajectoryData rev1 = testing::sample(
      replanned, frame, {.vehicle = "uav-7", .revision = 1, .motion_start_utc_ns = t0, .from_s = switch_s, .to_s = 5.0});
  ASSERT_TRUE(daemon.trajectories->write(rev0).ok());

  const GeoPoint origin = frame.anchor();
  auto px4 = FakePx4::open(domain, "");
  ASSERT_TRUE(px4);
  ChildProcess bridge = ChildProcess::spawn({SKYROUTE_CLI, "px4", "--vehicle", "uav-7", "--origin", geoArg(origin),
                                             "--rate-hz", "20", "--domain", std::to_string(domain), "--duration", "9.5"},
                                            "px4_switch");
  ASSERT_TRUE(waitForLine(bridge, "following plan plan-1 revision 0", 20.0)) << bridge.out() << bridge.err();
  ASSERT_TRUE(daemon.trajectories->write(rev1).ok());  // a replan, published before it starts
  ASSERT_TRUE(collectUntil(*px4, [&] { return !bridge.running(); }, 30.0));
  ASSERT_EQ(bridge.wait(1.0), 0) << bridge.err();
  EXPECT_NE(bridge.out().find("waiting at the first sample"), std::string::npos) << bridge.out();
  EXPECT_NE(bridge.out().find("switched to plan plan-1 revision 1"), std::string::npos) << bridge.out();
  EXPECT_NE(bridge.out().find("holding (holding_at_end)"), std::string::npos) << bridge.out();

  const auto& s = px4->setpoints;
  expectStrictlyIncreasingStamps(s);
  const RateStats rate = rateOf(s, 0.05);
  printRate(s, rate);
  EXPECT_NEAR(rate.mean_hz, 20.0, 1.0);
  const Px4Projection px4_frame(origin);
  int before = 0, first = 0, second = 0, held = 0;
  for (const auto& x : s) {
    const double t = static_cast<double>(static_cast<std::int64_t>(x.timestamp_us) * 1000 - t0) * 1e-9;
    const Eigen::Vector3d enu = frame.toEnu(px4_frame.toGeo(x.position));
    if (t < 0.0) {
      EXPECT_LT((enu - turn.p(0.0)).norm(), 0.01) << "waiting at the start, t=" << t;
      EXPECT_EQ(x.velocity, Eigen::Vector3d::Zero());
      ++before;
    } else if (t < switch_s) {
      EXPECT_LT((enu - turn.p(t)).norm(), 0.01) << "revision 0, t=" << t;
      ++first;
    } else if (t <= 5.0) {
      EXPECT_LT((enu - replanned.p(t)).norm(), 0.01) << "revision 1, t=" << t;
      ++second;
    } else {
      EXPECT_LT((enu - replanned.p(5.0)).norm(), 0.01) << "holding after the end, t=" << t;
      EXPECT_EQ(x.velocity, Eigen::Vector3d::Zero());
      EXPECT_EQ(x.acceleration, Eigen::Vector3d::Zero());
      ++held;
    }
  }
  EXPECT_GT(before, 5);
  EXPECT_GT(first, 40);
  EXPECT_GT(second, 30);
  EXPECT_GT(held, 40);
}

TEST(Px4E2E, HoldsWhenTheDaemonFallsSilent) {
  const int domain = 202;
  const LocalFrame frame = daemonFrame();
  FakeDaemon daemon(domain);
  const testing::Motion turn = testing::climbingTurn(Eigen::Vector3d(-400, 300, 800), 300.0, 0.05, 0.0);
  ASSERT_TRUE(daemon.trajectories
                  ->write(testing::sample(turn, frame, {.vehicle = "uav-s", .motion_start_utc_ns = utcNowNs(), .to_s = 60.0}))
                  .ok());
  auto px4 = FakePx4::open(domain, "");
  ASSERT_TRUE(px4);
  ChildProcess bridge =
      ChildProcess::spawn({SKYROUTE_CLI, "px4", "--vehicle", "uav-s", "--origin", geoArg(frame.anchor()), "--domain",
                           std::to_string(domain), "--silence-timeout", "1", "--duration", "6"},
                          "px4_silent");
  ASSERT_TRUE(waitForLine(bridge, "streaming setpoints", 20.0)) << bridge.out() << bridge.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  daemon.beating = false;
  const std::int64_t silent_from_us = utcNowNs() / 1000;
  ASSERT_TRUE(collectUntil(*px4, [&] { return !bridge.running(); }, 30.0));
  ASSERT_EQ(bridge.wait(1.0), 0) << bridge.err();
  EXPECT_NE(bridge.out().find("holding (holding_silent): no word from skyrouted"), std::string::npos) << bridge.out();

  // Moving until the timeout, then one position with zero velocity.
  std::vector<ReceivedSetpoint> after;
  Eigen::Vector3d first_position = px4->setpoints.front().position;
  bool moved = false;
  for (const auto& x : px4->setpoints) {
    if (x.timestamp_us < static_cast<std::uint64_t>(silent_from_us)) moved = moved || (x.position - first_position).norm() > 1.0;
    if (x.timestamp_us > static_cast<std::uint64_t>(silent_from_us) + 1'300'000) after.push_back(x);
  }
  EXPECT_TRUE(moved);
  ASSERT_GT(after.size(), 50u);
  for (const auto& x : after) {
    EXPECT_EQ(x.position, after.front().position);
    EXPECT_EQ(x.velocity, Eigen::Vector3d::Zero());
  }
}

TEST(Px4E2E, TakesTheOriginFromPx4AndHoldsWhenTheTrajectoryIsRetracted) {
  const int domain = 203;
  const LocalFrame frame = daemonFrame();
  FakeDaemon daemon(domain);
  const testing::Motion turn = testing::climbingTurn(Eigen::Vector3d(800, -600, 700), 200.0, 0.07, 1.0);
  const TrajectoryData t = testing::sample(turn, frame, {.vehicle = "uav-r", .motion_start_utc_ns = utcNowNs(), .to_s = 60.0});
  ASSERT_TRUE(daemon.trajectories->write(t).ok());
  auto px4 = FakePx4::open(domain, "uav_2");
  ASSERT_TRUE(px4);
  const GeoPoint ekf_origin{frame.anchor().lat_deg - 0.02, frame.anchor().lon_deg + 0.015, 431.5};
  ChildProcess bridge = ChildProcess::spawn(
      {SKYROUTE_CLI, "px4", "--vehicle", "uav-r", "--namespace", "/uav_2/", "--domain", std::to_string(domain), "--duration", "6"},
      "px4_origin");
  // PX4 tells its origin a few times a second, as its bridge streams vehicle_local_position.
  auto next_tell = Clock::now();
  ASSERT_TRUE(collectUntil(
      *px4,
      [&] {
        if (Clock::now() >= next_tell) {
          (void)px4->tellOrigin(ekf_origin.lat_deg, ekf_origin.lon_deg, static_cast<float>(ekf_origin.alt_amsl_m));
          next_tell += std::chrono::milliseconds(100);
        }
        return bridge.out().find("streaming setpoints") != std::string::npos || !bridge.running();
      },
      20.0))
      << bridge.out() << bridge.err();
  EXPECT_NE(bridge.out().find("from rt/uav_2/fmu/out/vehicle_local_position"), std::string::npos) << bridge.out();
  ASSERT_TRUE(collectUntil(*px4, [&] { return px4->setpoints.size() > 50; }, 10.0));
  ASSERT_TRUE(daemon.trajectories->dispose(t).ok());
  ASSERT_TRUE(collectUntil(*px4, [&] { return !bridge.running(); }, 30.0));
  ASSERT_EQ(bridge.wait(1.0), 0) << bridge.err();
  EXPECT_NE(bridge.out().find("holding (holding_retracted)"), std::string::npos) << bridge.out();

  // Relative to PX4's origin (ref_alt is a float32: 431.5 is exact).
  const Px4Projection px4_frame(ekf_origin);
  const auto& s = px4->setpoints;
  std::size_t following = 0;
  for (const auto& x : s) {
    if (x.velocity == Eigen::Vector3d::Zero()) break;
    const std::int64_t utc_ns = static_cast<std::int64_t>(x.timestamp_us) * 1000;
    EXPECT_LT((frame.toEnu(px4_frame.toGeo(x.position)) - trajectoryPositionAt(t, utc_ns)).norm(), 0.01);
    ++following;
  }
  EXPECT_GT(following, 50u);
  ASSERT_LT(following + 20, s.size()) << "no hold after the retraction";
  for (std::size_t i = following; i < s.size(); ++i) EXPECT_EQ(s[i].position, s[following].position);
}

TEST(Px4E2E, WithoutAnOriginWithinFiveSecondsItSaysSoAndExitsWithTheTimeoutCode) {
  const auto started = Clock::now();
  ChildProcess bridge = ChildProcess::spawn({SKYROUTE_CLI, "px4", "--vehicle", "uav-x", "--domain", "204"}, "px4_no_origin");
  EXPECT_EQ(bridge.wait(30.0), 4) << bridge.out() << bridge.err();
  const double took_s = std::chrono::duration<double>(Clock::now() - started).count();
  EXPECT_GE(took_s, 5.0);
  EXPECT_LT(took_s, 15.0);
  EXPECT_NE(bridge.err().find("no EKF origin from PX4 within 5 s"), std::string::npos) << bridge.err();
  EXPECT_NE(bridge.err().find("rt/fmu/out/vehicle_local_position"), std::string::npos) << bridge.err();
  EXPECT_NE(bridge.err().find("--origin"), std::string::npos) << bridge.err();
}

TEST(Px4E2E, BadOptionsExitTwoNamingTheOption) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--vehicle", "v", "--rate-hz", "10"}, "--rate-hz"},
      {{"--vehicle", "v", "--rate-hz", "51"}, "--rate-hz"},
      {{"--vehicle", "v", "--rate-hz", "fast"}, "--rate-hz"},
      {{"--vehicle", "v", "--origin", "47.1,8.5"}, "--origin"},
      {{"--vehicle", "v", "--origin", "97,8.5,400"}, "--origin"},
      {{"--vehicle", "v", "--origin", "north,8.5,400"}, "--origin"},
      {{"--vehicle", "v", "--namespace", "2uav"}, "--namespace"},
      {{"--vehicle", "v", "--silence-timeout", "0"}, "--silence-timeout"},
      {{"--vehicle", "v", "--silence-timeout", "soon"}, "--silence-timeout"},
      {{"--rate-hz", "30"}, "--vehicle"},
  };
  for (const auto& [args, option] : cases) {
    std::vector<std::string> argv{SKYROUTE_CLI, "px4"};
    argv.insert(argv.end(), args.begin(), args.end());
    ChildProcess p = ChildProcess::spawn(argv, "px4_bad");
    EXPECT_EQ(p.wait(10.0), 2) << args.back() << ": " << p.err();
    EXPECT_NE(p.err().find(option), std::string::npos) << p.err();
  }
}

}  // namespace
}  // namespace skyroute
