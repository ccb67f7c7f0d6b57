// What `skyroute px4` streams, checked against motions with a closed form (a climbing turn, and a
// revision that leaves it): positions in PX4's frame that map back onto the exact motion between
// the samples, velocity and acceleration that are the derivatives of those positions, yaw from the
// heading, a seamless switch to a new revision at its start, and the holds (end, silence,
// retraction) that last until a different trajectory arrives.
#include <cmath>

#include <gtest/gtest.h>

#include "service/offboard_follower.hpp"
#include "tests/service/synthetic_trajectory.hpp"

namespace skyroute {
namespace {

using testing::climbingTurn;
using testing::Motion;
using testing::SampledMotion;

constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;  // the motion's t = 0, UTC ns
constexpr GeoPoint kPx4Origin{46.96, 15.15, 350.0};    // about 3 km from the daemon's anchor

std::int64_t at(double t_s) { return kT0 + static_cast<std::int64_t>(std::llround(t_s * 1e9)); }

class OffboardFollowerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto frame = LocalFrame::create(46.94, 15.12);
    ASSERT_TRUE(frame.ok());
    frame_ = *frame;
  }
  // Where a setpoint puts the vehicle, in the daemon's ENU frame.
  Eigen::Vector3d enuOf(const OffboardSetpoint& s) const { return frame_->toEnu(px4_.toGeo(s.position_ned_m)); }
  TrajectoryData sampled(const Motion& m, SampledMotion s) const {
    s.motion_start_utc_ns = kT0;
    return testing::sample(m, *frame_, s);
  }

  std::optional<LocalFrame> frame_;
  Px4Projection px4_{kPx4Origin};
  Motion turn_ = climbingTurn(Eigen::Vector3d(1500, -800, 700), 300.0, 0.06, 1.5);  // 18 m/s
};

TEST_F(OffboardFollowerTest, SetpointsMapBackOntoTheExactMotionBetweenSamples) {
  OffboardFollower follower(kPx4Origin, {});
  ASSERT_TRUE(follower.offer(sampled(turn_, {.to_s = 30.0}), at(0.0)).ok());
  for (double t = 0.013; t < 29.9; t += 0.377) {  // never on a sample
    follower.heardFromDaemon(at(t));
    auto s = follower.step(at(t));
    ASSERT_TRUE(s);
    EXPECT_EQ(follower.mode(), FollowMode::kFollowing);
    EXPECT_EQ(s->time_utc_ns, at(t));
    EXPECT_LT((enuOf(*s) - turn_.p(t)).norm(), 1e-3) << "t=" << t;

    // Velocity and acceleration are the time derivatives of the NED positions given.
    constexpr double h = 1e-3;
    auto ned = [&](double u) { return follower.step(at(u))->position_ned_m; };
    const Eigen::Vector3d v_numeric = (ned(t + h) - ned(t - h)) / (2 * h);
    const Eigen::Vector3d a_numeric = (ned(t + 10 * h) - 2 * ned(t) + ned(t - 10 * h)) / (100 * h * h);
    const auto now = follower.step(at(t));
    EXPECT_LT((now->velocity_ned_mps - v_numeric).norm(), 2e-3) << "t=" << t;
    EXPECT_LT((now->acceleration_ned_mps2 - a_numeric).norm(), 2e-2) << "t=" << t;
    EXPECT_NEAR(now->velocity_ned_mps.z(), -1.5, 1e-6);  // climbing: negative down

    // Yaw: the compass heading of the motion (it turns at a constant rate: linear in time).
    const double heading = testing::compassHeadingOf(turn_.v(t)) * M_PI / 180.0;
    EXPECT_NEAR(std::remainder(now->yaw_rad - heading, 2 * M_PI), 0.0, 1e-9) << "t=" << t;
    EXPECT_LE(std::abs(now->yaw_rad), M_PI);
  }
}

TEST_F(OffboardFollowerTest, YawIsTheHeadingInMinusPiToPi) {
  // Straight flight at a heading of 350 degrees, then 180.
  for (double heading_deg : {350.0, 180.0, 90.0}) {
    const Eigen::Vector3d dir(std::sin(heading_deg * M_PI / 180.0), std::cos(heading_deg * M_PI / 180.0), 0.0);
    const Motion line{[=](double t) { return Eigen::Vector3d(Eigen::Vector3d(0, 0, 500) + 15.0 * t * dir); },
                      [=](double) { return Eigen::Vector3d(15.0 * dir); }, [](double) { return Eigen::Vector3d::Zero(); }};
    OffboardFollower follower(frame_->anchor(), {});  // PX4's origin at the daemon's: no convergence
    ASSERT_TRUE(follower.offer(sampled(line, {}), at(0.0)).ok());
    auto s = follower.step(at(4.1));
    ASSERT_TRUE(s);
    const double expected = std::remainder(heading_deg * M_PI / 180.0, 2 * M_PI);  // 350 -> -10 degrees
    EXPECT_NEAR(std::remainder(s->yaw_rad - expected, 2 * M_PI), 0.0, 1e-6) << heading_deg;
    EXPECT_GE(s->yaw_rad, -M_PI);
    EXPECT_LE(s->yaw_rad, M_PI);
    if (heading_deg == 350.0) {
      EXPECT_NEAR(s->yaw_rad, -10.0 * M_PI / 180.0, 1e-6);
    }
  }
}

