// Which plan statuses a viewer prints: each transition of a request once. The same transition can
// reach a ground station twice (a request answered by two daemons, or a status delivered again
// after rediscovery); a second "accepted", "planning" or "succeeded" of the same request says
// nothing new. A "replanned" status announces a new revision each time and is always new.
#pragma once

#include <set>
#include <string>
#include <tuple>

#include "service/mission_types.hpp"

namespace skyroute {

class StatusTransitions {
 public:
  // True the first time this (vehicle, request, state) is seen, and for every replanned status.
  bool firstTime(const PlanStatusData& status);

 private:
  std::set<std::tuple<std::string, std::string, PlanState>> seen_;
};

}  // namespace skyroute
