#include "planning/colony/hab_pp_rrt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skyroute::habpp {

namespace {
long long dist2(GridCell a, GridCell b) {
  const long long dx = a.x - b.x, dy = a.y - b.y;
  return dx * dx + dy * dy;
}
double dist(GridCell a, GridCell b) { return std::sqrt(static_cast<double>(dist2(a, b))); }
int coord(GridCell c, int depth) { return (depth & 1) == 0 ? c.x : c.y; }
}  // namespace

RrtAnt::RrtAnt(const GridLayer& grid, GridCell root, GridCell target, const HabPpParameters& params)
    : grid_(&grid),
      root_(root),
      target_(target),
      step_cells_(params.rrt_step_cells),
      near_radius_cells_(params.rrt_near_radius_cells),
      nodes_after_solution_(params.rrt_nodes_after_solution),
      near_nearest_(params.rrt_near_nearest),
      draws_per_step_(params.rrt_draws_per_step),
      sample_visibility_(params.rrt_sample_visibility),
      node_redraws_(params.rrt_node_redraws),
      node_at_(grid.cellCount(), -1) {
  reset();
}

void RrtAnt::reset() {
  for (const Node& n : nodes_) node_at_[grid_->index(n.cell)] = -1;
  nodes_.clear();
  kd_.clear();
  nodes_.push_back(Node{root_, -1, 0.0});
  kd_.push_back(KdLinks{});
  kd_root_ = 0;
  kd_rebuild_at_ = kFirstRebuild;
  node_at_[grid_->index(root_)] = 0;
  target_node_ = -1;
  reported_target_cost_ = std::numeric_limits<double>::infinity();
  nodes_since_solution_ = 0;
}

int RrtAnt::kdBuild(std::vector<int>& ids, std::size_t lo, std::size_t hi, int depth) {
  if (lo >= hi) return -1;
  const std::size_t mid = lo + (hi - lo) / 2;
  // Median by the splitting coordinate, ties by index, so the rebuilt tree is deterministic.
  // Nodes equal to the median's coordinate may fall on either side: the searches' bounds
  // (|diff| across the splitting line) hold for <= on the left and >= on the right.
  std::nth_element(ids.begin() + static_cast<std::ptrdiff_t>(lo), ids.begin() + static_cast<std::ptrdiff_t>(mid),
                   ids.begin() + static_cast<std::ptrdiff_t>(hi), [&](int a, int b) {
                     const int ca = coord(nodes_[a].cell, depth), cb = coord(nodes_[b].cell, depth);
                     return ca != cb ? ca < cb : a < b;
                   });
  const int node = ids[mid];
  kd_[node].left = kdBuild(ids, lo, mid, depth + 1);
  kd_[node].right = kdBuild(ids, mid + 1, hi, depth + 1);
  return node;
}

void RrtAnt::kdInsert(int node) {
  if (nodes_.size() >= kd_rebuild_at_) {
    // The tree grows outwards from its root, so insertion in growth order unbalances the k-d
    // tree (a search then visits a large part of it); rebuild it balanced whenever the node count
    // doubles (amortised O(log n) per node).
    kd_rebuild_at_ *= 2;
    std::vector<int> ids(nodes_.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
    for (KdLinks& k : kd_) k = KdLinks{};
    kd_root_ = kdBuild(ids, 0, ids.size(), 0);
    return;
  }
  const GridCell c = nodes_[node].cell;
  int at = kd_root_;
  for (int depth = 0;; ++depth) {
    int& next = coord(c, depth) < coord(nodes_[at].cell, depth) ? kd_[at].left : kd_[at].right;
    if (next < 0) {
      next = node;
      return;
    }
    at = next;
  }
}

int RrtAnt::nearest(GridCell c) const {
  int best = -1;
  long long best_d2 = std::numeric_limits<long long>::max();
  // A grown tree usually holds a node within a few cells of the sample: scan the square of radius
  // kRingCells around it in node_at_ first (the k-d tree, built in growth order, is far from
  // balanced). A node found within kRingCells (Euclidean) is the nearest, since every node outside
  // the square is farther; ties go to the lowest index, as in the k-d search, so the answer is the
  // same node either way.
  const int x0 = std::max(0, c.x - kRingCells), x1 = std::min(grid_->width() - 1, c.x + kRingCells);
  const int y0 = std::max(0, c.y - kRingCells), y1 = std::min(grid_->height() - 1, c.y + kRingCells);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const int node = node_at_[grid_->index(GridCell{x, y})];
      if (node < 0) continue;
      const long long d2 = dist2(nodes_[node].cell, c);
      if (d2 < best_d2 || (d2 == best_d2 && node < best)) {
        best_d2 = d2;
        best = node;
      }
    }
  }
  if (best >= 0 && best_d2 <= static_cast<long long>(kRingCells) * kRingCells) return best;
  best = -1;
  best_d2 = std::numeric_limits<long long>::max();
  kd_stack_.clear();
  kd_stack_.push_back(KdVisit{kd_root_, 0, 0});
  while (!kd_stack_.empty()) {
    const KdVisit v = kd_stack_.back();
    kd_stack_.pop_back();
    if (v.bound_d2 > best_d2) continue;  // ">" keeps equal-distance nodes for the index tie-break
    const long long d2 = dist2(nodes_[v.node].cell, c);
    if (d2 < best_d2 || (d2 == best_d2 && v.node < best)) {
      best_d2 = d2;
      best = v.node;
    }
    const long long diff = coord(c, v.depth) - coord(nodes_[v.node].cell, v.depth);
    const int near_side = diff < 0 ? kd_[v.node].left : kd_[v.node].right;
    const int far_side = diff < 0 ? kd_[v.node].right : kd_[v.node].left;
    // The far side lies across the splitting line, at least |diff| away; pushed first, so the near
    // side (popped first) usually tightens best_d2 before the far side is looked at.
    if (far_side >= 0) kd_stack_.push_back(KdVisit{far_side, v.depth + 1, std::max(v.bound_d2, diff * diff)});
    if (near_side >= 0) kd_stack_.push_back(KdVisit{near_side, v.depth + 1, v.bound_d2});
  }
  return best;
}

