#include "planning/colony/hab_pp.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <queue>
#include <string>

#include "planning/colony/hab_pp_output.hpp"
#include "planning/colony/hab_pp_rrt.hpp"
#include "planning/grid/any_angle_search.hpp"

namespace skyroute {

std::string_view to_string(HabPpStatus status) {
  switch (status) {
    case HabPpStatus::kConverged: return "converged";
    case HabPpStatus::kStoppedWithPath: return "stopped with path";
    case HabPpStatus::kStoppedWithoutPath: return "stopped without path";
    case HabPpStatus::kInvalidStart: return "invalid start";
    case HabPpStatus::kInvalidGoal: return "invalid goal";
    case HabPpStatus::kUnreachable: return "unreachable";
    case HabPpStatus::kInvalidParameters: return "invalid parameters";
  }
  return "unknown";
}

Status HabPpParameters::validate() const {
  auto bad = [](const char* field, const std::string& why) {
    return Status(make_error(ErrorCode::kInvalidArgument, field, std::string(field) + ": " + why));
  };
  const std::pair<const char*, int> counts[] = {
      {"simple_ants", simple_ants},         {"general_ants", general_ants},
      {"far_sighted_ants", far_sighted_ants}, {"sight_general_ants", sight_general_ants},
      {"sight_far_sighted_ants", sight_far_sighted_ants}, {"rrt_ants", rrt_ants},
      {"crossover_paths", crossover_paths}, {"max_ant_steps", max_ant_steps},
      {"crossover_points", crossover_points}, {"tighten_passes", tighten_passes}};
  for (const auto& [field, value] : counts) {
    if (value < 0) return bad(field, "must be >= 0, got " + std::to_string(value));
  }
  if (totalAnts() + rrt_ants == 0) return bad("simple_ants", "the colony has no ant of any species");
  if (ranked_paths < 1) return bad("ranked_paths", "must be >= 1");
  const std::pair<const char*, double> non_negative[] = {
      {"alpha", alpha}, {"beta", beta}, {"gamma", gamma}, {"w_length", w_length}, {"w_angle", w_angle},
      {"w_points", w_points}};
  for (const auto& [field, value] : non_negative) {
    if (!std::isfinite(value) || value < 0.0) return bad(field, "must be finite and >= 0");
  }
  if (!(w_length + w_angle + w_points > 0.0)) return bad("w_length", "the weights of eq. (2) sum to 0");
  if (!(rho > 0.0 && rho < 1.0)) return bad("rho", "must lie in (0, 1)");
  if (!(k_mix >= 0.0 && k_mix <= 1.0)) return bad("k_mix", "must lie in [0, 1]");
  if (!(d0_cells > 0.0) || !std::isfinite(d0_cells)) return bad("d0_cells", "must be > 0");
  if (!(rrt_step_cells >= 1.0) || !std::isfinite(rrt_step_cells)) return bad("rrt_step_cells", "must be >= 1");
  if (!(rrt_near_radius_cells >= 1.0) || !std::isfinite(rrt_near_radius_cells)) {
    return bad("rrt_near_radius_cells", "must be >= 1");
  }
  if (general_radius < 1) return bad("general_radius", "must be >= 1");
  if (far_sighted_radius < 1) return bad("far_sighted_radius", "must be >= 1");
  if (sight_max_radius < std::max(general_radius, far_sighted_radius)) {
    return bad("sight_max_radius", "must be >= general_radius and far_sighted_radius");
  }
  if (!(pheromone_min > 0.0 && pheromone_min <= pheromone_max) || !std::isfinite(pheromone_max)) {
    return bad("pheromone_min", "need 0 < pheromone_min <= pheromone_max");
  }
  if (!(angle_factor_floor > 0.0 && angle_factor_floor <= 1.0)) return bad("angle_factor_floor", "must lie in (0, 1]");
  if (!(angle_eval_epsilon_rad > 0.0) || !std::isfinite(angle_eval_epsilon_rad)) {
    return bad("angle_eval_epsilon_rad", "must be > 0");
  }
  if (output_corridor_cells < -1) return bad("output_corridor_cells", "must be >= -1");
  if (!(output_window_cells >= 0.0) || !std::isfinite(output_window_cells)) {
    return bad("output_window_cells", "must be >= 0 (0: no windowed re-planning)");
  }
  if (output_window_segments < 0) return bad("output_window_segments", "must be >= 0 (0: no windowed re-planning)");
  if (output_window_margin_cells < 0) return bad("output_window_margin_cells", "must be >= 0");
  if (output_ranked_routes < 1) return bad("output_ranked_routes", "must be >= 1");
  if (stable_iterations < 1) return bad("stable_iterations", "must be >= 1");
  if (rrt_nodes_after_solution < 0) return bad("rrt_nodes_after_solution", "must be >= 0 (0: never restart)");
  if (rrt_draws_per_step < 1) return bad("rrt_draws_per_step", "must be >= 1");
  if (rrt_node_redraws < 0) return bad("rrt_node_redraws", "must be >= 0");
  if (rrt_ants_join_tree && !rrt_tree_from_goal) {
    return bad("rrt_ants_join_tree", "needs rrt_tree_from_goal (an ant can only finish along a tree that ends at the goal)");
  }
  return Status::success();
}

namespace habpp {

namespace {
// x^e for the exponents of eq. (1): the paper's 2, 1 and 1 need no std::pow, which otherwise
// dominates the ants' innermost loop.
inline double powExponent(double x, double e) {
  if (e == 1.0) return x;
  if (e == 2.0) return x * x;
  if (e == 0.0) return 1.0;
  return std::pow(x, e);
}
inline double dist(GridCell a, GridCell b) {
  const double dx = a.x - b.x, dy = a.y - b.y;
  return std::sqrt(dx * dx + dy * dy);
}
}  // namespace

// ---- geometry ------------------------------------------------------------------------------------

std::vector<GridCell> segmentCells(GridCell a, GridCell b) { return GridLayer::segmentCells(a, b); }

// ---- fields --------------------------------------------------------------------------------------

namespace {
// Shortest 8-connected distances (1 and sqrt 2, no corner cutting) from goal to every free cell;
// infinity for blocked and unreachable cells.
std::vector<double> geodesicDistances(const GridLayer& grid, GridCell goal) {
  std::vector<double> d(grid.cellCount(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  d[grid.index(goal)] = 0.0;
  open.emplace(0.0, grid.index(goal));
  while (!open.empty()) {
    const auto [dc, i] = open.top();
    open.pop();
    if (dc > d[i]) continue;
    const GridCell c = grid.cellOf(i);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const GridCell n{c.x + dx, c.y + dy};
        if ((dx == 0 && dy == 0) || grid.blocked(n)) continue;
        if (dx != 0 && dy != 0 && (grid.blocked(GridCell{c.x + dx, c.y}) || grid.blocked(GridCell{c.x, c.y + dy}))) {
          continue;
        }
        const double nd = dc + (dx != 0 && dy != 0 ? std::sqrt(2.0) : 1.0);
        if (nd < d[grid.index(n)]) {
          d[grid.index(n)] = nd;
          open.emplace(nd, grid.index(n));
        }
      }
    }
  }
  return d;
}
}  // namespace

GridFields::GridFields(const GridLayer& grid, GridCell goal, const HabPpParameters& params)
    : grid_(&grid), goal_(goal), visibility_(grid.cellCount(), 0.0) {
  const int w = grid.width();
  const int h = grid.height();
  blocked_prefix_.assign(static_cast<std::size_t>(w + 1) * (h + 1), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y + 1) * (w + 1) + (x + 1);
      blocked_prefix_[i] = (grid.blocked(GridCell{x, y}) ? 1 : 0) + blocked_prefix_[i - 1] +
                           blocked_prefix_[i - (w + 1)] - blocked_prefix_[i - (w + 1) - 1];
    }
  }
  double far = 1.0;
  std::vector<double> to_goal;
  if (params.geodesic_visibility) {
    to_goal = geodesicDistances(grid, goal);
    for (double d : to_goal) {
      if (std::isfinite(d)) far = std::max(far, d);
    }
  } else {
    for (GridCell corner : {GridCell{0, 0}, GridCell{w - 1, 0}, GridCell{0, h - 1}, GridCell{w - 1, h - 1}}) {
      far = std::max(far, std::hypot(double(corner.x - goal.x), double(corner.y - goal.y)));
    }
  }
  const int reach = static_cast<int>(std::ceil(params.d0_cells));
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const GridCell c{x, y};
      const double to_goal_cells = params.geodesic_visibility ? std::min(to_goal[grid.index(c)], far)
                                                              : std::hypot(double(x - goal.x), double(y - goal.y));
      const double closeness = 1.0 - to_goal_cells / far;
      // Distance to the nearest blocked cell centre, exact up to d_0 (only that range matters).
      double nearest = params.d0_cells;
      for (int oy = -reach; oy <= reach; ++oy) {
        for (int ox = -reach; ox <= reach; ++ox) {
          const GridCell o{x + ox, y + oy};
          if (grid.inside(o) && grid.blocked(o)) nearest = std::min(nearest, std::hypot(double(ox), double(oy)));
        }
      }
      const double clearance = nearest / params.d0_cells;
      visibility_[grid.index(c)] = std::max(1e-3, params.k_mix * closeness + (1.0 - params.k_mix) * clearance);
    }
  }
}

