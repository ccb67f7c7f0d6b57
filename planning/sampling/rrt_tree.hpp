// An RRT* tree as plain data, for a planner run to hand on to the next one (tree reuse on
// replanning, rrt_tree_reuse.hpp): node 0 is the root; every other node's parent comes before it,
// so a tree is rebuilt in one pass in index order; costs are the path lengths from the root along
// the parents.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace skyroute {

inline constexpr std::uint32_t kRrtTreeNoParent = std::numeric_limits<std::uint32_t>::max();

struct RrtTree {
  std::vector<Eigen::Vector3d> positions_m;
  std::vector<std::uint32_t> parents;  // parents[0] = kRrtTreeNoParent, parents[i] < i
  std::vector<double> costs_m;         // path length from the root, metres

  std::size_t size() const { return positions_m.size(); }
  bool empty() const { return positions_m.empty(); }

  // Why the tree breaks the layout above (nullopt when it does not): lengths differ, a parent
  // comes after its child, a position or a cost is not finite.
  std::optional<std::string> layoutError() const {
    if (parents.size() != positions_m.size() || costs_m.size() != positions_m.size()) {
      return "positions_m, parents and costs_m differ in length";
    }
    for (std::size_t i = 0; i < positions_m.size(); ++i) {
      if (!positions_m[i].allFinite() || !std::isfinite(costs_m[i])) {
        return "node " + std::to_string(i) + " has a position or cost that is not finite";
      }
      if (i == 0 ? parents[i] != kRrtTreeNoParent : parents[i] >= i) {
        return "node " + std::to_string(i) + "'s parent does not come before it";
      }
    }
    return std::nullopt;
  }
};

}  // namespace skyroute
