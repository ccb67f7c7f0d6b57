// The one table from how a planner's search ended (PlannerStatus, planning/core/planner_status.hpp)
// to what the service says about it: the library error a leg planner returns, the reply's error
// code (PlanErrorCode) and the request's state (PlanState). The IDL conversion of those two is
// service/dds/conversions.cpp's; nothing else maps a planner status.
#pragma once

#include <span>
#include <string>

#include "planning/core/planner_status.hpp"
#include "planning/core/result.hpp"
#include "service/mission_types.hpp"

namespace skyroute {

struct PlannerStatusRow {
  PlannerStatus status;
  ErrorCode error;           // what a leg planner returns when its search ended so (unused with a path)
  PlanErrorCode plan_error;  // the reply's code; kNone when a path came out
  PlanState state;           // kSucceeded, kFailed or kCancelled
};

// Every PlannerStatus, once.
std::span<const PlannerStatusRow> plannerStatusTable();
const PlannerStatusRow& plannerStatusRow(PlannerStatus status);

// The error a leg planner returns when its search ended with `status` and no path it can use.
Error plannerError(PlannerStatus status, std::string field, std::string message);

}  // namespace skyroute
