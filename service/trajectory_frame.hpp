// The local frame a trajectory's ENU samples are in, recovered from the samples themselves. The
// daemon's frame (terrain/local_frame.hpp: azimuthal equidistant on WGS84 round an anchor, up =
// altitude AMSL minus the anchor's) is not on the wire, but every sample carries its position both
// in ENU and in WGS84, and one sample fixes the anchor: a tool that must convert interpolated ENU
// states exactly (`skyroute px4`) finds the anchor whose frame maps that sample's WGS84 position
// onto its ENU one, then checks every other sample against it.
#pragma once

#include "service/mission_types.hpp"
#include "terrain/local_frame.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

// Errors: kInvalidArgument (field "samples") when there are no samples, or when the samples do not
// fit one such frame within tolerance_m (naming the worst sample and its residual).
Result<LocalFrame> recoverTrajectoryFrame(const TrajectoryData& trajectory, double tolerance_m = 1e-3);

}  // namespace skyroute
