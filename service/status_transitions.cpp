#include "service/status_transitions.hpp"

namespace skyroute {

bool StatusTransitions::firstTime(const PlanStatusData& status) {
  // Replans, holds and new orders come again and again in one mission: each is news.
  if (status.state == PlanState::kReplanned || status.state == PlanState::kHolding ||
      status.state == PlanState::kReordered) {
    return true;
  }
  return seen_.emplace(status.vehicle_id, status.request_id, status.state).second;
}

}  // namespace skyroute