bool GridFields::windowFree(GridCell c, int r) const {
  const int w = grid_->width();
  const int x0 = c.x - r, y0 = c.y - r, x1 = c.x + r + 1, y1 = c.y + r + 1;
  if (x0 < 0 || y0 < 0 || x1 > w || y1 > grid_->height()) return false;
  auto at = [&](int x, int y) { return blocked_prefix_[static_cast<std::size_t>(y) * (w + 1) + x]; };
  return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0) == 0;
}

namespace {
// The points of the border of the window of radius r around at, in candidates()' order.
template <class Visit>
void forBorder(GridCell at, int r, Visit&& visit) {
  for (int dx = -r; dx <= r; ++dx) {
    visit(GridCell{at.x + dx, at.y - r});
    visit(GridCell{at.x + dx, at.y + r});
  }
  for (int dy = -r + 1; dy <= r - 1; ++dy) {
    visit(GridCell{at.x - r, at.y + dy});
    visit(GridCell{at.x + r, at.y + dy});
  }
}
}  // namespace

std::uint32_t GridFields::borderSight(GridCell c, int r) const {
  const std::size_t slot = grid_->index(c) * (kMaxCachedRadius - 1) + static_cast<std::size_t>(r - 2);
  const std::uint8_t bit = static_cast<std::uint8_t>(1u << (r - 2));
  if (border_sight_.empty()) {
    border_sight_.assign(grid_->cellCount() * (kMaxCachedRadius - 1), 0);
    border_known_.assign(grid_->cellCount(), 0);
  }
  std::uint8_t& known = border_known_[grid_->index(c)];
  if ((known & bit) == 0) {
    std::uint32_t mask = 0;
    int k = 0;
    forBorder(c, r, [&](GridCell q) {
      if (grid_->passable(q) && grid_->lineOfSight(c, q)) mask |= 1u << k;
      ++k;
    });
    border_sight_[slot] = mask;
    known |= bit;
  }
  return border_sight_[slot];
}

