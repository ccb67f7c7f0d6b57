#include "service/status_transitions.hpp"

namespace skyroute {

bool StatusTransitions::firstTime(const PlanStatusData& status) {
  if (status.state == PlanState::kReplanned) return true;
  return seen_.emplace(status.vehicle_id, status.request_id, status.state).second;
}

}  // namespace skyroute
