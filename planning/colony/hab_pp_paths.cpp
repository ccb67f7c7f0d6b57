// HAB-PP's path operations: pruning while an ant walks and on arrival (string pulling, then vertex
// relocation), the path crossover, and the ranking value of eq. (2).
#include "planning/colony/hab_pp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planning/colony/hab_pp_detail.hpp"
#include "planning/grid/any_angle_search.hpp"

namespace skyroute::habpp {

namespace {
inline double dist(GridCell a, GridCell b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return std::sqrt(dx * dx + dy * dy);
}
}  // namespace

void pruneLastStep(const GridLayer& grid, Path& path) {
  while (path.size() >= 3 && grid.lineOfSight(path[path.size() - 3], path.back())) {
    path.erase(path.end() - 2);
  }
}

Path prunePath(const GridLayer& grid, const Path& path) {
  if (path.size() <= 2) return path;
  Path out{path.front()};
  std::size_t i = 0;
  while (i + 1 < path.size()) {
    std::size_t k = path.size() - 1;
    while (k > i + 1 && !grid.lineOfSight(path[i], path[k])) --k;
    if (!(path[k] == out.back())) out.push_back(path[k]);
    i = k;
  }
  return out;
}

Path tightenPath(const GridLayer& grid, const Path& path, int max_passes) {
  return relaxPruned(grid, prunePath(grid, path), max_passes);
}

Path relaxPruned(const GridLayer& grid, Path p, int max_passes) {
  struct Move {
    double length;
    GridCell to;
  };
  Move moves[8];
  for (int pass = 0; pass < max_passes; ++pass) {
    bool changed = false;
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
      const GridCell a = p[i - 1], b = p[i + 1];
      if (grid.lineOfSight(a, b)) {
        p.erase(p.begin() + static_cast<std::ptrdiff_t>(i));
        --i;
        changed = true;
        continue;
      }
      // The shortening moves, shortest first; the first whose segments are in sight wins.
      const double now = dist(a, p[i]) + dist(p[i], b);
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const GridCell q{p[i].x + dx, p[i].y + dy};
          if ((dx == 0 && dy == 0) || q == a || q == b || grid.blocked(q)) continue;
          const double len = dist(a, q) + dist(q, b);
          if (len < now - 1e-9) moves[n++] = Move{len, q};
        }
      }
      auto before = [](const Move& u, const Move& v) {
        return u.length != v.length ? u.length < v.length : (u.to.x != v.to.x ? u.to.x < v.to.x : u.to.y < v.to.y);
      };
      for (int k = 1; k < n; ++k) {  // insertion sort of at most 8
        for (int j = k; j > 0 && before(moves[j], moves[j - 1]); --j) std::swap(moves[j], moves[j - 1]);
      }
      for (int k = 0; k < n; ++k) {
        // From the moved vertex outwards: a move that fails is blocked next to the vertex (by the
        // corner it bends round), so the walk stops after a few cells instead of crossing the whole
        // segment first (lineOfSight is symmetric, so the answer is the same).
        if (grid.lineOfSight(moves[k].to, a) && grid.lineOfSight(moves[k].to, b)) {
          p[i] = moves[k].to;
          changed = true;
          break;
        }
      }
    }
    if (!changed) break;
  }
  return p;
}

namespace {

bool allSegmentsVisible(const GridLayer& grid, const Path& p) {
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (!grid.lineOfSight(p[i - 1], p[i])) return false;
  }
  return true;
}

Path joined(const Path& head, std::size_t head_last, GridCell via, const Path& tail, std::size_t tail_first) {
  Path out(head.begin(), head.begin() + static_cast<std::ptrdiff_t>(head_last + 1));
  if (!(out.back() == via)) out.push_back(via);
  for (std::size_t i = tail_first; i < tail.size(); ++i) {
    if (!(out.back() == tail[i])) out.push_back(tail[i]);
  }
  return out;
}

}  // namespace

std::vector<Path> crossover(const GridLayer& grid, const Path& a, const Path& b, int max_points) {
  std::vector<Path> children;
  if (a.size() < 2 || b.size() < 2 || max_points <= 0) return children;
  const GridCell start = a.front();
  const GridCell goal = a.back();
  // (cell index, segment of a touching it), sorted by cell and then segment, so the first entry
  // of a cell is the first segment of a touching it (a sorted vector: no hashing, one allocation).
  std::vector<std::pair<std::size_t, std::size_t>> segment_of_a;
  for (std::size_t s = 0; s + 1 < a.size(); ++s) {
    for (GridCell c : segmentCells(a[s], a[s + 1])) segment_of_a.emplace_back(grid.index(c), s);
  }
  std::sort(segment_of_a.begin(), segment_of_a.end());
  auto first_segment_of_a = [&](std::size_t cell) -> const std::size_t* {
    const auto it = std::lower_bound(segment_of_a.begin(), segment_of_a.end(), std::pair<std::size_t, std::size_t>{cell, 0});
    return it != segment_of_a.end() && it->first == cell ? &it->second : nullptr;
  };
  struct Crossing {
    GridCell cell;
    std::size_t seg_a;
    std::size_t seg_b;
  };
  std::vector<Crossing> crossings;
  bool in_run = false;
  for (std::size_t s = 0; s + 1 < b.size(); ++s) {
    for (GridCell c : segmentCells(b[s], b[s + 1])) {
      if (!grid.inside(c)) continue;
      const std::size_t* seg_a = first_segment_of_a(grid.index(c));
      const bool shared = seg_a != nullptr && !(c == start) && !(c == goal) && grid.passable(c);
      if (shared && !in_run) crossings.push_back({c, *seg_a, s});  // one crossing per run of shared cells
      in_run = shared;
    }
  }
  const std::size_t count = crossings.size();
  const std::size_t used = std::min<std::size_t>(count, static_cast<std::size_t>(max_points));
  for (std::size_t k = 0; k < used; ++k) {
    const Crossing& x = crossings[count <= used ? k : (2 * k + 1) * count / (2 * used)];
    for (Path child : {joined(a, x.seg_a, x.cell, b, x.seg_b + 1), joined(b, x.seg_b, x.cell, a, x.seg_a + 1)}) {
      if (child.front() == start && child.back() == goal && allSegmentsVisible(grid, child)) {
        children.push_back(prunePath(grid, child));
      }
    }
  }
  return children;
}

std::vector<double> evaluate(const std::vector<Path>& paths, const HabPpParameters& params) {
  std::vector<double> out(paths.size(), 0.0);
  if (paths.empty()) return out;
  const double wsum = params.w_length + params.w_angle + params.w_points;  // eq. (2) wants sum 1
  std::vector<double> fl(paths.size()), fa(paths.size()), fp(paths.size());
  double min_l = std::numeric_limits<double>::infinity(), min_a = min_l, min_p = min_l;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    fl[i] = std::max(polylineLength(paths[i]), 1e-12);
    fa[i] = polylineAngleChange(paths[i]) + params.angle_eval_epsilon_rad;
    fp[i] = static_cast<double>(paths[i].size());
    min_l = std::min(min_l, fl[i]);
    min_a = std::min(min_a, fa[i]);
    min_p = std::min(min_p, fp[i]);
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    out[i] = (params.w_length * min_l / fl[i] + params.w_angle * min_a / fa[i] + params.w_points * min_p / fp[i]) / wsum;
  }
  return out;
}

}  // namespace skyroute::habpp
