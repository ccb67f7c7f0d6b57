// The audit every trajectory revision passes before it is put in force and published (docs/dds.md,
// "Audit before publishing"): a check that is not the planner's. It samples the revision's
// polynomial every AuditOptions::step_s (and at its end) and, at each sample, checks from the raw
// data of the world, never through the planner's collision queries (CollisionWorld, FCL, the
// octree, NoFlyZone's own tests):
//   - the ground clearance: height above the DEM's bilinear height (Heightfield::heightAt) at
//     least the vehicle's minimum clearance, and the sample over the DEM;
//   - the ceiling;
//   - every no-fly zone in force at the sample's world time: the distance from the vehicle's
//     centre to the prism (its own point-in-polygon and edge distances) at least the vehicle radius;
//   - the known obstacles: fixed ones over the whole trajectory, moving ones where their motion
//     puts them at the sample's time, up to the end of the replanning horizon (beyond it the
//     replanning loop looks again); the distance to each shape (sphere, box, vertical cylinder,
//     ellipsoid) at least the vehicle radius;
//   - the vehicle's limits: speed, acceleration, climb and descent rates, and for a fixed wing the
//     minimum airspeed and the bank angle of the turn flown.
// Distances may fall short by tolerance_m and limits be exceeded by limit_tolerance (a share of
// the limit): the planner checks limits every 0.1 s per segment, so a peak between its samples is
// not a refusal. The first failing sample is reported, naming the check.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/no_fly_zone.hpp"
#include "terrain/obstacle.hpp"
#include "trajectory/trajectory.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

class Heightfield;
class CollisionWorld;

struct AuditOptions {
  double step_s = 0.05;            // audit.step_s: time between audited samples
  double tolerance_m = 0.1;        // audit.tolerance_m: clearance, ceiling, zone and obstacle distances
  double limit_tolerance = 0.02;   // audit.limit_tolerance: share by which a limit may be exceeded
};

// kInvalidArgument naming the key (audit.step_s, ...) when an option is unusable.
std::optional<Error> validateAuditOptions(const AuditOptions& options);

// What a trajectory is audited against: the world's data, copied (never its queries).
struct AuditWorld {
  std::shared_ptr<const Heightfield> terrain;  // the DEM's heights (not a dilated copy)
  double min_clearance_m = 0.0;
  double ceiling_m = 0.0;
  double vehicle_radius_m = 0.0;
  std::vector<NoFlyZone> zones;
  std::vector<Obstacle> obstacles;
  // Moving obstacles are checked at samples up to this world time (the replanning horizon's end).
  double moving_until_world_s = 0.0;
};

// The data of a collision world (its terrain, clearance, ceiling, radius, zones and obstacles),
// with moving obstacles checked up to moving_until_world_s.
AuditWorld auditWorldOf(const CollisionWorld& world, double moving_until_world_s);

enum class AuditCheck {
  kOutsideDem,
  kGroundClearance,
  kCeiling,
  kNoFlyZone,
  kObstacle,
  kSpeed,
  kAcceleration,
  kClimbRate,
  kDescentRate,
  kMinAirspeed,
  kBankAngle,
  kNotFinite,
};
std::string_view to_string(AuditCheck check);

struct AuditFinding {
  AuditCheck check = AuditCheck::kNotFinite;
  double t_s = 0.0;     // trajectory time of the first failing sample
  std::string reason;   // what failed, with the values: "ground_clearance: 12.3 m above the DEM at ..."
};

// The audit of `trajectory`, whose t = 0 is world time start_world_s; nothing when it passes.
std::optional<AuditFinding> auditTrajectory(const Trajectory& trajectory, double start_world_s, const AuditWorld& world,
                                            const VehicleLimits& limits, const AuditOptions& options = {});

// What the audits of one service did: the heartbeat's counts (every flight shares them).
struct AuditCounters {
  std::atomic<std::uint64_t> audits{0};
  std::atomic<std::uint64_t> failures{0};
};

}  // namespace skyroute
