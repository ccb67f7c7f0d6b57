#include "planning/sampling/rrt_tree_reuse.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace skyroute {
namespace {

enum class EdgeState : std::uint8_t { kUnchecked, kValid, kBlocked };

// The old tree's edges, both ways: node i's neighbours are its parent and its children.
struct Adjacency {
  std::vector<std::uint32_t> first;  // neighbours of i are at [first[i], first[i + 1])
  std::vector<std::uint32_t> to;

  explicit Adjacency(const RrtTree& tree) {
    const std::size_t n = tree.size();
    std::vector<std::uint32_t> degree(n, 0);
    for (std::size_t i = 1; i < n; ++i) {
      ++degree[i];
      ++degree[tree.parents[i]];
    }
    first.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) first[i + 1] = first[i] + degree[i];
    to.resize(first[n]);
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 1; i < n; ++i) {
      const std::uint32_t p = tree.parents[i];
      to[fill[i]++] = p;
      to[fill[p]++] = static_cast<std::uint32_t>(i);
    }
  }
};

}  // namespace

Result<RerootedTree> rerootTree(const RrtTree& old_tree, const Eigen::Vector3d& new_root_m,
                               const MotionValidator& validator, const TreeReuseOptions& options,
                               const TerminationCondition& stop) {
  if (auto bad = old_tree.layoutError()) return make_error(ErrorCode::kInvalidArgument, "old_tree", *bad);
  if (!new_root_m.allFinite()) return make_error(ErrorCode::kInvalidArgument, "new_root_m", "is not finite");
  if (options.max_nodes == 0) return make_error(ErrorCode::kInvalidArgument, "max_nodes", "must be at least 1 (the root)");

  RerootedTree out;
  out.tree.positions_m.push_back(new_root_m);
  out.tree.parents.push_back(kRrtTreeNoParent);
  out.tree.costs_m.push_back(0.0);
  const std::size_t n = old_tree.size();
  out.dropped_nodes = n;
  const Eigen::AlignedBox3d bounds = validator.samplingBounds();
  ++out.motion_checks;  // the root's state check is a check of the world too
  if (n == 0 || options.max_nodes == 1 || !bounds.contains(new_root_m) || !validator.isStateValid(new_root_m)) {
    return out;
  }
  auto motionValid = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    ++out.motion_checks;
    return validator.isMotionValid(a, b);
  };
  const auto& p = old_tree.positions_m;

  // The root links: the nearest old nodes inside the bounds, nearest first.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr std::uint32_t kFromRoot = kRrtTreeNoParent;
  std::vector<double> dist(n, kInf);
  std::vector<std::uint32_t> via(n, kRrtTreeNoParent);  // tentative parent (old index, or kFromRoot)
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  {
    std::vector<Entry> by_distance;
    by_distance.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (bounds.contains(p[i])) by_distance.emplace_back((p[i] - new_root_m).norm(), static_cast<std::uint32_t>(i));
    }
    const std::size_t tries = std::min(by_distance.size(), options.root_links + options.root_link_tries);
    std::partial_sort(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(tries), by_distance.end());
    for (std::size_t k = 0; k < tries && out.root_links < options.root_links; ++k) {
      const auto [d, i] = by_distance[k];
      if (!motionValid(new_root_m, p[i])) continue;
      ++out.root_links;
      dist[i] = d;
      via[i] = kFromRoot;
      open.emplace(d, i);
    }
  }

  // Cheapest-first from the root over the old edges, each checked the first time it could
  // shorten a branch (an edge is between two nodes, so it is checked at most once).
  const Adjacency adjacency(old_tree);
  std::vector<EdgeState> edge(n, EdgeState::kUnchecked);  // edge i: node i to its old parent
  std::vector<std::uint32_t> new_index(n, kRrtTreeNoParent);
  std::size_t popped = 0;
  while (!open.empty() && out.tree.size() < options.max_nodes) {
    const auto [d, u] = open.top();
    open.pop();
    if (new_index[u] != kRrtTreeNoParent || d > dist[u]) continue;
    if (++popped % 64 == 0 && stop.shouldStop()) {
      out.stopped = true;
      break;
    }
    new_index[u] = static_cast<std::uint32_t>(out.tree.size());
    out.tree.positions_m.push_back(p[u]);
    out.tree.parents.push_back(via[u] == kFromRoot ? 0 : new_index[via[u]]);
    out.tree.costs_m.push_back(d);
    for (std::uint32_t k = adjacency.first[u]; k < adjacency.first[u + 1]; ++k) {
      const std::uint32_t v = adjacency.to[k];
      if (new_index[v] != kRrtTreeNoParent || !bounds.contains(p[v])) continue;
      const double through_u = d + (p[v] - p[u]).norm();
      if (through_u >= dist[v]) continue;
      EdgeState& e = edge[std::max(u, v)];  // the child of the two holds the edge
      if (e == EdgeState::kUnchecked) {
        e = motionValid(p[u], p[v]) ? EdgeState::kValid : EdgeState::kBlocked;
        if (e == EdgeState::kBlocked) ++out.blocked_edges;
      }
      if (e == EdgeState::kBlocked) continue;
      dist[v] = through_u;
      via[v] = u;
      open.emplace(through_u, v);
    }
  }
  out.kept_nodes = out.tree.size() - 1;
  out.dropped_nodes = n - out.kept_nodes;
  return out;
}

RrtTree cheapestPart(const RrtTree& tree, std::size_t max_nodes) {
  if (tree.layoutError()) return {};
  if (tree.size() <= max_nodes) return tree;
  // By cost, ties by index: a parent comes before its children either way (zero-length edges
  // included), so the order is a valid layout and any prefix of it a tree.
  std::vector<std::uint32_t> order(tree.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(i);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return tree.costs_m[a] != tree.costs_m[b] ? tree.costs_m[a] < tree.costs_m[b] : a < b;
  });
  order.resize(max_nodes);
  std::vector<std::uint32_t> new_index(tree.size(), kRrtTreeNoParent);
  RrtTree out;
  for (std::uint32_t v : order) {
    const std::uint32_t parent = tree.parents[v];
    if (parent != kRrtTreeNoParent && new_index[parent] == kRrtTreeNoParent) continue;  // costs not monotone
    new_index[v] = static_cast<std::uint32_t>(out.size());
    out.positions_m.push_back(tree.positions_m[v]);
    out.parents.push_back(parent == kRrtTreeNoParent ? kRrtTreeNoParent : new_index[parent]);
    out.costs_m.push_back(tree.costs_m[v]);
  }
  return out;
}

}  // namespace skyroute
