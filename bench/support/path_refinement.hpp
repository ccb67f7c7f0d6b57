// Continuous refinement of a valid path after LOSPO: an extra stage, not part of seed 003's LOSPO.
// Only the RRT* benchmark uses it (the counterpart of OMPL's path simplifier there), so it lives
// in bench/support.
//
// LOSPO (seed 003 section 2-3) only connects vertices it inserted on the path, so its corners can
// only slide along those vertices (100-170 m apart on a 10 km leg in real-time use) and it never
// moves a corner off the path. This stage moves and adds vertices anywhere, in small checked steps
// that each shorten the path, so the path tightens towards the taut path of its route family:
// - collapse: drop a vertex when its two neighbours see each other;
// - relax: move a vertex towards the closest point of the segment joining its neighbours (the
//   path length |a - v| + |v - b| is convex in v, so any step towards that segment shortens it);
//   when that is blocked, slide it along one of its own segments, or along the horizontal or the
//   vertical part of the steepest descent (how a corner moves along an edge or a ridge);
// - cut corners: replace a vertex v by one point on each of its segments, p on a -> v and q on
//   v -> b, when p -> q is a valid motion (the triangle inequality makes it shorter);
// - partial shortcuts (seeded): join two points inside different segments when they see each other.
// Each move is a line search that halves its step from the largest sensible one down to
// min_step_m. A vertex whose moves all failed is left alone until a neighbour changes, and its
// corner cut resumes from the last depth tried, so a converged path costs almost nothing.
//
// Each accepted change is checked by the validator before it replaces anything, and is strictly
// shorter: the path never becomes longer and never invalid. Every segment of the result that is not
// an input segment is verified once more at the end; on any doubt the input comes back unchanged. Deterministic: the same input, options and seed
// give the same path (the clock only decides when to stop).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "planning/core/motion_validator.hpp"
#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"

namespace skyroute {

struct PathRefinementOptions {
  int max_rounds = 40;              // a round tries every vertex once (and the shortcuts)
  double min_round_gain_m = 1e-3;   // stop when a round shortens the path by less
  double min_step_m = 0.05;         // smallest move or cut tried; a vertex below it is converged
  int max_vertices = 200;           // corner cutting and shortcuts add no vertices beyond this
  // Corner cuts and shortcuts make no segment shorter than this (0 = only min_step_m applies): a
  // trajectory stage that fits splines through the vertices may want them some metres apart.
  double min_segment_m = 0.0;
  int shortcut_attempts = 8;        // seeded partial shortcuts per round (0 = none)
  std::uint64_t seed = 1;
  bool collapse = true;
  bool relax = true;
  bool cut_corners = true;
  // Check every input segment first (an invalid one is an error). A caller that has just verified
  // the path (LOSPO's result is) may skip it to save a whole-path check inside its budget.
  bool check_input = true;
};

struct PathRefinementResult {
  std::vector<Eigen::Vector3d> path_m;  // same start and goal as the input
  double input_length_m = 0.0;
  double length_m = 0.0;
  int rounds = 0;
  std::uint64_t motion_checks = 0;
  int collapsed = 0, relaxed = 0, cut = 0, shortcuts = 0;  // accepted changes of each kind
  bool stopped_early = false;  // the termination condition fired; path_m is still valid
  double time_s = 0.0;
};

// Errors (kInvalidArgument, naming the field): fewer than two points or non-finite points, an
// input segment that is not a valid motion ("path", when check_input), options out of range.
Result<PathRefinementResult> refinePath(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path_m,
                                        const PathRefinementOptions& options = {},
                                        const TerminationCondition& stop = {});

}  // namespace skyroute