void RrtAnt::near(GridCell c, std::vector<int>& out) const {
  out.clear();
  const double r = near_radius_cells_;
  // k-nearest cap (see HabPpParameters::rrt_near_nearest): a max-heap of the k best (d2, index).
  const std::size_t k = near_nearest_ ? static_cast<std::size_t>(std::ceil(2.0 * std::exp(1.0) *
                                                                           std::log(static_cast<double>(nodes_.size()) + 1.0)))
                                      : 0;
  heap_.clear();
  kd_stack_.clear();
  kd_stack_.push_back(KdVisit{kd_root_, 0, 0});
  while (!kd_stack_.empty()) {
    const KdVisit v = kd_stack_.back();
    kd_stack_.pop_back();
    if (static_cast<double>(v.bound_d2) > r * r + 1e-9) continue;
    if (k > 0 && heap_.size() >= k && v.bound_d2 > heap_.front().first) continue;
    if (dist(nodes_[v.node].cell, c) <= r) {
      if (k == 0) {
        out.push_back(v.node);
      } else {
        const std::pair<long long, int> e{dist2(nodes_[v.node].cell, c), v.node};
        if (heap_.size() < k) {
          heap_.push_back(e);
          std::push_heap(heap_.begin(), heap_.end());
        } else if (e < heap_.front()) {
          std::pop_heap(heap_.begin(), heap_.end());
          heap_.back() = e;
          std::push_heap(heap_.begin(), heap_.end());
        }
      }
    }
    const long long diff = coord(c, v.depth) - coord(nodes_[v.node].cell, v.depth);
    const int near_side = diff < 0 ? kd_[v.node].left : kd_[v.node].right;
    const int far_side = diff < 0 ? kd_[v.node].right : kd_[v.node].left;
    if (far_side >= 0) kd_stack_.push_back(KdVisit{far_side, v.depth + 1, std::max(v.bound_d2, diff * diff)});
    if (near_side >= 0) kd_stack_.push_back(KdVisit{near_side, v.depth + 1, v.bound_d2});
  }
  // The traversal order depends only on the tree, so it is deterministic; no sort needed. The
  // k nearest come nearest first (ties by index).
  if (k > 0) {
    std::sort_heap(heap_.begin(), heap_.end());
    for (const auto& [d2, node] : heap_) out.push_back(node);
  }
}

