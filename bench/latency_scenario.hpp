// The missions and crossing obstacles of the latency benchmarks (e2e_latency_bench through
// skyrouted over DDS, engine_replan_bench inside the engine), in one place so both measure the
// same thing: seed 003's vehicle (V_ref 50 m/s) on lanes across the terrain, and cylinders that
// sweep across a vehicle's route to meet it a given time ahead.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

#include "service/mission_types.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute::bench {

inline MissionPointData above(const Heightfield& terrain, double e, double n, double agl_m) {
  return MissionPointData::enu(Eigen::Vector3d(e, n, terrain.heightAt(e, n) + agl_m));
}

inline VehicleLimitsData seed003Vehicle() {
  VehicleLimitsData l;
  l.v_ref_mps = 50.0;
  l.max_speed_mps = 60.0;
  l.max_accel_mps2 = 10.0;
  l.max_climb_rate_mps = 15.0;
  l.max_descent_rate_mps = 15.0;
  return l;
}

// Vehicle `vehicle` of `vehicles` on lanes across the terrain's middle, 5% in from each side,
// through one mission point at the centre.
inline MissionRequestData laneMission(const Heightfield& terrain, const std::string& id, int vehicle, int vehicles) {
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  const double w = box.sizes().x(), h = box.sizes().y();
  const double north = box.min().y() + h * (0.1 + 0.8 * (vehicles == 1 ? 0.5 : double(vehicle) / (vehicles - 1)));
  MissionRequestData m;
  m.request_id = id;
  m.vehicle_id = "uav-" + std::to_string(vehicle);
  m.begin = above(terrain, box.min().x() + 0.05 * w, north, 300);
  m.points = {above(terrain, box.center().x(), north + 100, 300)};
  m.end = above(terrain, box.max().x() - 0.05 * w, north, 300);
  m.limits = seed003Vehicle();
  m.limits.ceiling_amsl_m = 12000.0;
  return m;
}

// Seed 003's start and goal (Table 1 scenario on the real DEM), through their midpoint.
inline MissionRequestData seed003Mission(const MovingObstacleScenario& scenario, const std::string& id) {
  MissionRequestData m;
  m.request_id = id;
  m.vehicle_id = "uav-0";
  m.begin = MissionPointData::enu(scenario.start_m);
  m.points = {MissionPointData::enu(0.5 * (scenario.start_m + scenario.goal_m))};
  m.end = MissionPointData::enu(scenario.goal_m);
  m.limits = seed003Vehicle();
  m.limits.min_clearance_agl_m = 50.0;
  return m;
}

// A cylinder that meets the vehicle flying `t` about meet_s after now_ns, crossing its route from
// 1 km aside.
inline ObstacleUpdateData crossing(const TrajectoryData& t, std::int64_t now_ns, std::uint64_t id, double meet_s) {
  const double now_rel_s = static_cast<double>(now_ns - t.samples.front().utc_ns) * 1e-9;
  std::size_t k = 0;
  while (k + 1 < t.samples.size() && t.samples[k].t_rel_s < now_rel_s + meet_s) ++k;
  const Eigen::Vector3d p = t.samples[k].position_enu_m;
  Eigen::Vector3d heading = t.samples[k].velocity_enu_mps;
  heading.z() = 0.0;
  heading = heading.norm() > 0 ? heading.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d across(-heading.y(), heading.x(), 0.0);
  ObstacleUpdateData u;
  u.obstacle.id = id;
  u.obstacle.shape = ObstacleShape::kCylinder;
  u.obstacle.size_m = Eigen::Vector3d(150.0, 0.0, 250.0);
  u.obstacle.center_m = p - 1000.0 * across;
  u.obstacle.motion = BackAndForth{p - 1000.0 * across, p + 1000.0 * across,
                                   1000.0 / std::max(1.0, t.samples[k].t_rel_s - now_rel_s), 0.0};
  u.valid_from_utc_ns = now_ns;
  return u;
}

}  // namespace skyroute::bench
