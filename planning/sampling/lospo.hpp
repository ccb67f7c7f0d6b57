// LOSPO, line-of-sight path optimisation (seed 003 section 2-3, after Woo et al. 2021): vertices
// are inserted along the path at a fixed spacing; from the current vertex the planner looks for the
// farthest vertex it can see, testing from the goal backwards, connects the two by a straight
// segment, re-inserts vertices along that segment at the same spacing and moves on to the next
// vertex; it stops when the current vertex sees the goal.
//
// Every new segment is a checked valid motion and replaces a piece of path between the same two
// points, so by the triangle inequality the path never gets longer and never becomes invalid
// (both are also verified at the end: on any doubt the input comes back unchanged). Corners slide
// along the re-inserted vertices, so the result approaches the taut path in the input's route
// family; more passes (max_passes) bring it closer.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "planning/core/motion_validator.hpp"
#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"

namespace skyroute {

struct LospoOptions {
  double spacing_m = 50.0;   // distance between inserted vertices
  // Each step tests up to every vertex ahead, so a pass costs O(n^2) motion checks for n vertices.
  // For real-time use the spacing is raised to length / max_vertices when the path is longer than
  // max_vertices * spacing_m (0 = never).
  int max_vertices = 0;
  int max_passes = 1;        // the seed's algorithm is one pass; further passes restart on the result
  double min_pass_gain_m = 1e-3;  // stop repeating when a pass shortens the path by less
  bool merge_collinear = true;    // drop vertices where the path goes straight on (checked again)
  // Before each visibility test, check the points at 1/2, 1/4 and 3/4 of the way (isStateValid):
  // one invalid proves the motion invalid. Same result as without, fewer motion checks.
  bool point_prefilter = true;
};

struct LospoResult {
  std::vector<Eigen::Vector3d> path_m;  // same start and goal as the input
  double input_length_m = 0.0;
  double length_m = 0.0;
  int passes = 0;
  std::uint64_t motion_checks = 0;
  std::uint64_t point_checks = 0;  // cheap rejections tried before a motion check (isStateValid calls)
  bool stopped_early = false;  // the termination condition fired; path_m is still valid
  double time_s = 0.0;
};

// Errors (kInvalidArgument): a path of fewer than two points or with non-finite points, a spacing
// that is not finite and positive (or would insert more than 10^6 vertices), max_passes < 1, or an
// input segment that is not a valid motion (field "path", naming the segment).
Result<LospoResult> lospo(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path_m,
                          const LospoOptions& options = {}, const TerminationCondition& stop = {});

// The input checks every path post-processing stage makes (LOSPO, refinePath): at least two
// points, all finite (kInvalidArgument, field "path", naming the point).
Status checkPathPoints(const std::vector<Eigen::Vector3d>& path_m);

// The path with extra vertices on every segment so no two consecutive ones are farther apart than
// spacing_m (equal pieces per segment); the original vertices are kept.
std::vector<Eigen::Vector3d> densifyPath(const std::vector<Eigen::Vector3d>& path_m, double spacing_m);

}  // namespace skyroute