void RrtAnt::setParent(int node, int parent) {
  Node& n = nodes_[node];
  if (n.parent >= 0) {  // unlink from the old parent's children
    if (n.prev_sibling >= 0) nodes_[n.prev_sibling].next_sibling = n.next_sibling;
    else nodes_[n.parent].first_child = n.next_sibling;
    if (n.next_sibling >= 0) nodes_[n.next_sibling].prev_sibling = n.prev_sibling;
  }
  n.parent = parent;
  n.prev_sibling = -1;
  n.next_sibling = nodes_[parent].first_child;
  if (n.next_sibling >= 0) nodes_[n.next_sibling].prev_sibling = node;
  nodes_[parent].first_child = node;
  // The new cost flows down the subtree (Table 3 leaves this implicit in Cost(x, V)).
  subtree_stack_.clear();
  subtree_stack_.push_back(node);
  while (!subtree_stack_.empty()) {
    const int i = subtree_stack_.back();
    subtree_stack_.pop_back();
    nodes_[i].cost = nodes_[nodes_[i].parent].cost + dist(nodes_[nodes_[i].parent].cell, nodes_[i].cell);
    for (int ch = nodes_[i].first_child; ch >= 0; ch = nodes_[ch].next_sibling) subtree_stack_.push_back(ch);
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
  nodes_.push_back(Node{cell, -1, 0.0});
  kd_.push_back(KdLinks{});
  kdInsert(id);
  node_at_[grid_->index(cell)] = id;
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

int RrtAnt::nodeNear(GridCell c) const {
  if (const int n = node_at_[grid_->index(c)]; n >= 0) return n;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const GridCell q{c.x + dx, c.y + dy};
      if (!grid_->inside(q)) continue;
      const int n = node_at_[grid_->index(q)];
      if (n >= 0 && grid_->lineOfSight(c, q)) return n;
    }
  }
  return -1;
}

Path RrtAnt::branchToRoot(int node) const {
  Path p;
  for (int i = node; i >= 0; i = nodes_[i].parent) p.push_back(nodes_[i].cell);
  return p;
}

Path RrtAnt::pathTo(int node) const {
  Path p = branchToRoot(node);
  std::reverse(p.begin(), p.end());
  return p;
}

std::optional<GridCell> RrtAnt::steer(GridCell base, GridCell rand) const {
  // Steer on integer coordinates: at most s_RRT cells towards the sample, rounded to a cell centre.
  // Choice: when that point is blocked or out of sight, the step is halved until it is free and
  // visible (down to one cell), so the long s_RRT still lets the tree through doors and corridors.
  const double d = dist(base, rand);
  double reach = std::min(step_cells_, d);
  for (;;) {
    const double f = d > 0.0 ? reach / d : 0.0;
    const GridCell t{base.x + static_cast<int>(std::lround((rand.x - base.x) * f)),
                     base.y + static_cast<int>(std::lround((rand.y - base.y) * f))};
    if (t == base) return std::nullopt;
    if (!grid_->blocked(t) && grid_->lineOfSight(base, t)) return t;
    reach *= 0.5;
  }
}

std::optional<Path> RrtAnt::step(const PheromoneField& pheromone, Rng& rng) {
  if (target_node_ >= 0 && nodes_after_solution_ > 0 && nodes_since_solution_ >= nodes_after_solution_) {
    reset();
    ++restarts_;
  }
  // Choice: a draw that cannot grow the tree (the sample, or the steered point, is already a node,
  // as most draws are once the pheromone concentrates on the ranked paths the tree has covered) is
  // redrawn, up to HabPpParameters::rrt_draws_per_step times in all, so each step adds a node as
  // section 4 intends; a sample that lands on a node is rejected by one lookup and does not count
  // towards those draws, up to HabPpParameters::rrt_node_redraws times.
  int from = -1;
  GridCell new_cell{};
  int node_draws = 0;
  for (int draw = 0; draw < draws_per_step_ && from < 0; ++draw) {
    const GridCell rand = sample_visibility_ ? pheromone.sampleWithVisibility(rng) : pheromone.sample(rng);
    if (node_at_[grid_->index(rand)] >= 0) {
      if (node_draws++ < node_redraws_) --draw;  // a draw on a node costs one lookup: it does not count
      continue;
    }
    const int n = nearest(rand);
    if (std::optional<GridCell> t = steer(nodes_[n].cell, rand); t && node_at_[grid_->index(*t)] < 0) {
      from = n;
      new_cell = *t;
    }
  }
  if (from < 0) return std::nullopt;
  near(new_cell, near_nodes_);
  const int id = addNode(new_cell, near_nodes_, from);
  rewire(id, near_nodes_);
  if (target_node_ >= 0) ++nodes_since_solution_;

  // Connect the target when it is within one extension and in sight; afterwards it is an ordinary
  // node that rewiring may improve.
  if (new_cell == target_) {
    target_node_ = id;
  } else if (target_node_ < 0 && dist(new_cell, target_) <= step_cells_ && grid_->lineOfSight(new_cell, target_)) {
    near(target_, target_near_);
    target_node_ = addNode(target_, target_near_, id);
  }
  if (target_node_ >= 0 && nodes_[target_node_].cost + 1e-9 < reported_target_cost_) {
    reported_target_cost_ = nodes_[target_node_].cost;
    return pathTo(target_node_);
  }
  return std::nullopt;
}

}  // namespace skyroute::habpp
