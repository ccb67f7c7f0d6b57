// A mission request spoiled in one way, and the failed status it must get back: the table rows of
// the tests that send bad requests to the engine or to the daemon.
#pragma once

#include <functional>
#include <string>

#include "service/mission_types.hpp"

namespace skyroute::testing {

struct SpoiledRequest {
  std::string name;
  std::function<void(MissionRequestData&)> spoil;
  PlanErrorCode code;
  std::string field;  // the status's field starts with this
};

}  // namespace skyroute::testing
