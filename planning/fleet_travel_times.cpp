#include "planning/fleet_travel_times.hpp"

#include <chrono>

namespace skyroute {

std::vector<int> bfsDistanceMap4(const GridLayer& grid, GridCell source) {
  std::vector<int> dist(grid.cellCount(), kUnreachableSteps);
  if (grid.blocked(source)) return dist;
  std::vector<std::size_t> queue;
  queue.reserve(grid.cellCount());
  dist[grid.index(source)] = 0;
  queue.push_back(grid.index(source));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const GridCell c = grid.cellOf(queue[head]);
    const int next = dist[queue[head]] + 1;
    for (const GridCell& m : kFourMoves) {
      const GridCell n{c.x + m.x, c.y + m.y};
      if (grid.blocked(n)) continue;
      const std::size_t i = grid.index(n);
      if (dist[i] != kUnreachableSteps) continue;
      dist[i] = next;
      queue.push_back(i);
    }
  }
  return dist;
}

std::vector<GridCell> descendDistanceMap4(const GridLayer& grid, const std::vector<int>& distance_map, GridCell from) {
  std::vector<GridCell> path;
  if (!grid.inside(from) || distance_map[grid.index(from)] == kUnreachableSteps) return path;
  GridCell c = from;
  path.push_back(c);
  while (distance_map[grid.index(c)] > 0) {
    const int want = distance_map[grid.index(c)] - 1;
    for (const GridCell& m : kFourMoves) {
      const GridCell n{c.x + m.x, c.y + m.y};
      if (grid.inside(n) && distance_map[grid.index(n)] == want) {
        c = n;
        break;
      }
    }
    path.push_back(c);
  }
  return path;
}

TravelTimeTable TravelTimeTable::build(const GridLayer& grid, const FleetProblem& problem) {
  const auto start = std::chrono::steady_clock::now();
  TravelTimeTable table;
  const int nu = problem.vehicleCount();
  const int nt = problem.taskCount();
  for (const FleetVehicle& v : problem.vehicles) table.depot_maps_.push_back(bfsDistanceMap4(grid, v.depot));
  for (const FleetTask& t : problem.tasks) table.task_maps_.push_back(bfsDistanceMap4(grid, t.cell));
  auto at = [&](const std::vector<int>& map, GridCell c) {
    return grid.inside(c) ? map[grid.index(c)] : kUnreachableSteps;
  };
  table.depot_task_.resize(static_cast<std::size_t>(nu) * nt);
  table.task_task_.resize(static_cast<std::size_t>(nt) * nt);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nt; ++j) table.depot_task_[i * nt + j] = at(table.depot_maps_[i], problem.tasks[j].cell);
  }
  for (int a = 0; a < nt; ++a) {
    for (int b = 0; b < nt; ++b) table.task_task_[a * nt + b] = at(table.task_maps_[a], problem.tasks[b].cell);
  }
  table.build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return table;
}

}  // namespace skyroute