TEST_F(OffboardFollowerTest, WaitsAtTheFirstSampleAndHoldsTheLastAfterTheEnd) {
  OffboardFollower follower(kPx4Origin, {});
  ASSERT_TRUE(follower.offer(sampled(turn_, {.from_s = 2.0, .to_s = 6.0}), at(0.0)).ok());
  auto early = follower.step(at(1.0));
  ASSERT_TRUE(early);
  EXPECT_EQ(follower.mode(), FollowMode::kBeforeStart);
  EXPECT_LT((enuOf(*early) - turn_.p(2.0)).norm(), 1e-3);
  EXPECT_EQ(early->velocity_ned_mps, Eigen::Vector3d::Zero());

  follower.heardFromDaemon(at(6.5));
  auto late = follower.step(at(6.5));
  ASSERT_TRUE(late);
  EXPECT_EQ(follower.mode(), FollowMode::kHoldingAtEnd);
  EXPECT_LT((enuOf(*late) - turn_.p(6.0)).norm(), 1e-3);
  EXPECT_EQ(late->velocity_ned_mps, Eigen::Vector3d::Zero());
  EXPECT_EQ(late->acceleration_ned_mps2, Eigen::Vector3d::Zero());
  bool said = false;
  for (const auto& e : follower.takeEvents()) said = said || e.find("ended") != std::string::npos;
  EXPECT_TRUE(said);
  // The same revision again (a restarted daemon's transient-local history) does not end the hold.
  ASSERT_TRUE(follower.offer(sampled(turn_, {.from_s = 2.0, .to_s = 6.0}), at(7.0)).ok());
  auto still = follower.step(at(7.5));
  EXPECT_EQ(follower.mode(), FollowMode::kHoldingAtEnd);
  EXPECT_EQ(still->position_ned_m, late->position_ned_m);
  EXPECT_EQ(still->time_utc_ns, at(7.5));
}

TEST_F(OffboardFollowerTest, ANewRevisionTakesOverAtItsStartWithoutAJump) {
  const double switch_s = 10.0;
  const Motion replanned = testing::divergingAt(turn_, switch_s, Eigen::Vector3d(4.0, -2.0, 1.0));
  OffboardFollower follower(kPx4Origin, {});
  ASSERT_TRUE(follower.offer(sampled(turn_, {.to_s = 30.0}), at(0.0)).ok());
  (void)follower.step(at(1.0));
  // Revision 1 arrives early and starts at switch_s, at the state revision 0 predicts there.
  ASSERT_TRUE(follower.offer(sampled(replanned, {.revision = 1, .from_s = switch_s, .to_s = 30.0}), at(2.0)).ok());
  follower.heardFromDaemon(at(9.0));
  auto before = follower.step(at(switch_s - 0.5));
  EXPECT_LT((enuOf(*before) - turn_.p(switch_s - 0.5)).norm(), 1e-3) << "switched too early";
  auto after = follower.step(at(switch_s + 0.5));
  EXPECT_LT((enuOf(*after) - replanned.p(switch_s + 0.5)).norm(), 1e-3) << "did not switch";
  EXPECT_GT((replanned.p(switch_s + 0.5) - turn_.p(switch_s + 0.5)).norm(), 0.4);  // the test tells them apart

  bool said = false;
  for (const auto& e : follower.takeEvents()) said = said || e.find("switched to plan plan-1 revision 1") != std::string::npos;
  EXPECT_TRUE(said);

  // Across the switch the setpoints move as the vehicle does: no jump.
  OffboardFollower across(kPx4Origin, {});
  ASSERT_TRUE(across.offer(sampled(turn_, {.to_s = 30.0}), at(0.0)).ok());
  ASSERT_TRUE(across.offer(sampled(replanned, {.revision = 1, .from_s = switch_s, .to_s = 30.0}), at(0.0)).ok());
  across.heardFromDaemon(at(switch_s));
  auto just_before = across.step(at(switch_s - 1e-3));
  auto just_after = across.step(at(switch_s + 1e-3));
  const Eigen::Vector3d moved = just_after->position_ned_m - just_before->position_ned_m;
  EXPECT_LT((moved - just_before->velocity_ned_mps * 2e-3).norm(), 1e-4);
  const Eigen::Vector3d dv = just_after->velocity_ned_mps - just_before->velocity_ned_mps;
  EXPECT_LT((dv - just_before->acceleration_ned_mps2 * 2e-3).norm(), 1e-4);
}

