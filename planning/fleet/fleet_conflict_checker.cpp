#include "planning/fleet/fleet_conflict_checker.hpp"

#include <algorithm>
#include <cstdlib>
#include <optional>

namespace skyroute {

std::string FleetCheckReport::summary() const {
  std::string s;
  int shown = 0;
  for (const FleetConflict& c : conflicts) {
    if (shown++ == 3) break;
    s += std::string(c.kind == FleetConflict::Kind::kVertex ? "vertex" : "swap") + " conflict of agents " +
         std::to_string(c.a) + " and " + std::to_string(c.b) + " at step " + std::to_string(c.step) + " " +
         describeCell(c.cell) + "; ";
  }
  for (const std::string& v : violations) {
    if (shown++ >= 6) break;
    s += v + "; ";
  }
  if (shown == 0) return "no problems";
  return s;
}

FleetCheckReport checkFleetPlan(const GridLayer& grid, const FleetProblem& problem,
                                const std::vector<std::vector<GridCell>>& paths,
                                const std::vector<std::vector<int>>& sequences) {
  FleetCheckReport report;
  const int nu = problem.vehicleCount();
  const int nt = problem.taskCount();
  if (static_cast<int>(paths.size()) != nu || static_cast<int>(sequences.size()) != nu) {
    report.violations.push_back("expected " + std::to_string(nu) + " paths and sequences, got " +
                                std::to_string(paths.size()) + " and " + std::to_string(sequences.size()));
    return report;
  }
  auto cellAt = [&](int v, int t) {
    const auto& p = paths[static_cast<std::size_t>(v)];
    return p[static_cast<std::size_t>(std::min<std::size_t>(static_cast<std::size_t>(t), p.size() - 1))];
  };

  // Each path on its own.
  for (int v = 0; v < nu; ++v) {
    const auto& p = paths[static_cast<std::size_t>(v)];
    const std::string who = "vehicle " + problem.vehicles[static_cast<std::size_t>(v)].id;
    if (p.empty()) {
      report.violations.push_back(who + ": empty path");
      continue;
    }
    const GridCell depot = problem.vehicles[static_cast<std::size_t>(v)].depot;
    if (!(p.front() == depot)) report.violations.push_back(who + ": starts at " + describeCell(p.front()) + ", not its depot");
    if (!(p.back() == depot)) report.violations.push_back(who + ": ends at " + describeCell(p.back()) + ", not its depot");
    for (std::size_t t = 0; t < p.size(); ++t) {
      if (grid.blocked(p[t])) {
        report.violations.push_back(who + ": on blocked cell " + describeCell(p[t]) + " at step " + std::to_string(t));
      }
      if (t > 0 && std::abs(p[t].x - p[t - 1].x) + std::abs(p[t].y - p[t - 1].y) > 1) {
        report.violations.push_back(who + ": jumps from " + describeCell(p[t - 1]) + " to " + describeCell(p[t]) +
                                    " at step " + std::to_string(t));
      }
    }
  }
  if (!report.violations.empty()) return report;  // conflicts are meaningless on broken paths

  // Tasks: each exactly once, within capacity, on the path in the given order.
  std::vector<int> times_assigned(static_cast<std::size_t>(nt), 0);
  for (int v = 0; v < nu; ++v) {
    const auto& seq = sequences[static_cast<std::size_t>(v)];
    const std::string who = "vehicle " + problem.vehicles[static_cast<std::size_t>(v)].id;
    if (static_cast<int>(seq.size()) > problem.capacity(v)) {
      report.violations.push_back(who + ": " + std::to_string(seq.size()) + " tasks exceed its capacity " +
                                  std::to_string(problem.capacity(v)));
    }
    std::size_t t = 0;
    const auto& p = paths[static_cast<std::size_t>(v)];
    for (int j : seq) {
      if (j < 0 || j >= nt) {
        report.violations.push_back(who + ": task index " + std::to_string(j) + " out of range");
        continue;
      }
      ++times_assigned[static_cast<std::size_t>(j)];
      const GridCell want = problem.tasks[static_cast<std::size_t>(j)].cell;
      while (t < p.size() && !(p[t] == want)) ++t;
      if (t == p.size()) {
        report.violations.push_back(who + ": path does not visit task " + problem.tasks[static_cast<std::size_t>(j)].id +
                                    " " + describeCell(want) + " in its turn");
        t = 0;
      }
    }
  }
  for (int j = 0; j < nt; ++j) {
    if (times_assigned[static_cast<std::size_t>(j)] != 1) {
      report.violations.push_back("task " + problem.tasks[static_cast<std::size_t>(j)].id + " is assigned " +
                                  std::to_string(times_assigned[static_cast<std::size_t>(j)]) + " times");
    }
  }

  // Pairs of vehicles, and vehicles against moving obstacles, at every step until all is still.
  int end = 0;
  for (const auto& p : paths) end = std::max(end, static_cast<int>(p.size()) - 1);
  for (const MovingObstacle& o : problem.moving_obstacles) end = std::max(end, o.endStep());
  for (int t = 0; t <= end; ++t) {
    for (int a = 0; a < nu; ++a) {
      for (int b = a + 1; b < nu; ++b) {
        if (cellAt(a, t) == cellAt(b, t)) {
          report.conflicts.push_back({FleetConflict::Kind::kVertex, a, b, t, cellAt(a, t)});
        }
        if (t > 0 && cellAt(a, t - 1) == cellAt(b, t) && cellAt(b, t - 1) == cellAt(a, t) &&
            !(cellAt(a, t) == cellAt(a, t - 1))) {
          report.conflicts.push_back({FleetConflict::Kind::kSwap, a, b, t, cellAt(a, t)});
        }
      }
      for (std::size_t k = 0; k < problem.moving_obstacles.size(); ++k) {
        const MovingObstacle& o = problem.moving_obstacles[k];
        const int b = nu + static_cast<int>(k);
        const std::optional<GridCell> now = o.cellAt(t);
        const std::optional<GridCell> before = o.cellAt(t - 1);
        if (now && *now == cellAt(a, t)) report.conflicts.push_back({FleetConflict::Kind::kVertex, a, b, t, cellAt(a, t)});
        if (t > 0 && now && before && *before == cellAt(a, t) && *now == cellAt(a, t - 1) &&
            !(*now == *before)) {
          report.conflicts.push_back({FleetConflict::Kind::kSwap, a, b, t, cellAt(a, t)});
        }
      }
    }
  }
  return report;
}

}  // namespace skyroute