int sightRadius(const GridFields& fields, GridCell at, int base_radius, bool expanding, int max_radius) {
  int r = base_radius;
  if (!expanding) return r;
  while (r < max_radius && fields.windowFree(at, r + 1)) ++r;
  return r;
}

std::vector<GridCell> candidates(const GridFields& fields, GridCell at, int radius,
                                 const std::vector<std::uint8_t>& visited) {
  std::vector<GridCell> out;
  candidates(fields, at, radius, visited, out);
  return out;
}

void candidates(const GridFields& fields, GridCell at, int radius, const std::vector<std::uint8_t>& visited,
                std::vector<GridCell>& out) {
  const GridLayer& grid = fields.grid();
  const GridCell goal = fields.goal();
  out.clear();
  if (std::max(std::abs(goal.x - at.x), std::abs(goal.y - at.y)) <= radius && grid.lineOfSight(at, goal)) {
    out.push_back(goal);
    return;
  }
  for (int r = radius; r >= 1; --r) {
    // A free window makes every border point visible (the segment stays inside the free square).
    const bool window_free = fields.windowFree(at, r);
    // Radius 1 (the simple ants, most of the colony): the segment to a side neighbour touches only
    // the two cells, to a diagonal one also the two cells beside the corner, so lineOfSight
    // reduces to those tests.
    // Radii 2 to 4 read the cached border mask (GridFields::borderSight).
    const bool cached = !window_free && r >= 2 && r <= GridFields::kMaxCachedRadius;
    const std::uint32_t mask = cached ? fields.borderSight(at, r) : 0;
    int k = 0;
    auto visible = [&](GridCell c) {
      if (window_free) return true;
      if (cached) return ((mask >> k) & 1u) != 0;
      if (r > 1) return grid.lineOfSight(at, c);
      return c.x == at.x || c.y == at.y ||
             (grid.passable(GridCell{c.x, at.y}) && grid.passable(GridCell{at.x, c.y}));
    };
    forBorder(at, r, [&](GridCell c) {
      if (!grid.blocked(c) && visited[grid.index(c)] == 0 && visible(c)) out.push_back(c);
      ++k;
    });
    if (!out.empty()) return;
  }
}

