#include "planning/fleet/fleet_problem.hpp"

#include <cstdlib>
#include <map>
#include <set>
#include <utility>

#include "planning/fleet/fleet_travel_times.hpp"

namespace skyroute {

std::string describeCell(GridCell c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; }

std::optional<GridCell> MovingObstacle::cellAt(int step) const {
  if (step < start_step || step >= endStep()) return std::nullopt;
  return cells[static_cast<std::size_t>(step - start_step)];
}

MovingObstacle MovingObstacle::straight(std::string id, GridCell start, int dx, int dy, int start_step, int steps) {
  MovingObstacle o;
  o.id = std::move(id);
  o.start_step = start_step;
  for (int k = 0; k <= steps; ++k) o.cells.push_back(GridCell{start.x + k * dx, start.y + k * dy});
  return o;
}

int FleetProblem::capacity(int i) const {
  const int limit = vehicles[static_cast<std::size_t>(i)].max_tasks;
  return limit > 0 ? limit : taskCount();
}

namespace {

Status checkCell(const GridLayer& grid, GridCell c, const std::string& field) {
  if (!grid.inside(c)) {
    return make_error(ErrorCode::kOutsideMap, field,
                      describeCell(c) + " lies outside the " + std::to_string(grid.width()) + " x " +
                          std::to_string(grid.height()) + " grid");
  }
  if (grid.blocked(c)) return make_error(ErrorCode::kOccupied, field, describeCell(c) + " is blocked");
  return Status::success();
}

// How errors name a vehicle or task: by its id, or by its position when the id is empty.
std::string placeField(const std::string& kind, std::size_t position, const std::string& id) {
  return kind + " " + (id.empty() ? "#" + std::to_string(position) : id);
}

// An id must be given and unique among its kind (`seen` holds the ids so far).
Status checkId(const std::string& kind, const std::string& field, const std::string& id, std::set<std::string>& seen) {
  if (id.empty()) return make_error(ErrorCode::kInvalidArgument, field, "empty id");
  if (!seen.insert(id).second) return make_error(ErrorCode::kInvalidArgument, field, "duplicate " + kind + " id '" + id + "'");
  return Status::success();
}

}  // namespace

Status validateFleetProblem(const GridLayer& grid, const FleetProblem& problem) {
  if (problem.vehicles.empty()) return make_error(ErrorCode::kInvalidArgument, "vehicles", "none given");

  std::set<std::string> vehicle_ids;
  std::map<std::pair<int, int>, std::string> depot_owner;
  for (std::size_t i = 0; i < problem.vehicles.size(); ++i) {
    const FleetVehicle& v = problem.vehicles[i];
    const std::string field = placeField("vehicle", i, v.id);
    if (Status s = checkId("vehicle", field, v.id, vehicle_ids); !s) return s;
    if (v.max_tasks < 0) {
      return make_error(ErrorCode::kInvalidArgument, field + " max_tasks",
                        "max_tasks " + std::to_string(v.max_tasks) + " is negative");
    }
    if (Status s = checkCell(grid, v.depot, field + " depot"); !s) return s;
    auto [it, fresh] = depot_owner.emplace(std::pair{v.depot.x, v.depot.y}, v.id);
    if (!fresh) {
      return make_error(ErrorCode::kInvalidArgument, field + " depot",
                        describeCell(v.depot) + " is also the depot of vehicle " + it->second);
    }
  }

  std::set<std::string> task_ids;
  for (std::size_t j = 0; j < problem.tasks.size(); ++j) {
    const FleetTask& t = problem.tasks[j];
    const std::string field = placeField("task", j, t.id);
    if (Status s = checkId("task", field, t.id, task_ids); !s) return s;
    if (Status s = checkCell(grid, t.cell, field); !s) return s;
    // A vehicle parks on its depot before and after its tour (eq. 7), so a task there could only
    // be served while the owner is away; the paper places tasks off the vehicles' cells.
    if (auto it = depot_owner.find({t.cell.x, t.cell.y}); it != depot_owner.end()) {
      return make_error(ErrorCode::kOccupied, field,
                        describeCell(t.cell) + " lies on the depot of vehicle " + it->second);
    }
  }

  long long total_capacity = 0;
  bool unlimited = false;
  for (const FleetVehicle& v : problem.vehicles) {
    if (v.max_tasks == 0) unlimited = true;
    total_capacity += v.max_tasks;
  }
  if (!unlimited && total_capacity < static_cast<long long>(problem.tasks.size())) {
    return make_error(ErrorCode::kInvalidArgument, "tasks",
                      std::to_string(problem.tasks.size()) + " tasks exceed the vehicles' total capacity of " +
                          std::to_string(total_capacity) + " (sum of max_tasks)");
  }

  std::set<std::string> obstacle_ids;
  for (std::size_t k = 0; k < problem.moving_obstacles.size(); ++k) {
    const MovingObstacle& o = problem.moving_obstacles[k];
    const std::string field = "moving obstacle " + (o.id.empty() ? "#" + std::to_string(k) : o.id);
    if (!o.id.empty() && !obstacle_ids.insert(o.id).second) {
      return make_error(ErrorCode::kInvalidArgument, field, "duplicate obstacle id '" + o.id + "'");
    }
    if (o.start_step < 0) {
      return make_error(ErrorCode::kInvalidArgument, field + " start_step",
                        "start_step " + std::to_string(o.start_step) + " is negative");
    }
    for (std::size_t s = 1; s < o.cells.size(); ++s) {
      const int manhattan = std::abs(o.cells[s].x - o.cells[s - 1].x) + std::abs(o.cells[s].y - o.cells[s - 1].y);
      if (manhattan > 1) {
        return make_error(ErrorCode::kInvalidArgument, field,
                          "jumps " + std::to_string(manhattan) + " cells at step " +
                              std::to_string(o.start_step + static_cast<int>(s)) + " (at most one per step)");
      }
    }
    if (auto c = o.cellAt(0)) {
      if (auto it = depot_owner.find({c->x, c->y}); it != depot_owner.end()) {
        return make_error(ErrorCode::kOccupied, field,
                          "covers the depot of vehicle " + it->second + " " + describeCell(*c) + " at step 0");
      }
    }
  }

  // Reachability last: it costs one breadth-first search per depot.
  std::vector<std::vector<int>> depot_maps;
  for (const FleetVehicle& v : problem.vehicles) depot_maps.push_back(bfsDistanceMap4(grid, v.depot));
  for (const FleetTask& t : problem.tasks) {
    bool reachable = false;
    for (const auto& map : depot_maps) reachable = reachable || map[grid.index(t.cell)] != kUnreachableSteps;
    if (!reachable) {
      return make_error(ErrorCode::kUnreachable, "task " + t.id,
                        describeCell(t.cell) + " cannot be reached from any depot");
    }
  }
  return Status::success();
}

}  // namespace skyroute
