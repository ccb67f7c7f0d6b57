// A ground station prints each transition of a request once.
#include <gtest/gtest.h>

#include "service/status_transitions.hpp"

namespace skyroute {
namespace {

PlanStatusData status(const std::string& request, PlanState state, double planning_time_s = 0.0) {
  PlanStatusData s;
  s.vehicle_id = "uav-1";
  s.request_id = request;
  s.state = state;
  s.planning_time_s = planning_time_s;
  return s;
}

TEST(StatusTransitions, EachTransitionOfARequestOnce) {
  StatusTransitions printed;
  EXPECT_TRUE(printed.firstTime(status("r1", PlanState::kAccepted)));
  EXPECT_TRUE(printed.firstTime(status("r1", PlanState::kPlanning)));
  EXPECT_FALSE(printed.firstTime(status("r1", PlanState::kAccepted)));
  EXPECT_FALSE(printed.firstTime(status("r1", PlanState::kPlanning)));
  EXPECT_TRUE(printed.firstTime(status("r1", PlanState::kSucceeded, 0.2)));
  EXPECT_FALSE(printed.firstTime(status("r1", PlanState::kSucceeded, 0.3)));  // a second daemon's answer
  // Another request of the same vehicle has its own transitions.
  EXPECT_TRUE(printed.firstTime(status("r2", PlanState::kAccepted)));
  PlanStatusData other_vehicle = status("r1", PlanState::kAccepted);
  other_vehicle.vehicle_id = "uav-2";
  EXPECT_TRUE(printed.firstTime(other_vehicle));
}

TEST(StatusTransitions, EveryReplanIsNew) {
  StatusTransitions printed;
  EXPECT_TRUE(printed.firstTime(status("r1", PlanState::kReplanned, 0.01)));
  EXPECT_TRUE(printed.firstTime(status("r1", PlanState::kReplanned, 0.02)));
}

}  // namespace
}  // namespace skyroute
