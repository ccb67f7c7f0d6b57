// One vehicle of a fleet mission in 3D: its grid plan (cells and task steps from GMTPA) becomes a
// route at the cruise altitude, climbing over its begin and descending onto its end, and the
// trajectory stage turns that route into the trajectory it flies.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/fleet/fleet_paths.hpp"
#include "service/fleet_mission.hpp"
#include "service/mission_types.hpp"
#include "service/route_planner.hpp"
#include "terrain/collision_world.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// "name[i]": how a fleet request's list items are named in errors.
inline std::string indexedField(const char* name, std::size_t i) {
  return std::string(name) + "[" + std::to_string(i) + "]";
}

// What every vehicle's route shares.
struct FleetRouteContext {
  const FleetRequestData& request;
  const GridLayer& grid;                         // the flight band's grid
  std::shared_ptr<const CollisionWorld> world;
  double cruise_m = 0.0;                         // the flight band's altitude (ENU up)
  VehicleLimits limits;
  const FleetMissionOptions& options;
};

// Vehicle i's trajectory, appended to out.flown, out.trajectories (visiting order and legs; the
// samples come after the separation repair) and out.status.allocation.
std::optional<PlanError> addFleetVehicleRoute(const FleetRouteContext& context, std::size_t i, const VehiclePlan& plan,
                                              FleetPlanOutput& out);

}  // namespace skyroute
