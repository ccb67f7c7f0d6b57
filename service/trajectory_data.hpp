// Turns a planned trajectory into the service's TrajectoryData: samples every dt with relative and
// absolute UTC time, ENU state, heading and WGS84 position.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "service/mission_types.hpp"
#include "terrain/local_frame.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

struct TrajectoryIdentity {
  std::string vehicle_id;
  std::string plan_id;
  std::uint32_t revision = 0;
  std::string request_id;
};

// Samples toTrajectoryData makes of a trajectory this long (at most; the last is the end).
std::size_t sampleCount(double duration_s, double dt_s);

TrajectoryData toTrajectoryData(const Trajectory& trajectory, const LocalFrame& frame, double dt_s,
                                std::int64_t start_utc_ns, const TrajectoryIdentity& identity);

}  // namespace skyroute
