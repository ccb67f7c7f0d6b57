#include "planning/core/planner_status.hpp"

namespace skyroute {

std::string_view to_string(PlannerStatus status) {
  switch (status) {
    case PlannerStatus::kSolved: return "solved";
    case PlannerStatus::kStoppedWithPath: return "stopped with a path";
    case PlannerStatus::kApproximate: return "approximate";
    case PlannerStatus::kStartInvalid: return "start invalid";
    case PlannerStatus::kGoalInvalid: return "goal invalid";
    case PlannerStatus::kNoPath: return "no path";
    case PlannerStatus::kBudgetExhausted: return "budget exhausted";
    case PlannerStatus::kTimeout: return "timeout";
    case PlannerStatus::kCancelled: return "cancelled";
    case PlannerStatus::kInvalidParameters: return "invalid parameters";
  }
  return "unknown";
}

}  // namespace skyroute