TEST_F(OffboardFollowerTest, BeforeAnyStartTheRevisionThatStartsFirstIsFlownFirst) {
  const Motion replanned = testing::divergingAt(turn_, 5.0, Eigen::Vector3d(4.0, 0.0, 0.0));
  // Both arrive before revision 0 starts: revision 0 is flown from 2 s, revision 1 from 5 s.
  OffboardFollower later(kPx4Origin, {});
  ASSERT_TRUE(later.offer(sampled(turn_, {.from_s = 2.0, .to_s = 30.0}), at(0.0)).ok());
  (void)later.step(at(0.5));
  ASSERT_TRUE(later.offer(sampled(replanned, {.revision = 1, .from_s = 5.0, .to_s = 30.0}), at(1.0)).ok());
  EXPECT_LT((enuOf(*later.step(at(1.5))) - turn_.p(2.0)).norm(), 1e-3);
  EXPECT_LT((enuOf(*later.step(at(4.0))) - turn_.p(4.0)).norm(), 1e-3);
  later.heardFromDaemon(at(6.0));
  EXPECT_LT((enuOf(*later.step(at(6.0))) - replanned.p(6.0)).norm(), 1e-3);

  // A revision that starts no later than the waiting one replaces it at once.
  OffboardFollower sooner(kPx4Origin, {});
  ASSERT_TRUE(sooner.offer(sampled(turn_, {.from_s = 4.0, .to_s = 30.0}), at(0.0)).ok());
  (void)sooner.step(at(0.5));
  ASSERT_TRUE(sooner.offer(sampled(replanned, {.revision = 1, .from_s = 3.0, .to_s = 30.0}), at(1.0)).ok());
  EXPECT_LT((enuOf(*sooner.step(at(1.5))) - replanned.p(3.0)).norm(), 1e-3);
  EXPECT_EQ(sooner.mode(), FollowMode::kBeforeStart);
}

TEST_F(OffboardFollowerTest, HoldsWhenTheDaemonFallsSilentUntilADifferentTrajectoryArrives) {
  OffboardFollower follower(kPx4Origin, {.silence_timeout_s = 2.0});
  ASSERT_TRUE(follower.offer(sampled(turn_, {.to_s = 30.0}), at(0.0)).ok());
  auto flying = follower.step(at(1.9));
  EXPECT_EQ(follower.mode(), FollowMode::kFollowing);
  auto held = follower.step(at(2.1));
  EXPECT_EQ(follower.mode(), FollowMode::kHoldingSilent);
  EXPECT_EQ(held->position_ned_m, flying->position_ned_m);
  EXPECT_EQ(held->velocity_ned_mps, Eigen::Vector3d::Zero());
  // The daemon is back with the same revision: still holding (resuming would jump ahead).
  follower.heardFromDaemon(at(5.0));
  ASSERT_TRUE(follower.offer(sampled(turn_, {.to_s = 30.0}), at(5.0)).ok());
  EXPECT_EQ(follower.step(at(5.1))->position_ned_m, flying->position_ned_m);
  EXPECT_EQ(follower.mode(), FollowMode::kHoldingSilent);
  // A new revision, already started: followed.
  ASSERT_TRUE(follower.offer(sampled(turn_, {.revision = 1, .from_s = 5.0, .to_s = 30.0}), at(5.2)).ok());
  auto resumed = follower.step(at(6.0));
  EXPECT_EQ(follower.mode(), FollowMode::kFollowing);
  EXPECT_LT((enuOf(*resumed) - turn_.p(6.0)).norm(), 1e-3);
}

TEST_F(OffboardFollowerTest, ARetractionHoldsAndAMovedOriginKeepsTheHoldInPlace) {
  OffboardFollower follower(kPx4Origin, {});
  ASSERT_TRUE(follower.offer(sampled(turn_, {.to_s = 30.0}), at(0.0)).ok());
  auto flying = follower.step(at(3.0));
  follower.retract();
  auto held = follower.step(at(3.02));
  EXPECT_EQ(follower.mode(), FollowMode::kHoldingRetracted);
  EXPECT_EQ(held->position_ned_m, flying->position_ned_m);

  const GeoPoint moved_origin{46.95, 15.10, 400.0};
  follower.setOrigin(moved_origin);
  auto same_place = follower.step(at(3.04));
  const GeoPoint there = Px4Projection(moved_origin).toGeo(same_place->position_ned_m);
  EXPECT_LT((frame_->toEnu(there) - enuOf(*flying)).norm(), 1e-6);
}

TEST_F(OffboardFollowerTest, SamplesThatFitNoFrameAreIgnoredWithTheReason) {
  OffboardFollower follower(kPx4Origin, {});
  TrajectoryData broken = sampled(turn_, {});
  broken.samples[4].geo.lon_deg += 1e-4;
  Status offered = follower.offer(broken, at(0.0));
  ASSERT_FALSE(offered.ok());
  EXPECT_EQ(offered.error().field, "samples[4]");
  EXPECT_FALSE(follower.step(at(1.0)));
  EXPECT_EQ(follower.mode(), FollowMode::kWaiting);
  const auto events = follower.takeEvents();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("ignored plan plan-1 revision 0"), std::string::npos) << events[0];
}

}  // namespace
}  // namespace skyroute
