#include "planning/hab_pp_rrt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skyroute::habpp {

namespace {
double dist(GridCell a, GridCell b) { return std::hypot(double(a.x - b.x), double(a.y - b.y)); }
}  // namespace

RrtAnt::RrtAnt(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params)
    : grid_(&grid),
      start_(start),
      goal_(goal),
      step_cells_(params.rrt_step_cells),
      near_radius_cells_(params.rrt_near_radius_cells),
      nodes_after_solution_(params.rrt_nodes_after_solution),
      node_at_(grid.cellCount(), -1) {
  buckets_x_ = (grid.width() + kBucketCells - 1) / kBucketCells;
  buckets_y_ = (grid.height() + kBucketCells - 1) / kBucketCells;
  buckets_.resize(static_cast<std::size_t>(buckets_x_) * buckets_y_);
  reset();
}

void RrtAnt::reset() {
  for (const Node& n : nodes_) {
    node_at_[grid_->index(n.cell)] = -1;
    buckets_[bucketOf(n.cell)].clear();
  }
  nodes_.clear();
  nodes_.push_back(Node{start_, -1, 0.0, {}});
  node_at_[grid_->index(start_)] = 0;
  buckets_[bucketOf(start_)].push_back(0);
  goal_node_ = -1;
  reported_goal_cost_ = std::numeric_limits<double>::infinity();
  nodes_since_solution_ = 0;
}

int RrtAnt::nearest(GridCell c) const {
  // Rings of buckets around c's bucket; a node in ring R + 1 or beyond is more than R buckets'
  // width away, so the search stops once the best distance is within that. Ties go to the lowest
  // index, as in a scan of every node.
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  const int bx = c.x / kBucketCells, by = c.y / kBucketCells;
  const int rings = std::max(buckets_x_, buckets_y_);
  for (int r = 0; r <= rings; ++r) {
    for (int y = by - r; y <= by + r; ++y) {
      if (y < 0 || y >= buckets_y_) continue;
      for (int x = bx - r; x <= bx + r; ++x) {
        if (x < 0 || x >= buckets_x_ || (std::abs(x - bx) != r && std::abs(y - by) != r)) continue;
        for (int i : buckets_[static_cast<std::size_t>(y) * buckets_x_ + x]) {
          const double d = dist(nodes_[i].cell, c);
          if (d < best_d || (d == best_d && i < best)) {
            best_d = d;
            best = i;
          }
        }
      }
    }
    if (best >= 0 && best_d <= static_cast<double>(r) * kBucketCells) break;
  }
  return best;
}

std::vector<int> RrtAnt::near(GridCell c) const {
  std::vector<int> out;
  const int reach = static_cast<int>(std::ceil(near_radius_cells_));
  const int x0 = std::max(0, (c.x - reach) / kBucketCells), x1 = std::min(buckets_x_ - 1, (c.x + reach) / kBucketCells);
  const int y0 = std::max(0, (c.y - reach) / kBucketCells), y1 = std::min(buckets_y_ - 1, (c.y + reach) / kBucketCells);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      for (int i : buckets_[static_cast<std::size_t>(y) * buckets_x_ + x]) {
        if (dist(nodes_[i].cell, c) <= near_radius_cells_) out.push_back(i);
      }
    }
  }
  std::sort(out.begin(), out.end());  // index order, as a scan of every node gives
  return out;
}

void RrtAnt::setParent(int node, int parent) {
  Node& n = nodes_[node];
  if (n.parent >= 0) {
    auto& siblings = nodes_[n.parent].children;
    siblings.erase(std::find(siblings.begin(), siblings.end(), node));
  }
  n.parent = parent;
  nodes_[parent].children.push_back(node);
  // The new cost flows down the subtree (Table 3 leaves this implicit in Cost(x, V)).
  std::vector<int> stack{node};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    nodes_[i].cost = nodes_[nodes_[i].parent].cost + dist(nodes_[nodes_[i].parent].cell, nodes_[i].cell);
    for (int ch : nodes_[i].children) stack.push_back(ch);
  }
}

