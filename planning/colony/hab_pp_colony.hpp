// HAB-PP's colony (Table 2): the ants of every species and the RRT* trees, the ranked list L_R and
// the pheromone field, run one iteration at a time by planHabPp. Internal to the planner (its
// interface is hab_pp.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "planning/colony/hab_pp.hpp"
#include "planning/colony/hab_pp_rrt.hpp"

namespace skyroute::habpp {

// Where a path in the pool of one iteration came from.
enum class Origin : std::uint8_t { kRanked, kAnts, kTrees };

struct Ant {
  int base_radius = 1;
  bool expanding = false;
  Path path;
  std::vector<std::uint8_t> visited;  // tabu marks, one per cell
  std::vector<std::size_t> marked;    // which marks to clear on restart
  int steps = 0;
};

class Colony {
 public:
  // Choice: the RRT* species draws from its own random stream (derived from the plan's seed), so
  // the ants of HAB-PP and of Improved HAB-PP with the same seed draw the same numbers and walk the
  // same way until the first RRT* path enters the ranked list: the two planners are compared on
  // common random numbers, and what differs is what the trees contribute.
  Colony(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params, std::uint64_t seed);

  // One iteration n_I of Table 2 (lines 6-27). Returns whether the ranked list changed, as the
  // stopping rule counts it (see HabPpParameters::rrt_stop_top_paths).
  bool iterate(Rng& rng, HabPpResult& stats);

  const std::vector<Path>& ranked() const { return ranked_; }
  // The shortest path that has been in the ranked list at any iteration (eq. (2) may have pushed
  // it out since for paths with fewer points or less turning).
  const Path& shortestRanked() const { return shortest_ranked_; }
  // The shortest path the RRT* species has brought (pruned as on arrival); empty if none.
  const Path& bestTreePath() const { return best_tree_path_; }

 private:
  void restart(Ant& ant);
  void mark(Ant& ant, GridCell c);

  // Lines 10-18 of Table 2 for one ant: choose j by eq. (1), move, prune; a path on arrival.
  std::optional<Path> step(Ant& ant, Rng& rng);

  // Lines 23-25: evaluate (eq. 2), sort, drop duplicates, cut to N_R. entered[origin] is set when
  // a path of that origin that was not in the list before is in it now.
  bool rank(std::vector<Path>& pool, const std::vector<Origin>& origin, bool entered[3]);

  const GridLayer& grid_;
  GridCell start_;
  GridCell goal_;
  HabPpParameters params_;
  GridFields fields_;
  PheromoneField pheromone_;
  int max_steps_ = 0;
  std::vector<Ant> ants_;
  std::vector<RrtAnt> rrt_;
  std::vector<Path> ranked_;
  std::vector<double> ranked_eval_;
  std::vector<std::vector<std::uint32_t>> ranked_cells_;  // pheromone cells of each ranked path
  Path shortest_ranked_;
  Path best_tree_path_;
  double best_tree_length_ = 0.0;
  double shortest_ranked_length_ = 0.0;
  std::vector<double> weights_;
  std::vector<GridCell> candidates_;  // reused by every ant step
  bool joining_ = false;  // this iteration, ants may finish along a tree (rrt_ants_join_tree)
  bool joined_ = false;   // the path step() just returned was finished along a tree
  Rng rrt_rng_;
};

}  // namespace skyroute::habpp
