#include "service/planner_status.hpp"

#include <array>

namespace skyroute {
namespace {

// A leg's own budget running out (iterations or its wall-clock cap) is "no path within the
// budget", so unreachable; only the request's deadline or cancel (kTimeout, kCancelled from the
// caller's termination condition) ends the request as such. An approximate path is never flown.
constexpr std::array<PlannerStatusRow, 10> kTable{{
    {PlannerStatus::kSolved, ErrorCode::kInternal, PlanErrorCode::kNone, PlanState::kSucceeded},
    {PlannerStatus::kStoppedWithPath, ErrorCode::kInternal, PlanErrorCode::kNone, PlanState::kSucceeded},
    {PlannerStatus::kApproximate, ErrorCode::kUnreachable, PlanErrorCode::kUnreachable, PlanState::kFailed},
    {PlannerStatus::kStartInvalid, ErrorCode::kOccupied, PlanErrorCode::kUnderGround, PlanState::kFailed},
    {PlannerStatus::kGoalInvalid, ErrorCode::kOccupied, PlanErrorCode::kUnderGround, PlanState::kFailed},
    {PlannerStatus::kNoPath, ErrorCode::kUnreachable, PlanErrorCode::kUnreachable, PlanState::kFailed},
    {PlannerStatus::kBudgetExhausted, ErrorCode::kUnreachable, PlanErrorCode::kUnreachable, PlanState::kFailed},
    {PlannerStatus::kTimeout, ErrorCode::kTimeout, PlanErrorCode::kTimeout, PlanState::kFailed},
    {PlannerStatus::kCancelled, ErrorCode::kCancelled, PlanErrorCode::kCancelled, PlanState::kCancelled},
    {PlannerStatus::kInvalidParameters, ErrorCode::kInvalidArgument, PlanErrorCode::kInvalidArgument, PlanState::kFailed},
}};

}  // namespace

std::span<const PlannerStatusRow> plannerStatusTable() { return kTable; }

const PlannerStatusRow& plannerStatusRow(PlannerStatus status) {
  for (const PlannerStatusRow& row : kTable) {
    if (row.status == status) return row;
  }
  return kTable[static_cast<std::size_t>(PlannerStatus::kNoPath)];
}

Error plannerError(PlannerStatus status, std::string field, std::string message) {
  return make_error(plannerStatusRow(status).error, std::move(field), std::move(message));
}

}  // namespace skyroute
