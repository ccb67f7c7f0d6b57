// Douglas-Peucker simplification of a 3D polyline that never drops chosen vertices (e.g. mission
// points). Guarantee: every dropped vertex lies within tolerance_m of the segment that replaces it,
// and every point of that segment lies within tolerance_m of the original polyline (both ways, so
// a vehicle flying the straight segments stays in a corridor of that half-width around the route).
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"

namespace skyroute {

// Indices of the kept vertices, ascending; always the first, the last and every index in keep.
// Errors (kInvalidArgument): tolerance not positive and finite, a non-finite vertex, a keep index
// out of range.
Result<std::vector<std::size_t>> simplifyPolyline(const std::vector<Eigen::Vector3d>& points, double tolerance_m,
                                                  const std::vector<std::size_t>& keep = {});

// Distance from p to the segment a-b (to a when the segment is degenerate).
double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace skyroute
