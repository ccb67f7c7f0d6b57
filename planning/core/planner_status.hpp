// The one status vocabulary of the planners (grid searches, any-angle, space-time A*, RRT*,
// HAB-PP, the fleet's path stage): how a search ended. The service turns it into its reply codes
// in one table (service/planner_status.hpp).
#pragma once

#include <string_view>

#include "planning/core/termination.hpp"

namespace skyroute {

enum class PlannerStatus {
  kSolved,             // a path from start to goal (optimal where the planner proves it, converged for HAB-PP)
  kStoppedWithPath,    // the termination condition stopped an anytime search after it found a path: the best so far
  kApproximate,        // no path to the goal; the path ends at the reached state nearest it (when asked for)
  kStartInvalid,       // start outside the planner's space or blocked
  kGoalInvalid,        // goal outside the planner's space or blocked
  kNoPath,             // proven: no path joins start and goal (open list empty, no connected cells)
  kBudgetExhausted,    // an iteration, expansion or conflict budget ran out before a path
  kTimeout,            // the deadline passed before a path
  kCancelled,          // the cancel flag was set before a path
  kInvalidParameters,  // the planner's parameters are invalid (the result's message says which)
};

std::string_view to_string(PlannerStatus status);

// A path start..goal is there (solved, or the best so far when stopped).
inline bool hasPath(PlannerStatus s) { return s == PlannerStatus::kSolved || s == PlannerStatus::kStoppedWithPath; }

// The search ended on a budget, a deadline or a cancel before any path.
inline bool isStopped(PlannerStatus s) {
  return s == PlannerStatus::kBudgetExhausted || s == PlannerStatus::kTimeout || s == PlannerStatus::kCancelled;
}

// The status of a search that the termination condition stopped before any path, by its reason.
inline PlannerStatus stoppedStatus(TerminationCondition::Reason reason) {
  switch (reason) {
    case TerminationCondition::Reason::kCancelled: return PlannerStatus::kCancelled;
    case TerminationCondition::Reason::kIterations: return PlannerStatus::kBudgetExhausted;
    case TerminationCondition::Reason::kDeadline:
    case TerminationCondition::Reason::kNone: break;
  }
  return PlannerStatus::kTimeout;
}

}  // namespace skyroute