double angleFactor(double heading_x, double heading_y, GridCell at, GridCell to, double floor) {
  const double sx = to.x - at.x;
  const double sy = to.y - at.y;
  const double hn = std::sqrt(heading_x * heading_x + heading_y * heading_y);
  const double sn = std::sqrt(sx * sx + sy * sy);
  if (hn == 0.0 || sn == 0.0) return 1.0;
  const double cos_theta = (heading_x * sx + heading_y * sy) / (hn * sn);
  return std::max(floor, 0.5 * (1.0 + cos_theta));
}

std::size_t rouletteSelect(const std::vector<double>& weights, Rng& rng) {
  double sum = 0.0;
  for (double w : weights) sum += w;
  const double r = std::uniform_real_distribution<double>(0.0, sum)(rng);
  double acc = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    acc += weights[i];
    if (r < acc) return i;
  }
  // Rounding can leave r == sum: the last index with a positive weight.
  for (std::size_t i = weights.size(); i-- > 0;) {
    if (weights[i] > 0.0) return i;
  }
  return weights.size() - 1;
}

// ---- pruning and crossover -----------------------------------------------------------------------

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

namespace {
// tightenPath after its greedy pruning, for paths that are already pruned (prunePath is
// idempotent: after a pass no kept point sees a later one beyond its successor), such as the
// crossover's children.
Path relaxPruned(const GridLayer& grid, Path p, int max_passes);
}  // namespace

Path tightenPath(const GridLayer& grid, const Path& path, int max_passes) {
  return relaxPruned(grid, prunePath(grid, path), max_passes);
}

namespace {
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
}  // namespace

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

// ---- evaluation and pheromone --------------------------------------------------------------------

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

PheromoneField::PheromoneField(const GridFields& fields, const HabPpParameters& params)
    : fields_(&fields), params_(params), tau_(fields.grid().cellCount()), stamp_(fields.grid().cellCount(), 0),
      in_active_(fields.grid().cellCount(), 0) {
  const GridLayer& grid = fields.grid();
  for (std::size_t i = 0; i < tau_.size(); ++i) {
    const GridCell c = grid.cellOf(i);
    // Choice: blocked cells start (and stay) at the floor: no ant or sample reads them and no path
    // deposits on them, so the update and the sampling need not look at them.
    tau_[i] = grid.passable(c) ? std::clamp(fields.visibility(c), params.pheromone_min, params.pheromone_max)
                               : params.pheromone_min;
    if (grid.passable(c)) free_cells_.push_back(i);
    if (tau_[i] > params.pheromone_min) {
      in_active_[i] = 1;
      active_.push_back(static_cast<std::uint32_t>(i));
    }
  }
  if (params.rrt_ants > 0 && params.rrt_sample_visibility) {
    eta_beta_.assign(tau_.size(), 0.0);
    floor_eta_cumulative_.reserve(free_cells_.size());
    double sum = 0.0;
    for (std::size_t i : free_cells_) {
      eta_beta_[i] = powExponent(fields.visibility(grid.cellOf(i)), params.beta);
      sum += eta_beta_[i];
      floor_eta_cumulative_.push_back(sum);
    }
  }
}

