// The daemon's local frame recovered from a trajectory's samples: the anchor comes back, wherever
// the samples are, and samples that fit no single frame are refused naming the worst one.
#include <gtest/gtest.h>

#include "service/trajectory_frame.hpp"
#include "tests/service/synthetic_trajectory.hpp"

namespace skyroute {
namespace {

TEST(TrajectoryFrame, RecoversTheAnchorOfTheFrameTheSamplesWereMadeIn) {
  for (double anchor_alt_m : {0.0, 312.5}) {
    auto frame = LocalFrame::create(46.94, 15.12, anchor_alt_m);
    ASSERT_TRUE(frame.ok());
    // Far from the anchor (8 km), where the frame is no longer a plain shift of another one.
    const auto motion = testing::climbingTurn(Eigen::Vector3d(6000, -5000, 800), 300.0, 0.06, 1.5);
    const TrajectoryData t = testing::sample(motion, *frame, {});
    auto recovered = recoverTrajectoryFrame(t);
    ASSERT_TRUE(recovered.ok()) << recovered.error().describe();
    EXPECT_NEAR(recovered->anchor().lat_deg, 46.94, 1e-11);  // 1 micrometre
    EXPECT_NEAR(recovered->anchor().lon_deg, 15.12, 1e-11);
    EXPECT_NEAR(recovered->anchor().alt_amsl_m, anchor_alt_m, 1e-9);
    for (const auto& s : t.samples) EXPECT_LT((recovered->toEnu(s.geo) - s.position_enu_m).norm(), 1e-6);
  }
}

TEST(TrajectoryFrame, SamplesThatFitNoFrameAreRefusedNamingTheWorst) {
  auto frame = LocalFrame::create(46.94, 15.12);
  ASSERT_TRUE(frame.ok());
  TrajectoryData t = testing::sample(testing::climbingTurn(Eigen::Vector3d(0, 0, 800), 300.0, 0.06, 0.0), *frame, {});
  t.samples[7].geo.lat_deg += 1e-5;  // about 1 m
  auto recovered = recoverTrajectoryFrame(t);
  ASSERT_FALSE(recovered.ok());
  EXPECT_EQ(recovered.error().field, "samples[7]");
  EXPECT_FALSE(recoverTrajectoryFrame(TrajectoryData{}).ok());
}

}  // namespace
}  // namespace skyroute
