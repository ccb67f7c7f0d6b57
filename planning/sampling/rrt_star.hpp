// RRT* in 3D (Karaman and Frazzoli 2011; seed 003 section 2-2) over a MotionValidator: the
// planner samples in the validator's bounds (the flyable volume), steers at most max_step_m toward
// the sample, picks the cheapest valid parent among the neighbours within the rewiring radius
// (ChooseBestParent) and reconnects those neighbours through the new node when that shortens them
// (Rewire). Once a path exists it samples only where a shorter path can pass (the informed set:
// the prolate spheroid with foci start and goal, Gammell et al. 2014) and keeps improving until
// the termination condition stops it.
//
// Reproducible: every random draw comes from one generator seeded by options.seed and nothing
// depends on the clock except when to stop, so with an iteration budget (and no deadline) the same
// seed gives a bit-identical tree and path.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "planning/core/motion_validator.hpp"
#include "planning/core/planner_status.hpp"
#include "planning/core/polyline.hpp"
#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/sampling/rrt_tree.hpp"

namespace skyroute {

struct RrtStarOptions {
  std::uint64_t seed = 1;
  double goal_bias = 0.05;       // probability of sampling the goal itself, in [0, 1)
  double max_step_m = 0.0;       // steering range; 0 = 20% of the sampling box's diagonal
  double rewire_factor = 1.1;    // multiple (> 1) of Karaman and Frazzoli's lowest gamma
  bool informed_sampling = true; // once a path exists, sample only in its informed set
  std::uint64_t max_nodes = 0;   // node budget (tree size); 0 = unlimited
  bool allow_approximate = false;
  // Try the straight start -> goal motion first: when it is valid it is the optimum, return it.
  bool try_direct_first = true;
  // Near set for ChooseBestParent and Rewire: false = the nodes within Karaman and Frazzoli's
  // rewiring radius (capped at the steering range), true = the k nearest nodes with
  // k = ceil(rewire_factor * e * (1 + 1/d) * log(n)) (k-nearest RRT*, OMPL's default).
  bool k_nearest = false;
  // Once a path exists, drop from the nearest-neighbour index every node outside the informed set
  // of the best path (no path through such a node can be shorter; OMPL's InformedRRTstar prunes
  // likewise), so new nodes steer from, connect to and rewire only nodes that can still improve
  // the solution. The nodes stay in the tree (their subtrees keep valid parents). Only with
  // informed_sampling.
  bool prune_tree = false;
  // Once a path exists, skip the motion checks that cannot lead to a shorter one: rewiring a
  // neighbour whose cost through the new node plus its straight line to the goal is no shorter
  // than the best path (no path through it or its subtree can be), and connecting a new node to
  // the goal when that path would not be shorter. Fewer checks per iteration; off by default so
  // existing callers (the route planner, the replanner) keep their trees exactly.
  bool skip_hopeless_checks = false;
  // A coarse way from start to goal (for example round a ridge through a pass, found on the
  // terrain's flyable regions), for a search over a region where uniform samples find such a way
  // late. Until the first path, each sample is, with probability guide_bias, drawn near a random
  // point of guide_m: within guide_radius_m of it east and north, between its height and the top
  // of the sampling box. After the first path only the informed set is sampled (the guide does not
  // bias the optimum). No guide (empty, or a bias of 0) leaves every draw as without this option.
  std::vector<Eigen::Vector3d> guide_m = {};
  double guide_bias = 0.0;       // in [0, 1)
  double guide_radius_m = 0.0;
};

struct RrtStarResult {
  PlannerStatus status = PlannerStatus::kBudgetExhausted;
  std::vector<Eigen::Vector3d> path_m;  // start .. goal (or the approximate end); empty without a path
  double length_m = 0.0;                // polyline length of path_m
  double distance_to_goal_m = 0.0;      // 0 for exact solutions
  std::size_t tree_size = 0;            // nodes in the tree, start included
  std::size_t seeded_nodes = 0;         // of them, taken over from a seed tree (planFromTree), root included
  std::uint64_t iterations = 0;         // samples drawn
  std::uint64_t motion_checks = 0;      // isMotionValid calls
  std::uint64_t solution_improvements = 0;
  double first_solution_s = -1.0;       // time to the first exact path, -1 when none
  std::uint64_t first_solution_iteration = 0;
  double time_s = 0.0;
  TerminationCondition::Reason stop_reason = TerminationCondition::Reason::kNone;
  bool node_budget_reached = false;

  bool solved() const { return status == PlannerStatus::kSolved; }
};

class RrtStar {
 public:
  // The validator must outlive the planner; it is only read.
  explicit RrtStar(const MotionValidator& validator, RrtStarOptions options = {});

  // Errors (kInvalidArgument, naming the field): non-finite start or goal, an empty or
  // non-finite sampling box, options out of range. Planning outcomes are statuses in the result.
  Result<RrtStarResult> plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                             const TerminationCondition& stop) const;
  // Stops at whichever of the two conditions fires first (for example a per-leg budget and the
  // caller's deadline or cancel flag); stop_reason is the first one's reason when both fire.
  Result<RrtStarResult> plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                             const TerminationCondition& stop, const TerminationCondition& outer) const;

  // As above, and the tree grown is stored in *tree_out (as data, for a later planFromTree).
  Result<RrtStarResult> plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                             const TerminationCondition& stop, const TerminationCondition& outer,
                             RrtTree* tree_out) const;
  // Grows `seed` instead of a tree with the start alone: its root (node 0) is the start, and its
  // nodes and edges are taken as they are (the caller vouches that they are valid against this
  // validator and that the costs are the path lengths from the root: rerootTree() makes such a
  // tree). The nodes near the goal are tried for a goal connection before the first sample, so
  // a seed that already reaches the goal's neighbourhood gives a path with no new sample; the
  // search then goes on until `stop` (iterations count new samples only). Errors as plan(), and
  // kInvalidArgument ("seed_tree") for an empty seed or one that breaks RrtTree's layout.
  Result<RrtStarResult> planFromTree(const RrtTree& seed, const Eigen::Vector3d& goal_m,
                                     const TerminationCondition& stop, const TerminationCondition& outer,
                                     RrtTree* tree_out = nullptr) const;

  const RrtStarOptions& options() const { return options_; }

 private:
  Result<RrtStarResult> plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                             const TerminationCondition& stop, const TerminationCondition* outer,
                             const RrtTree* seed = nullptr, RrtTree* tree_out = nullptr) const;

  const MotionValidator& validator_;
  RrtStarOptions options_;
};

// Karaman and Frazzoli's rewiring radius for n nodes in a d-dimensional space of free volume
// free_volume: rewire_factor * 2 (1 + 1/d)^(1/d) (free_volume / unit_ball_volume)^(1/d) (log n / n)^(1/d).
double rrtStarRewireRadius(std::size_t n, int dimension, double free_volume, double rewire_factor);

}  // namespace skyroute