void PheromoneField::nextStamp() {
  if (++stamp_now_ == 0) {  // wrapped: clear the stamps once
    std::fill(stamp_.begin(), stamp_.end(), 0);
    stamp_now_ = 1;
  }
}

std::vector<std::uint32_t> PheromoneField::pathCells(const Path& path) {
  const GridLayer& grid = fields_->grid();
  std::vector<std::uint32_t> cells;
  nextStamp();
  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    for (GridCell c : segmentCells(path[s], path[s + 1])) {  // Fig. 3: the cells between points too
      if (!grid.inside(c)) continue;
      const std::size_t i = grid.index(c);
      if (stamp_[i] == stamp_now_) continue;
      stamp_[i] = stamp_now_;
      cells.push_back(static_cast<std::uint32_t>(i));
    }
  }
  return cells;
}

void PheromoneField::update(const std::vector<Path>& ranked, const std::vector<double>& evaluation) {
  std::vector<std::vector<std::uint32_t>> cells;
  cells.reserve(ranked.size());
  for (const Path& p : ranked) cells.push_back(pathCells(p));
  updateCells(cells, evaluation);
}

void PheromoneField::updateCells(const std::vector<std::vector<std::uint32_t>>& ranked_cells,
                                 const std::vector<double>& evaluation) {
  const double keep = 1.0 - params_.rho;
  for (std::uint32_t i : active_) tau_[i] *= keep;
  for (std::size_t k = 0; k < ranked_cells.size(); ++k) {
    const double deposit = params_.rho * evaluation[k];
    for (std::uint32_t i : ranked_cells[k]) {
      if (in_active_[i] == 0) {  // at the floor: evaporate it here, as the full pass would have
        in_active_[i] = 1;
        active_.push_back(i);
        tau_[i] *= keep;
      }
      tau_[i] += deposit;
    }
  }
  std::size_t kept = 0;
  for (std::uint32_t i : active_) {
    tau_[i] = std::clamp(tau_[i], params_.pheromone_min, params_.pheromone_max);
    if (tau_[i] > params_.pheromone_min) {
      active_[kept++] = i;
    } else {
      in_active_[i] = 0;
    }
  }
  active_.resize(kept);
  excess_table_ = ExcessTable::kStale;
}

GridCell PheromoneField::sample(Rng& rng) const { return sampleWeighted(rng, false); }

GridCell PheromoneField::sampleWithVisibility(Rng& rng) const {
  // eta^beta is tabulated only for a colony with RRT* ants and rrt_sample_visibility.
  return sampleWeighted(rng, !floor_eta_cumulative_.empty());
}

GridCell PheromoneField::sampleWeighted(Rng& rng, bool with_eta) const {
  const GridLayer& grid = fields_->grid();
  const double floor_weight = powExponent(params_.pheromone_min, params_.alpha);
  const ExcessTable wanted = with_eta ? ExcessTable::kWithEta : ExcessTable::kPheromoneOnly;
  if (excess_table_ != wanted) {
    excess_cells_.clear();
    excess_cumulative_.clear();
    double sum = 0.0;
    excess_cells_.reserve(active_.size());
    excess_cumulative_.reserve(active_.size());
    for (std::uint32_t i : active_) {  // all free: blocked cells stay at the floor
      sum += (powExponent(tau_[i], params_.alpha) - floor_weight) * (with_eta ? eta_beta_[i] : 1.0);
      excess_cells_.push_back(i);
      excess_cumulative_.push_back(sum);
    }
    excess_table_ = wanted;
  }
  const double excess = excess_cumulative_.empty() ? 0.0 : excess_cumulative_.back();
  const double floor_sum = with_eta ? floor_eta_cumulative_.back() : static_cast<double>(free_cells_.size());
  const double r = std::uniform_real_distribution<double>(0.0, excess + floor_weight * floor_sum)(rng);
  if (r < excess) {
    const auto it = std::upper_bound(excess_cumulative_.begin(), excess_cumulative_.end(), r);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - excess_cumulative_.begin()),
                                                excess_cells_.size() - 1);
    return grid.cellOf(excess_cells_[k]);
  }
  const double at = (r - excess) / floor_weight;  // a position in the floor part, in floor cells
  const std::size_t k =
      with_eta ? static_cast<std::size_t>(std::upper_bound(floor_eta_cumulative_.begin(), floor_eta_cumulative_.end(), at) -
                                          floor_eta_cumulative_.begin())
               : static_cast<std::size_t>(at);
  return grid.cellOf(free_cells_[std::min<std::size_t>(k, free_cells_.size() - 1)]);
}

