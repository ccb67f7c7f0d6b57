#include "planning/colony/hab_pp_colony.hpp"

#include <algorithm>

#include "planning/colony/hab_pp_detail.hpp"
#include "planning/grid/any_angle_search.hpp"

namespace skyroute::habpp {

Colony::Colony(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params, std::uint64_t seed)
    : grid_(grid), start_(start), goal_(goal), params_(params), fields_(grid, goal, params),
      pheromone_(fields_, params), rrt_rng_(seed ^ 0x9e3779b97f4a7c15ULL) {
  max_steps_ = params.max_ant_steps > 0 ? params.max_ant_steps : 2 * (grid.width() + grid.height());
  auto add = [&](int count, int radius, bool expanding) {
    for (int i = 0; i < count; ++i) {
      Ant a;
      a.base_radius = radius;
      a.expanding = expanding;
      a.visited.assign(grid.cellCount(), 0);
      restart(a);
      ants_.push_back(std::move(a));
    }
  };
  add(params.simple_ants, 1, false);
  add(params.general_ants, params.general_radius, false);
  add(params.far_sighted_ants, params.far_sighted_radius, false);
  add(params.sight_general_ants, params.general_radius, true);
  add(params.sight_far_sighted_ants, params.far_sighted_radius, true);
  const int trees = params.rrt_shared_tree ? std::min(params.rrt_ants, 1) : params.rrt_ants;
  for (int i = 0; i < trees; ++i) {
    if (params.rrt_tree_from_goal) rrt_.emplace_back(grid, goal, start, params);
    else rrt_.emplace_back(grid, start, goal, params);
  }
}

bool Colony::iterate(Rng& rng, HabPpResult& stats) {
  std::vector<Path> arrivals;
  const bool list_full = ranked_.size() >= static_cast<std::size_t>(params_.ranked_paths);
  joining_ = params_.rrt_ants_join_tree && !list_full && !rrt_.empty();
  for (Ant& ant : ants_) {
    if (std::optional<Path> p = step(ant, rng)) {
      arrivals.push_back(std::move(*p));
      ++stats.ant_arrivals;
      if (joined_) ++stats.joined_arrivals;
    }
  }
  const std::size_t ant_count = arrivals.size();  // arrivals[ant_count..] came from the trees
  // Each RRT* ant adds one node: to the species' one tree, or each to its own.
  const bool trees_rest = params_.rrt_rest_when_full && list_full;
  for (int k = 0; k < (trees_rest ? 0 : params_.rrt_ants); ++k) {
    RrtAnt& tree = rrt_[rrt_.size() == 1 ? 0 : static_cast<std::size_t>(k)];
    ++stats.rrt_steps;
    if (std::optional<Path> p = tree.step(pheromone_, rrt_rng_)) {
      if (params_.rrt_tree_from_goal) std::reverse(p->begin(), p->end());
      arrivals.push_back(tightenPath(grid_, *p, params_.tighten_passes));
      if (const double length = polylineLength(arrivals.back());
          best_tree_path_.empty() || length < best_tree_length_ - 1e-9) {
        best_tree_path_ = arrivals.back();
        best_tree_length_ = length;
      }
      ++stats.rrt_arrivals;
    }
  }
  bool changed = false;
  if (!arrivals.empty()) {
    std::vector<Path> pool = ranked_;
    // Where each pool path came from (kRanked: the list itself; the arrivals' species otherwise;
    // a crossover child takes its arrival's), for the stopping rule.
    std::vector<Origin> origin(pool.size(), Origin::kRanked);
    const std::size_t parents = std::min<std::size_t>(ranked_.size(), params_.crossover_paths);
    // An arrival equal to an earlier one of this iteration gives the same children (which the
    // ranking drops as duplicates), and a path crossed with itself gives nothing new: skip both.
    std::vector<std::uint8_t> repeat(arrivals.size(), 0);
    for (std::size_t k = 1; k < arrivals.size(); ++k) {
      for (std::size_t e = 0; e < k && repeat[k] == 0; ++e) repeat[k] = arrivals[e] == arrivals[k] ? 1 : 0;
    }
    for (std::size_t r = 0; r < parents; ++r) {
      for (std::size_t k = 0; k < arrivals.size(); ++k) {
        if (repeat[k] != 0 || arrivals[k] == ranked_[r]) continue;
        for (Path& child : crossover(grid_, ranked_[r], arrivals[k], params_.crossover_points)) {
          pool.push_back(relaxPruned(grid_, std::move(child), params_.tighten_passes));  // children come pruned
          origin.push_back(k < ant_count ? Origin::kAnts : Origin::kTrees);
          ++stats.crossover_children;
        }
      }
    }
    for (std::size_t k = 0; k < arrivals.size(); ++k) {
      pool.push_back(std::move(arrivals[k]));
      origin.push_back(k < ant_count ? Origin::kAnts : Origin::kTrees);
    }
    const std::size_t top = std::min<std::size_t>(ranked_.size(), std::max(1, params_.crossover_paths));
    const std::vector<Path> top_before(ranked_.begin(), ranked_.begin() + static_cast<std::ptrdiff_t>(top));
    bool entered[3] = {false, false, false};
    changed = rank(pool, origin, entered);
    const bool only_trees_entered = entered[static_cast<int>(Origin::kTrees)] && !entered[static_cast<int>(Origin::kAnts)];
    if (changed && only_trees_entered && params_.rrt_stop_top_paths) {
      // Only RRT* paths (or their crossover children) entered the list: unless they changed
      // its top paths, the stopping rule's count goes on.
      const std::size_t top_now = std::min<std::size_t>(ranked_.size(), std::max(1, params_.crossover_paths));
      changed = top_now != top_before.size() || !std::equal(top_before.begin(), top_before.end(), ranked_.begin());
    }
  }
  pheromone_.updateCells(ranked_cells_, ranked_eval_);
  return changed;
}

void Colony::restart(Ant& ant) {
  for (std::size_t i : ant.marked) ant.visited[i] = 0;
  ant.marked.clear();
  ant.path.assign(1, start_);
  mark(ant, start_);
  ant.steps = 0;
}

void Colony::mark(Ant& ant, GridCell c) {
  const std::size_t i = grid_.index(c);
  if (ant.visited[i] == 0) {
    ant.visited[i] = 1;
    ant.marked.push_back(i);
  }
}

std::optional<Path> Colony::step(Ant& ant, Rng& rng) {
  const GridCell at = ant.path.back();
  const int radius = sightRadius(fields_, at, ant.base_radius, ant.expanding, params_.sight_max_radius);
  std::vector<GridCell>& c = candidates_;
  candidates(fields_, at, radius, ant.visited, c);
  if (c.empty() || ant.steps >= max_steps_) {  // Choice: a stuck or lost ant starts over
    restart(ant);
    return std::nullopt;
  }
  // Choice: before its first step an ant's heading points at the goal.
  double hx = goal_.x - at.x, hy = goal_.y - at.y;
  if (ant.path.size() >= 2) {
    hx = at.x - ant.path[ant.path.size() - 2].x;
    hy = at.y - ant.path[ant.path.size() - 2].y;
  }
  weights_.resize(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    weights_[k] = powExponent(pheromone_.at(c[k]), params_.alpha) *
                  powExponent(fields_.visibility(c[k]), params_.beta) *
                  powExponent(angleFactor(hx, hy, at, c[k], params_.angle_factor_floor), params_.gamma);
  }
  const GridCell j = c[rouletteSelect(weights_, rng)];
  ant.path.push_back(j);
  mark(ant, j);
  ++ant.steps;
  pruneLastStep(grid_, ant.path);
  joined_ = false;
  if (!(j == goal_)) {
    // rrt_ants_join_tree: next to a node of a tree from the goal, finish along its branch.
    if (!joining_) return std::nullopt;
    int node = -1;
    const RrtAnt* tree = nullptr;
    for (const RrtAnt& t : rrt_) {
      if ((node = t.nodeNear(j)) >= 0) {
        tree = &t;
        break;
      }
    }
    if (tree == nullptr) return std::nullopt;
    const Path branch = tree->branchToRoot(node);  // node first, the goal last
    if (!(branch.front() == j)) ant.path.push_back(branch.front());
    ant.path.insert(ant.path.end(), branch.begin() + 1, branch.end());
    joined_ = true;
  }
  Path arrived = tightenPath(grid_, ant.path, params_.tighten_passes);
  restart(ant);
  return arrived;
}

bool Colony::rank(std::vector<Path>& pool, const std::vector<Origin>& origin, bool entered[3]) {
  const std::vector<double> eval = evaluate(pool, params_);
  std::vector<std::size_t> order(pool.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto lex = [](const Path& p, const Path& q) {
    return std::lexicographical_compare(p.begin(), p.end(), q.begin(), q.end(), [](GridCell u, GridCell v) {
      return u.x != v.x ? u.x < v.x : u.y < v.y;
    });
  };
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t k) {
    if (eval[i] != eval[k]) return eval[i] > eval[k];
    return lex(pool[i], pool[k]);
  });
  std::vector<Path> next;
  std::vector<double> next_eval;
  std::vector<std::vector<std::uint32_t>> next_cells;
  for (std::size_t i : order) {
    if (!next.empty() && next.back() == pool[i]) continue;  // equal paths sort next to each other
    if (next.size() >= static_cast<std::size_t>(params_.ranked_paths)) break;
    if (i >= ranked_.size() && std::find(ranked_.begin(), ranked_.end(), pool[i]) == ranked_.end()) {
      entered[static_cast<int>(origin[i])] = true;
    }
    next.push_back(pool[i]);
    next_eval.push_back(eval[i]);
    // The pool starts with the ranked list itself, whose cells are known.
    next_cells.push_back(i < ranked_cells_.size() ? ranked_cells_[i] : pheromone_.pathCells(pool[i]));
  }
  const bool changed = next != ranked_;
  for (const Path& p : next) {
    const double length = polylineLength(p);
    if (shortest_ranked_.empty() || length < shortest_ranked_length_ - 1e-9) {
      shortest_ranked_ = p;
      shortest_ranked_length_ = length;
    }
  }
  ranked_ = std::move(next);
  ranked_eval_ = std::move(next_eval);
  ranked_cells_ = std::move(next_cells);
  return changed;
}

}  // namespace skyroute::habpp
