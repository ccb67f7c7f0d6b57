// The length of a polyline, written once for every kind of point the planners use: ENU metres in
// 3D (the sampling planners, LOSPO) and grid cell centres (the any-angle searches, HAB-PP). A point
// type takes part by a segmentLength(a, b) next to its own definition, found by argument-dependent
// lookup (GridCell's is in terrain/grid_layer.hpp); Eigen's 3D vectors have theirs here.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace skyroute {

// Euclidean distance from a to b, in the points' unit (metres for ENU points).
inline double segmentLength(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (b - a).norm(); }

// Sum of the segments' lengths, first to last (0 for fewer than two points).
template <class Point>
double polylineLength(const std::vector<Point>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += segmentLength(path[i - 1], path[i]);
  return length;
}

}  // namespace skyroute
