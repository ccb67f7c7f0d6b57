// No-fly zones: vertical prisms over a polygon in the ENU frame, between a floor and a ceiling on
// the up axis, optionally in force only during a time window on the world clock. The geometry
// answers two questions for the collision world: does the vehicle's sphere at a point touch the
// zone, and does the sphere swept along a segment touch it. Both grow the prism by the sphere's
// radius (horizontally round the polygon, and below the floor and above the ceiling), which is
// the exact Minkowski sum except at the top and bottom rims, where it is a little larger: never
// smaller, so a path judged clear is clear.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planning/core/result.hpp"

namespace skyroute {

struct NoFlyZone {
  std::string name;                      // what the user calls it (a GeoJSON feature's id or index)
  std::vector<Eigen::Vector2d> ring_m;   // east, north; open (the last vertex is not the first again)
  double floor_m = 0.0;                  // up axis of the frame (altitude AMSL with the default anchor)
  double ceiling_m = 0.0;
  std::optional<double> valid_from_s;    // world clock (UTC seconds); in force in [from, until)
  std::optional<double> valid_until_s;

  bool activeAt(double t_s) const;
  // In force at some time of [t0_s, t1_s].
  bool activeDuring(double t0_s, double t1_s) const;
  Eigen::AlignedBox2d boundsEn() const;
  // The sphere of radius margin_m at p touches the zone (ignores the time window).
  bool touchesPoint(const Eigen::Vector3d& p_m, double margin_m = 0.0) const;
  // The sphere of radius margin_m swept along a -> b touches the zone (ignores the time window).
  bool touchesSegment(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, double margin_m = 0.0) const;
  // The horizontal polygon, grown by margin_m, meets the axis-aligned square of the given centre
  // and edge (for grids).
  bool touchesSquare(const Eigen::Vector2d& center_m, double edge_m, double margin_m = 0.0) const;
};

// Checks a zone's geometry. kInvalidArgument with field = the zone's name and a message saying
// what is wrong: fewer than 3 vertices, a coordinate, floor or ceiling that is not finite (NaN), a
// repeated vertex or crossing edges (self-intersection), the floor above the ceiling, or a window
// that ends before it starts.
std::optional<Error> checkNoFlyZone(const NoFlyZone& zone);

// When-aware questions over a set of zones. t_s: the world time (nothing: every zone counts, as
// for a timeless planner); window_s > 0 with a time: zones in force at any time of [t, t + window].
const NoFlyZone* zoneTouchingPoint(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& p_m, double margin_m,
                                   std::optional<double> t_s = std::nullopt, double window_s = 0.0);
const NoFlyZone* zoneTouchingSegment(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& a_m,
                                     const Eigen::Vector3d& b_m, double margin_m,
                                     std::optional<double> t_s = std::nullopt, double window_s = 0.0);

}  // namespace skyroute
