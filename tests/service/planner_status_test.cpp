// The one table from a planner's status to the service's reply: every status has one row, and a
// leg planner's error built from it reaches the reply code and the request state the row names.
#include "service/planner_status.hpp"

#include <set>

#include <gtest/gtest.h>

namespace skyroute {
namespace {

const PlannerStatus kEveryStatus[] = {
    PlannerStatus::kSolved,      PlannerStatus::kStoppedWithPath, PlannerStatus::kApproximate,
    PlannerStatus::kStartInvalid, PlannerStatus::kGoalInvalid,    PlannerStatus::kNoPath,
    PlannerStatus::kBudgetExhausted, PlannerStatus::kTimeout,     PlannerStatus::kCancelled,
    PlannerStatus::kInvalidParameters,
};

TEST(PlannerStatusTable, EveryStatusHasExactlyOneRow) {
  std::set<PlannerStatus> seen;
  for (const PlannerStatusRow& row : plannerStatusTable()) EXPECT_TRUE(seen.insert(row.status).second) << to_string(row.status);
  for (PlannerStatus s : kEveryStatus) {
    EXPECT_EQ(seen.count(s), 1u) << to_string(s);
    EXPECT_EQ(plannerStatusRow(s).status, s) << to_string(s);
  }
  EXPECT_EQ(seen.size(), std::size(kEveryStatus));
}

TEST(PlannerStatusTable, AnErrorFromARowReachesTheRowsReplyCodeAndState) {
  MissionRequestData request;
  request.request_id = "r1";
  for (const PlannerStatusRow& row : plannerStatusTable()) {
    if (row.state == PlanState::kSucceeded) {
      EXPECT_TRUE(hasPath(row.status)) << to_string(row.status);
      EXPECT_EQ(row.plan_error, PlanErrorCode::kNone);
      continue;
    }
    EXPECT_FALSE(hasPath(row.status)) << to_string(row.status);
    const PlanError error = toPlanError(plannerError(row.status, "legs[2]", "what happened"));
    EXPECT_EQ(error.code, row.plan_error) << to_string(row.status);
    EXPECT_EQ(error.field, "legs[2]");
    const PlanStatusData status = PlanStatusData::failed(request, error, 0.5);
    EXPECT_EQ(status.state, row.state) << to_string(row.status);
    EXPECT_EQ(status.error_code, row.plan_error) << to_string(row.status);
  }
}

TEST(PlannerStatusTable, OnlyTheCallersStopEndsARequestAsTimedOutOrCancelled) {
  // A leg's own budget running out is no path within it; the request's deadline and cancel are
  // what they say.
  EXPECT_EQ(plannerStatusRow(PlannerStatus::kBudgetExhausted).plan_error, PlanErrorCode::kUnreachable);
  EXPECT_EQ(plannerStatusRow(stoppedStatus(TerminationCondition::Reason::kIterations)).plan_error,
            PlanErrorCode::kUnreachable);
  EXPECT_EQ(plannerStatusRow(stoppedStatus(TerminationCondition::Reason::kDeadline)).plan_error, PlanErrorCode::kTimeout);
  EXPECT_EQ(plannerStatusRow(stoppedStatus(TerminationCondition::Reason::kCancelled)).state, PlanState::kCancelled);
  EXPECT_EQ(plannerStatusRow(PlannerStatus::kApproximate).state, PlanState::kFailed);
}

}  // namespace
}  // namespace skyroute