// ---- the colony ----------------------------------------------------------------------------------

namespace {

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
  Colony(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params, std::uint64_t seed)
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

  // One iteration n_I of Table 2 (lines 6-27). Returns whether the ranked list changed, as the
  // stopping rule counts it (see HabPpParameters::rrt_stop_top_paths).
  bool iterate(Rng& rng, HabPpResult& stats) {
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

  const std::vector<Path>& ranked() const { return ranked_; }
  // The shortest path that has been in the ranked list at any iteration (eq. (2) may have pushed
  // it out since for paths with fewer points or less turning).
  const Path& shortestRanked() const { return shortest_ranked_; }
  // The shortest path the RRT* species has brought (pruned as on arrival); empty if none.
  const Path& bestTreePath() const { return best_tree_path_; }

 private:
  void restart(Ant& ant) {
    for (std::size_t i : ant.marked) ant.visited[i] = 0;
    ant.marked.clear();
    ant.path.assign(1, start_);
    mark(ant, start_);
    ant.steps = 0;
  }
  void mark(Ant& ant, GridCell c) {
    const std::size_t i = grid_.index(c);
    if (ant.visited[i] == 0) {
      ant.visited[i] = 1;
      ant.marked.push_back(i);
    }
  }

  // Lines 10-18 of Table 2 for one ant: choose j by eq. (1), move, prune; a path on arrival.
  std::optional<Path> step(Ant& ant, Rng& rng) {
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

  // Lines 23-25: evaluate (eq. 2), sort, drop duplicates, cut to N_R. entered[origin] is set when
  // a path of that origin that was not in the list before is in it now.
  bool rank(std::vector<Path>& pool, const std::vector<Origin>& origin, bool entered[3]) {
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

// 8-connected flood fill without corner cutting: exactly the cells an any-angle path can reach,
// since a segment that passes lineOfSight steps through side- or corner-adjacent free cells.
bool connected(const GridLayer& grid, GridCell start, GridCell goal) {
  std::vector<std::uint8_t> seen(grid.cellCount(), 0);
  std::deque<GridCell> queue{start};
  seen[grid.index(start)] = 1;
  while (!queue.empty()) {
    const GridCell c = queue.front();
    queue.pop_front();
    if (c == goal) return true;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const GridCell n{c.x + dx, c.y + dy};
        if ((dx == 0 && dy == 0) || grid.blocked(n) || seen[grid.index(n)] != 0) continue;
        if (dx != 0 && dy != 0 && (grid.blocked(GridCell{c.x + dx, c.y}) || grid.blocked(GridCell{c.x, c.y + dy}))) {
          continue;
        }
        seen[grid.index(n)] = 1;
        queue.push_back(n);
      }
    }
  }
  return false;
}

}  // namespace
}  // namespace habpp

