// RRT* tree reuse on replanning (seed 003 section 3-2: when an obstacle invades the path, RRT*
// adds vertices to its tree and a new path is made from it). The tree of the leg being flown is
// kept; a replan starts from the takeover point, not from the old root, so the tree is re-rooted
// there: the takeover point joins its nearest old nodes by valid motions, and every old node it
// still reaches through valid old edges is kept with the shortest such path as its new branch.
// An edge that now crosses an obstacle (a new one, or one grown by the replan's margins) is never
// used, so the part of the tree behind it is kept only when the takeover point reaches it some
// other way. The planner then grows the kept tree (RrtStar::planFromTree) instead of a new one.
//
// Bounded work: every kept node costs one motion check (its edge), the root links at most
// root_links + root_link_tries; the walk goes out from the new root cheapest-first (Dijkstra), so
// when the node cap or the stop condition ends it, what is kept is the part nearest the root by
// path length, still a tree with true costs.
#pragma once

#include <cstdint>

#include "planning/core/motion_validator.hpp"
#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "planning/sampling/rrt_tree.hpp"

namespace skyroute {

struct TreeReuseOptions {
  std::size_t max_nodes = 2000;     // nodes kept at most, the new root included (> 0)
  std::size_t root_links = 8;       // the new root joins this many of its nearest old nodes ...
  std::size_t root_link_tries = 24; // ... trying at most this many more when motions are blocked
};

struct RerootedTree {
  RrtTree tree;                     // rooted at the new root; the root alone when nothing is kept
  std::size_t kept_nodes = 0;       // old nodes kept
  std::size_t dropped_nodes = 0;    // old nodes not kept (unreached, blocked, outside the bounds or the cap)
  std::size_t blocked_edges = 0;    // old edges found invalid
  std::size_t root_links = 0;       // valid motions from the new root to old nodes
  std::uint64_t motion_checks = 0;
  bool stopped = false;             // the stop condition ended the walk early
};

// Errors (kInvalidArgument naming the field): old_tree breaks RrtTree's layout ("old_tree"), a
// new root that is not finite ("new_root_m"), max_nodes of 0 ("max_nodes"). A new root the
// validator rejects keeps nothing (the planner reports the invalid start itself).
Result<RerootedTree> rerootTree(const RrtTree& old_tree, const Eigen::Vector3d& new_root_m,
                               const MotionValidator& validator, const TreeReuseOptions& options = {},
                               const TerminationCondition& stop = {});

// The max_nodes cheapest nodes of a tree (all of it when it has no more), still a tree: a parent
// costs no more than its children, so it is kept whenever they are. For a bounded tree to keep.
// A tree that breaks RrtTree's layout gives an empty tree.
RrtTree cheapestPart(const RrtTree& tree, std::size_t max_nodes);

}  // namespace skyroute
