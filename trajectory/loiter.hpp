// A loiter: what a fixed wing flies while it waits, since it cannot stop. A level circle flown
// at a constant speed, entered from any flown state (position to jerk) by one degree-7 segment,
// then a chain of degree-7 arcs whose ends are the circle's own states (position to jerk), so the
// whole is continuous to the jerk and repeats exactly turn after turn. Each arc spans an eighth
// of a turn by default: the degree-7 Hermite interpolant of a circle that short strays from it by
// far less than a millimetre, so its speed and bank are the circle's within a fraction of a percent.
// Geometry and limits only: whether the circle is clear of the world is the caller's check.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "trajectory/segment.hpp"
#include "trajectory/spline7.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

struct LoiterCircle {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  // ENU, at the circle's height
  double radius_m = 0.0;
  double speed_mps = 0.0;
  bool turning_left = true;  // counter-clockwise seen from above
  int arcs_per_turn = 8;

  double turnS() const;            // the time of one turn
  double arcAngleRad() const;      // signed angle of one arc (positive turning left)
  // The uniform circular motion's position to jerk at the angle theta_rad (from east, counter-clockwise).
  Eigen::Vector3d positionAt(double theta_rad) const;
  KnotDerivatives derivativesAt(double theta_rad) const;
};

// `arcs` consecutive arcs of the circle, the first starting at angle from_rad.
std::vector<Segment> loiterArcs(const LoiterCircle& circle, double from_rad, std::size_t arcs);

// How the loiter is laid out from the entry state: the side it turns to, its radius and speed,
// and the entry: the circle touches the line of the entry velocity lead_m ahead of the entry
// point, and the entry segment joins it join_turn_rad of a turn further on (room to ease the bank
// in). The join is level: a climb or descent at the entry is eased out over the entry segment.
struct LoiterShape {
  bool turning_left = true;
  double radius_m = 0.0;
  double speed_mps = 0.0;
  double join_turn_rad = 1.5707963267948966;
  double lead_m = 0.0;
  int arcs_per_turn = 8;
};

struct LoiterPath {
  LoiterCircle circle;
  std::vector<Segment> segments;  // the entry segment, then the arcs
  double join_angle_rad = 0.0;    // where the entry joins the circle
  double end_angle_rad = 0.0;     // where the last arc ends (the next arc would start)
};

// The entry and enough whole arcs to fly the circle for at least circle_s after the join.
// kInvalidArgument ("loiter.entry") when the entry has no horizontal velocity to turn from, and
// ("loiter.shape") for a radius or speed that is not positive and finite.
Result<LoiterPath> loiterFrom(const TrajectoryState& entry, const LoiterShape& shape, double circle_s);

}  // namespace skyroute