HabPpResult planHabPp(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params,
                      std::uint64_t seed, const TerminationCondition& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  auto cpu_seconds = [&] { return static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC; };
  HabPpResult result;
  auto fail = [&](HabPpStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.total_time_s = seconds();
    result.total_cpu_s = cpu_seconds();
    return result;
  };
  if (const Status valid = params.validate(); !valid) return fail(HabPpStatus::kInvalidParameters, valid.error().describe());
  auto where = [](GridCell c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; };
  if (!grid.inside(start)) return fail(HabPpStatus::kInvalidStart, "start: " + where(start) + " is outside the grid");
  if (grid.blocked(start)) return fail(HabPpStatus::kInvalidStart, "start: " + where(start) + " is blocked");
  if (!grid.inside(goal)) return fail(HabPpStatus::kInvalidGoal, "goal: " + where(goal) + " is outside the grid");
  if (grid.blocked(goal)) return fail(HabPpStatus::kInvalidGoal, "goal: " + where(goal) + " is blocked");
  if (start == goal) {
    result.status = HabPpStatus::kConverged;
    result.path = {start};
    result.first_path_time_s = seconds();
    result.total_time_s = result.first_path_time_s;
    return result;
  }
  if (!habpp::connected(grid, start, goal)) {
    return fail(HabPpStatus::kUnreachable, "goal: no free path joins start " + where(start) + " and goal " + where(goal));
  }

  habpp::Rng rng(seed);
  habpp::Colony colony(grid, start, goal, params, seed);
  int unchanged = 0;
  int unchanged_with_arrivals = 0;
  for (;;) {
    const auto reason = stop.reason(result.iterations);
    if (reason != TerminationCondition::Reason::kNone) {
      result.stop_reason = reason;
      result.status = colony.ranked().empty() ? HabPpStatus::kStoppedWithoutPath : HabPpStatus::kStoppedWithPath;
      break;
    }
    ++result.iterations;
    const std::uint64_t arrivals_before = result.ant_arrivals + result.rrt_arrivals;
    const bool changed = colony.iterate(rng, result);
    if (result.first_path_time_s < 0.0 && !colony.ranked().empty()) {
      result.first_path_time_s = seconds();
      result.first_path_cpu_s = cpu_seconds();
      result.first_path_iteration = result.iterations;
      result.first_path_by_rrt = result.rrt_arrivals > 0;
      result.first_path_by_join = result.joined_arrivals > 0;
    }
    // Table 2's termination: the ranked list stops changing. Choice: unchanged for
    // stable_iterations iterations once it holds N_R paths; while it holds fewer (a small map may
    // not have N_R distinct paths), unchanged for stable_iterations iterations in which some path
    // arrived, so a long search for the first few paths does not end the plan.
    const bool arrived = result.ant_arrivals + result.rrt_arrivals > arrivals_before;
    unchanged = changed ? 0 : unchanged + 1;
    unchanged_with_arrivals = changed ? 0 : unchanged_with_arrivals + (arrived ? 1 : 0);
    const bool full = colony.ranked().size() >= static_cast<std::size_t>(params.ranked_paths);
    if (!colony.ranked().empty() &&
        (full ? unchanged >= params.stable_iterations : unchanged_with_arrivals >= params.stable_iterations)) {
      result.status = HabPpStatus::kConverged;
      break;
    }
  }
  if (!colony.ranked().empty()) {
    result.ranked_length_cells = polylineLength(colony.ranked().front());
    const std::vector<habpp::Path>& ranked = colony.ranked();
    const std::size_t count = std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(params.output_ranked_routes));
    std::vector<habpp::Path> routes(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(count));
    auto offer = [&routes](const habpp::Path& route) {
      if (!route.empty() && std::find(routes.begin(), routes.end(), route) == routes.end()) routes.push_back(route);
    };
    if (params.output_ranked_routes > 1) offer(colony.shortestRanked());
    if (params.output_tree_route) offer(colony.bestTreePath());
    result.path = params.output_corridor_cells >= 0
                      ? habpp::tautPath(grid, routes, params.output_corridor_cells, params.tighten_passes)
                      : ranked.front();
    result.path = habpp::replanWindows(grid, result.path,
                                       habpp::WindowOptions{.segments = params.output_window_segments,
                                                            .span_cells = params.output_window_cells,
                                                            .margin_cells = params.output_window_margin_cells},
                                       params.tighten_passes);
    result.length_cells = polylineLength(result.path);
    result.angle_change_rad = polylineAngleChange(result.path);
  } else {
    result.message = "no ant reached the goal before the termination condition (" +
                     std::string(to_string(result.stop_reason)) + ")";
  }
  result.total_time_s = seconds();
  result.total_cpu_s = cpu_seconds();
  return result;
}

}  // namespace skyroute
