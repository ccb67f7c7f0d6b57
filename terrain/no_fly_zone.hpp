// No-fly zones: vertical prisms over a polygon in the ENU frame, between a floor and a ceiling on
// the up axis, optionally in force only during a time window on the world clock. The geometry
// answers two questions for the collision world: does the vehicle's sphere at a point touch the
// zone, and does the sphere swept along a segment touch it. Both grow the prism by the sphere's
// radius (horizontally round the polygon, and below the floor and above the ceiling), which is
// the exact Minkowski sum except at the top and bottom rims, where it is a little larger: never
// smaller, so a path judged clear is clear.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "planning/core/result.hpp"

namespace skyroute {

// What a zone's ring may be (docs/nofly.md). The vertex bound keeps every check of a zone (and
// every collision test against it, linear in its vertices) bounded; it is checked before any
// other work on the ring. A zone's area must be at least kMinNoFlyZoneAreaM2, and its mean width
// (2 area / perimeter) at least kMinNoFlyZoneMeanWidthM: vertices on one line in latitude and
// longitude keep a few square metres of area in the local frame (the projection bends the line),
// so the width tells a sliver from a zone.
inline constexpr std::size_t kMaxNoFlyZoneVertices = 10000;
// The zones published to a daemon (DDS) are copied into each of its worlds on every change: their
// vertices together are bounded as well.
inline constexpr std::size_t kMaxPublishedNoFlyVertices = 100000;
inline constexpr double kMinNoFlyZoneAreaM2 = 1.0;
inline constexpr double kMinNoFlyZoneMeanWidthM = 0.5;

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
  // The same for any axis-aligned rectangle (e.g. a terrain's bounds).
  bool touchesRectangle(const Eigen::AlignedBox2d& box_m, double margin_m = 0.0) const;
};

// Checks a zone's ring, in O(n log n): kInvalidArgument with field "ring" and a message saying
// what is wrong: more than kMaxNoFlyZoneVertices vertices (checked first, before anything else),
// fewer than 3, a coordinate that is not finite (NaN) or not on Earth, a repeated vertex, edges
// that fold back, cross or touch (self-intersection, ring_simplicity.hpp), or (nearly) zero area.
std::optional<Error> checkNoFlyRing(const std::vector<Eigen::Vector2d>& ring_m);

// Checks a zone: its ring (checkNoFlyRing), then its heights and window. kInvalidArgument with
// field = the zone's name and a message saying what is wrong: the ring's faults, a floor or
// ceiling that is not finite (NaN), the floor above the ceiling, or a window that ends before it
// starts.
std::optional<Error> checkNoFlyZone(const NoFlyZone& zone);

// When-aware questions over a set of zones. t_s: the world time (nothing: every zone counts, as
// for a timeless planner); window_s > 0 with a time: zones in force at any time of [t, t + window].
const NoFlyZone* zoneTouchingPoint(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& p_m, double margin_m,
                                   std::optional<double> t_s = std::nullopt, double window_s = 0.0);
const NoFlyZone* zoneTouchingSegment(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& a_m,
                                     const Eigen::Vector3d& b_m, double margin_m,
                                     std::optional<double> t_s = std::nullopt, double window_s = 0.0);

}  // namespace skyroute
