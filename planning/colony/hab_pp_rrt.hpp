// The RRT* species of Improved HAB-PP (seed 004, section 4): an RRT* tree on integer grid
// coordinates that grows one node per RRT* ant step, picks the point to grow towards by roulette
// wheel on the shared pheromone field instead of uniform sampling, and hands every path it finds
// (and every later improvement of it) to the colony's ranked list, whose pheromone it samples in
// turn. Rooted at the start as in Table 3, or at the goal (HabPpParameters::rrt_tree_from_goal),
// where the ants can finish along its branches (nodeNear, branchToRoot). Extension length s_RRT and rewiring radius r_RRT are larger than a stand-alone
// RRT* would use, for fast rather than optimal paths (the ants optimise).
#pragma once

#include <optional>
#include <vector>

#include "planning/colony/hab_pp.hpp"

namespace skyroute::habpp {

class RrtAnt {
 public:
  // A tree rooted at `root` that looks for `target` (the start and the goal, or the other way round).
  RrtAnt(const GridLayer& grid, GridCell root, GridCell target, const HabPpParameters& params);

  // One RRT* iteration (Table 3, lines 5-32) with x_rand drawn from the pheromone field. Returns a
  // root-to-target path when the tree first reaches the target or lowers the target's cost.
  // Choice (steering): a blocked step is halved until free and visible, see hab_pp_rrt.cpp.
  // Option: a tree that has grown rrt_nodes_after_solution (> 0) nodes past its first path starts
  // over from the root, like an arrived ant, so the species keeps bringing fresh paths.
  std::optional<Path> step(const PheromoneField& pheromone, Rng& rng);

  std::size_t nodeCount() const { return nodes_.size(); }
  // A node at c or at one of its 8 neighbours in sight of c; -1 if none.
  int nodeNear(GridCell c) const;
  // The tree's branch from node to the root, node first.
  Path branchToRoot(int node) const;
  bool reachedTarget() const { return target_node_ >= 0; }
  std::uint64_t restarts() const { return restarts_; }

 private:
  struct Node {
    GridCell cell;
    int parent = -1;
    double cost = 0.0;  // path length from the start, cells
    // Children as an intrusive doubly linked list (no per-node allocation).
    int first_child = -1;
    int next_sibling = -1;
    int prev_sibling = -1;
  };
  void reset();
  int nearest(GridCell c) const;
  // The point a step from base towards rand reaches; nothing when it cannot leave base.
  std::optional<GridCell> steer(GridCell base, GridCell rand) const;
  static constexpr int kRingCells = 3;  // nearest(): the square scanned before the k-d tree
  // Nodes within r_RRT of c, in k-d traversal order (deterministic), into out.
  void near(GridCell c, std::vector<int>& out) const;
  int addNode(GridCell cell, const std::vector<int>& near_nodes, int fallback_parent);
  void rewire(int node, const std::vector<int>& near_nodes);
  void setParent(int node, int parent);
  Path pathTo(int node) const;

  const GridLayer* grid_;
  GridCell root_;
  GridCell target_;
  double step_cells_;
  double near_radius_cells_;
  int nodes_after_solution_;
  bool near_nearest_;
  int draws_per_step_;
  bool sample_visibility_;
  int node_redraws_;

  // Nodes also form a 2D k-d tree (splitting on x at even depths and y at odd ones; node i of
  // the RRT* is k-d node i; inserted in growth order and rebuilt balanced as the tree doubles), so nearest() and near() visit O(log n) nodes on
  // average instead of scanning the tree or rings of buckets (a sample far from the tree, as the
  // pheromone field gives near the goal, made a ring search scan most of the map). Squared
  // distances are exact integers; ties go to the lowest index, as in a scan of every node.
  struct KdLinks {
    int left = -1;
    int right = -1;
  };
  void kdInsert(int node);
  int kdBuild(std::vector<int>& ids, std::size_t lo, std::size_t hi, int depth);
  static constexpr std::size_t kFirstRebuild = 64;
  int kd_root_ = 0;
  std::size_t kd_rebuild_at_ = kFirstRebuild;
  std::vector<Node> nodes_;
  std::vector<KdLinks> kd_;
  std::vector<int> node_at_;  // node index of each grid cell, -1 if none
  // Reused buffers, so a step allocates nothing once they have grown.
  struct KdVisit {
    int node;
    int depth;
    long long bound_d2;  // lower bound of the squared distance to anything in this subtree
  };
  mutable std::vector<KdVisit> kd_stack_;
  mutable std::vector<std::pair<double, int>> scratch_;
  mutable std::vector<std::pair<long long, int>> heap_;  // near(): the k nearest so far
  std::vector<int> near_nodes_;
  std::vector<int> target_near_;
  std::vector<int> subtree_stack_;
  int target_node_ = -1;
  double reported_target_cost_ = 0.0;  // goal cost last handed to the colony (infinity: none yet)
  int nodes_since_solution_ = 0;
  std::uint64_t restarts_ = 0;
};

}  // namespace skyroute::habpp