int RrtAnt::addNode(GridCell cell, const std::vector<int>& near_nodes, int fallback_parent) {
  // Lines 9-19: the cheapest visible parent among the near nodes. Candidates cheaper than the
  // (visible) fallback are tried cheapest first, so only the line of sight of the winner and of
  // the cheaper hidden ones is checked.
  int parent = fallback_parent;
  const double fallback_cost = nodes_[fallback_parent].cost + dist(nodes_[fallback_parent].cell, cell);
  scratch_.clear();
  for (int i : near_nodes) {
    const double c = nodes_[i].cost + dist(nodes_[i].cell, cell);
    if (c < fallback_cost) scratch_.emplace_back(c, i);
  }
  std::sort(scratch_.begin(), scratch_.end());
  for (const auto& [c, i] : scratch_) {
    if (grid_->lineOfSight(nodes_[i].cell, cell)) {
      parent = i;
      break;
    }
  }
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{cell, -1, 0.0, {}});
  node_at_[grid_->index(cell)] = id;
  buckets_[bucketOf(cell)].push_back(id);
  setParent(id, parent);
  return id;
}

void RrtAnt::rewire(int node, const std::vector<int>& near_nodes) {
  // Lines 22-32: near nodes that become cheaper through the new node take it as parent.
  for (int i : near_nodes) {
    if (i == node || i == nodes_[node].parent) continue;
    const double c = nodes_[node].cost + dist(nodes_[node].cell, nodes_[i].cell);
    if (c + 1e-9 < nodes_[i].cost && grid_->lineOfSight(nodes_[node].cell, nodes_[i].cell)) setParent(i, node);
  }
}

Path RrtAnt::pathTo(int node) const {
  Path p;
  for (int i = node; i >= 0; i = nodes_[i].parent) p.push_back(nodes_[i].cell);
  std::reverse(p.begin(), p.end());
  return p;
}

std::optional<Path> RrtAnt::step(const PheromoneField& pheromone, Rng& rng) {
  if (goal_node_ >= 0 && nodes_since_solution_ >= nodes_after_solution_) {
    reset();
    ++restarts_;
  }
  const GridCell rand = pheromone.sample(rng);
  const int from = nearest(rand);
  const GridCell base = nodes_[from].cell;
  // Steer on integer coordinates: at most s_RRT cells towards the sample, rounded to a cell centre.
  // Choice: when that point is blocked or out of sight, the step is halved until it is free and
  // visible (down to one cell), so the long s_RRT still lets the tree through doors and corridors.
  const double d = dist(base, rand);
  double reach = std::min(step_cells_, d);
  GridCell target = base;
  for (;;) {
    const double f = d > 0.0 ? reach / d : 0.0;
    const GridCell t{base.x + static_cast<int>(std::lround((rand.x - base.x) * f)),
                     base.y + static_cast<int>(std::lround((rand.y - base.y) * f))};
    if (t == base) return std::nullopt;
    if (!grid_->blocked(t) && grid_->lineOfSight(base, t)) {
      target = t;
      break;
    }
    reach *= 0.5;
  }
  if (node_at_[grid_->index(target)] >= 0) return std::nullopt;
  std::vector<int> near_nodes = near(target);
  const int id = addNode(target, near_nodes, from);
  rewire(id, near_nodes);
  if (goal_node_ >= 0) ++nodes_since_solution_;

  // Connect the goal when it is within one extension and in sight; afterwards it is an ordinary
  // node that rewiring may improve.
  if (target == goal_) {
    goal_node_ = id;
  } else if (goal_node_ < 0 && dist(target, goal_) <= step_cells_ && grid_->lineOfSight(target, goal_)) {
    goal_node_ = addNode(goal_, near(goal_), id);
  }
  if (goal_node_ >= 0 && nodes_[goal_node_].cost + 1e-9 < reported_goal_cost_) {
    reported_goal_cost_ = nodes_[goal_node_].cost;
    return pathTo(goal_node_);
  }
  return std::nullopt;
}

}  // namespace skyroute::habpp
