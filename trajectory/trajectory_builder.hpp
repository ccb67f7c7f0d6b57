// Waypoints + vehicle limits + options -> trajectory + report. The steps (seed 003 section 3-1):
// extra waypoints at the LOSPO spacing, time allocation, minimum-snap degree-7 spline, then
// feasibility (limits and, with a motion check, terrain and obstacles) and repair: corners the
// curve turns through tighter than the vehicle's min turn radius are rounded geometrically
// (corner_rounding.hpp: a fillet arc, or at a fixed waypoint a straight pass along the turn's
// bisector between two fillets), each checked clear with the motion check before it is adopted;
// segments whose curve collides are split at the middle of their straight chord (pulling the
// curve onto the checked path); segments over a limit are stretched in time, first locally, then
// the whole trajectory uniformly (which scales speeds by 1/k and accelerations by 1/k^2 exactly
// for a rest-to-rest spline). Then it checks again; the report says what was repaired or why not.
// At the interior fixed waypoints (mission points) the vehicle passes, or comes to rest
// (knot_stops.hpp): in the pass mode a fixed corner whose pass-through does not fit or collides
// becomes a stop, and when the repairs end with a violation the fixed waypoint nearest it becomes
// a stop and the trajectory is built again, then every fixed waypoint, and (when asked) as the
// last resort every corner of the path (straight rest-to-rest pieces on the checked path, which
// always fly). The report lists the stops and why.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "trajectory/corner_rounding.hpp"
#include "trajectory/feasibility.hpp"
#include "trajectory/knot_stops.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/time_allocation.hpp"
#include "trajectory/trajectory.hpp"
#include "trajectory/vehicle_limits.hpp"

namespace skyroute {

struct TrajectoryOptions {
  // Extra waypoints between the original ones at this spacing (m), the LOSPO vertex spacing;
  // 0 = none (the curve may then stray from the checked straight path).
  double waypoint_spacing_m = 100.0;
  TimeAllocationOptions time_allocation;  // its start/end speeds are taken from `boundary`
  SplineBoundary boundary;                // rest to rest by default
  FeasibilityOptions feasibility;
  bool repair = true;
  int max_repair_rounds = 12;
  double min_waypoint_separation_m = 1e-3;  // consecutive input waypoints closer than this: error
  double min_split_length_m = 0.5;          // never split a segment whose chord is shorter
  // Indices into the input waypoints the trajectory must pass exactly, e.g. the mission points
  // where legs join (the first and last always are). A fixed corner is never cut: a turn-radius
  // repair there flies straight through it along the turn's bisector. Any order, duplicates ok.
  std::vector<std::size_t> fixed_waypoints;
  // Turn-radius repair by rounding the corners the curve turns through too tightly; off = a turn
  // violation is reported as unrepairable.
  bool round_corners = true;
  CornerRoundingOptions corner_rounding;
  // What the trajectory does at the interior fixed waypoints: pass (and stop only where passing
  // cannot be made to fly) or stop at every one.
  FixedWaypointMode fixed_waypoint_mode = FixedWaypointMode::kPass;
  // When nothing else flies, rest at every corner of the path too: each piece between two
  // waypoints is then a straight rest-to-rest line on the checked path, clear wherever the path
  // is and slowed into every limit by the uniform stretch (the route stage asks for it: a route
  // whose legs are clear always gets a trajectory). Off, the failure is reported.
  bool stop_at_corners_as_last_resort = false;
};

// An interior waypoint where the trajectory comes to rest (zero velocity, acceleration and jerk),
// and why: a fixed one, or (the last resort) a corner of the path.
struct WaypointStop {
  std::size_t waypoint = 0;  // index into the input waypoints
  std::string reason;        // the stop mode, or why the trajectory could not be made to fly without it
};

enum class TrajectoryStatus {
  kFeasible,    // passed every check as built
  kRepaired,    // passed after repairs (listed in the report)
  kInfeasible,  // still violates something; failure_reason says what and why it could not be fixed
};
std::string_view to_string(TrajectoryStatus status);

struct TrajectoryBuildReport {
  TrajectoryStatus status = TrajectoryStatus::kInfeasible;
  std::vector<std::string> repairs;  // one line per repair action
  std::string failure_reason;        // empty unless kInfeasible
  FeasibilityReport final_check;     // of the returned trajectory
  std::size_t input_waypoints = 0;
  std::size_t knots = 0;             // waypoints of the final spline (input + extra + repair)
  std::size_t corners_rounded = 0;   // input corners replaced by a fillet or a pass-through
  int repair_rounds = 0;
  double build_ms = 0.0;
  std::vector<WaypointStop> stops;   // by input index
  // kInfeasible: the violation the repairs could not fix (the one failure_reason is about), and
  // the fixed waypoint (input index, the ends included) nearest it in time, so a caller can name
  // the mission point where the trajectory cannot be flown and the limit.
  std::optional<Violation> failure_violation;
  std::optional<std::size_t> failure_waypoint;
};

struct BuiltTrajectory {
  Trajectory trajectory;
  std::vector<Eigen::Vector3d> knots;  // the spline's waypoints, knots[j] at trajectory.knotTimes()[j]
  TrajectoryBuildReport report;
};

// Errors (bad input only, naming the field): "waypoints", "waypoints[i]", "limits.*",
// "options.*" (e.g. "options.fixed_waypoints" for an index out of range), "boundary.*". An
// infeasible trajectory is not an error: it comes back with status kInfeasible so the caller can
// decide (replan, relax limits). kCancelled ("trajectory") when options.feasibility.stop_requested
// stopped a check.
// collision: optional motion check (times are trajectory times from 0).
Result<BuiltTrajectory> buildTrajectory(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TrajectoryOptions& options = {}, const MotionCheck* collision = nullptr);

}  // namespace skyroute
