// What the web map tests share: a map state over the embedded terrain, and trajectories along
// ENU points with their WGS84 positions filled in as the daemon fills them.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "service/gcs_map_state.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"

namespace skyroute::testing {

// The embedded terrain's map state (null, with a test failure, if the terrain does not load).
inline std::shared_ptr<GcsMapState> embeddedTerrainMapState() {
  auto terrain = defaultTerrainHeightfield();
  if (!terrain) {
    ADD_FAILURE() << "data/default_terrain.tif did not load";
    return nullptr;
  }
  auto image = hillshadePngWgs84(terrain->dem());
  if (!image) {
    ADD_FAILURE() << image.error().describe();
    return nullptr;
  }
  return std::make_shared<GcsMapState>(terrain, std::move(*image), "default_terrain.tif");
}

// One sample a second along straight lines through points_m (ENU), starting at start_utc_ns.
inline TrajectoryData trajectoryThrough(const LocalFrame& frame, const std::string& vehicle, std::uint32_t revision,
                                       const std::vector<Eigen::Vector3d>& points_m, std::int64_t start_utc_ns,
                                       int samples_per_leg = 10) {
  TrajectoryData t;
  t.vehicle_id = vehicle;
  t.plan_id = vehicle + "-plan";
  t.revision = revision;
  t.request_id = vehicle + "-request";
  t.created_utc_ns = start_utc_ns;
  for (std::size_t leg = 0; leg + 1 < points_m.size(); ++leg) {
    for (int k = 0; k < samples_per_leg; ++k) {
      if (k == 0 && leg > 0) continue;  // the leg's first sample is the previous leg's last
      TrajectorySampleData s;
      s.t_rel_s = static_cast<double>(t.samples.size());
      s.utc_ns = start_utc_ns + static_cast<std::int64_t>(s.t_rel_s * 1e9);
      s.position_enu_m = points_m[leg] + (points_m[leg + 1] - points_m[leg]) * (k / double(samples_per_leg - 1));
      s.geo = frame.toGeo(s.position_enu_m);
      t.samples.push_back(s);
    }
  }
  return t;
}

}  // namespace skyroute::testing
