// The identity the DDS tests give a made-up trajectory: plan-<vehicle>, req-<vehicle>.
#pragma once

#include <cstdint>
#include <string>

#include "service/mission_types.hpp"

namespace skyroute::testing {

inline TrajectoryData namedTrajectory(const std::string& vehicle, std::uint32_t revision) {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = "plan-" + vehicle;
  t.revision = revision;
  t.request_id = "req-" + vehicle;
  return t;
}

}  // namespace skyroute::testing
