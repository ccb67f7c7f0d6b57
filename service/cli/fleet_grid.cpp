#include "service/cli/fleet_grid.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "planning/fleet/fleet_planner.hpp"
#include "service/cli/fleet_common.hpp"
#include "service/map_figure.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {

namespace {

const std::string kTool = "fleet";

std::vector<GridCell> parseCells(const std::string& option, const std::string& text) {
  std::vector<GridCell> cells = parseListOption(kTool, option, text, &parseGridCell);
  if (cells.empty()) fail(kTool, kExitUsage, option + ": no cells given (expected X,Y;X,Y;...)");
  return cells;
}

GridLayer loadGrid(const FleetGridArgs& o) {
  if (!o.map.empty()) {
    auto loaded = loadMovingAiMap(o.map);
    if (!loaded) fail(kTool, kExitBadInput, "--map " + loaded.error().describe());
    return std::move(loaded).value();
  }
  std::cerr << "loading " << o.dem << " ..." << std::endl;
  auto dem = Dem::load(o.dem);
  if (!dem) fail(kTool, kExitBadInput, "--dem " + dem.error().describe());
  auto terrain = Heightfield::build(dem.value());
  if (!terrain) fail(kTool, kExitBadInput, "--dem " + terrain.error().describe());
  auto built = buildTerrainGrid(*terrain.value(), o.grid_options);
  if (!built) fail(kTool, kExitUsage, built.error().describe());
  return std::move(built).value();
}

// The grid (free white, blocked grey) cropped to the fleet, every route in the vehicle's colour,
// depots as filled squares and tasks as rings in the colour of the vehicle that serves them.
// north_up: grid y grows north (terrain grids), so rows are drawn flipped.
void writePng(const std::string& path, const GridLayer& grid, const FleetProblem& problem, const FleetPlan& plan,
              bool north_up) {
  MapFigureContent figure;
  figure.title = "skyroute fleet (grid): " + std::to_string(problem.vehicles.size()) + " vehicles, " +
                 std::to_string(problem.tasks.size()) + " tasks, makespan " + std::to_string(plan.makespan());
  auto at = [](GridCell c) { return Eigen::Vector2d(c.x, c.y); };
  for (const VehiclePlan& v : plan.paths.vehicles) {
    const Rgb colour = vehicleRgb(static_cast<std::size_t>(v.vehicle));
    FigureLine line{"vehicle " + std::to_string(v.vehicle), {}, colour, 3.0};
    for (const GridCell& c : v.cells) line.points.push_back(at(c));
    figure.lines.push_back(std::move(line));
    figure.markers.push_back({MarkerKind::kDepot, at(problem.vehicles[static_cast<std::size_t>(v.vehicle)].depot), 0, colour});
    for (int j : v.tasks) figure.markers.push_back({MarkerKind::kTask, at(problem.tasks[static_cast<std::size_t>(j)].cell), 0, colour});
  }
  if (Status saved = saveGridFigure(grid, north_up, figure, path); !saved.ok()) {
    fail(kTool, kExitUsage, "--png " + saved.error().describe());
  }
}

void writeJson(const std::string& path, const FleetProblem& problem, const FleetPlan& plan) {
  nlohmann::ordered_json doc;  // keys in the documented order
  doc["makespan"] = plan.makespan();
  doc["vehicles"] = nlohmann::ordered_json::array();
  for (const VehiclePlan& v : plan.paths.vehicles) {
    nlohmann::ordered_json one;
    const GridCell depot = problem.vehicles[static_cast<std::size_t>(v.vehicle)].depot;
    one["depot"] = {depot.x, depot.y};
    one["tasks"] = nlohmann::ordered_json::array();
    for (int j : v.tasks) {
      const GridCell c = problem.tasks[static_cast<std::size_t>(j)].cell;
      one["tasks"].push_back({c.x, c.y});
    }
    one["path"] = nlohmann::ordered_json::array();
    for (int t = 0; t <= plan.makespan(); ++t) {
      const GridCell c = v.cellAt(t);
      one["path"].push_back({t, c.x, c.y});
    }
    doc["vehicles"].push_back(std::move(one));
  }
  std::ofstream file(path);
  file << doc.dump() << "\n";
  if (!file) fail(kTool, kExitUsage, "--out " + path + ": writing failed");
}

void printPlan(const GridLayer& grid, const FleetProblem& problem, const FleetPlan& plan, FleetAllocator allocator) {
  std::cout << "grid " << grid.width() << " x " << grid.height() << ", " << problem.vehicleCount() << " vehicles, "
            << problem.taskCount() << " tasks, allocation " << to_string(allocator) << "\n";
  for (const VehiclePlan& v : plan.paths.vehicles) {
    const GridCell d = problem.vehicles[static_cast<std::size_t>(v.vehicle)].depot;
    std::cout << "vehicle " << v.vehicle << " at (" << d.x << ", " << d.y << "): tasks";
    if (v.tasks.empty()) std::cout << " none";
    for (std::size_t k = 0; k < v.tasks.size(); ++k) {
      const GridCell c = problem.tasks[static_cast<std::size_t>(v.tasks[k])].cell;
      std::cout << " " << v.tasks[k] << "(" << c.x << ", " << c.y << ")@" << v.task_steps[k];
    }
    std::cout << ", home at step " << v.finish_step << "\n";
  }
  std::cout << "makespan " << plan.makespan() << " steps (allocation estimate " << plan.allocation.makespan_steps
            << "), sum of costs " << plan.paths.sum_of_steps << "\n"
            << "conflicts resolved " << plan.paths.conflicts_resolved << " (" << plan.paths.detours << " detours, "
            << plan.paths.waits << " waits), conflict-free: " << (plan.check.ok() ? "yes" : "no") << "\n";
  std::printf("time: travel times %.3f ms, allocation %.3f ms, paths %.3f ms, total %.3f ms\n",
              plan.table_time_s * 1e3, plan.allocation.time_s * 1e3, plan.paths.time_s * 1e3, plan.total_time_s * 1e3);
}

}  // namespace

void runFleetOnGrid(const FleetGridArgs& o) {
  const auto allocator = parseFleetAllocator(o.algo);
  if (!allocator) fail(kTool, kExitUsage, "--algo: '" + o.algo + "' is not one of greedy, ga, exact");
  if (o.capacity < 0) fail(kTool, kExitUsage, "--capacity: must be >= 0 (0: no limit)");
  if (!(o.budget_s > 0.0)) fail(kTool, kExitUsage, "--budget-s: must be > 0");
  checkOutputPath(kTool, "--out", o.out, {"json"});
  checkOutputPath(kTool, "--png", o.png, {"png"});
  const std::vector<GridCell> depots = parseCells("--vehicles", o.vehicles);
  const std::vector<GridCell> tasks = parseCells("--tasks", o.tasks);
  const GridLayer grid = loadGrid(o);

  FleetProblem problem;
  for (std::size_t i = 0; i < depots.size(); ++i) problem.vehicles.push_back({std::to_string(i), depots[i], o.capacity});
  for (std::size_t j = 0; j < tasks.size(); ++j) problem.tasks.push_back({std::to_string(j), tasks[j]});
  FleetPlannerOptions options;
  options.allocator = *allocator;
  options.ga.seed = o.seed;
  const auto plan = planFleet(grid, problem, options, TerminationCondition::afterMilliseconds(o.budget_s * 1e3));
  if (!plan) {
    const Error& e = plan.error();
    // Items are named by index: "vehicle 2", "task 5" follow the order on the command line. A
    // depot or task off the grid, blocked or repeated is a bad option value; the rest is planning.
    const std::string option =
        e.field.rfind("vehicle", 0) == 0 ? "--vehicles: " : e.field.rfind("task", 0) == 0 ? "--tasks: " : "";
    const bool bad_input = e.code == ErrorCode::kOutsideMap || e.code == ErrorCode::kOccupied ||
                           e.code == ErrorCode::kInvalidArgument;
    fail(kTool, bad_input ? kExitUsage : kExitPlanningFailed, option + e.describe());
  }
  printPlan(grid, problem, *plan, *allocator);
  if (!o.out.empty()) writeJson(o.out, problem, *plan);
  if (!o.png.empty()) writePng(o.png, grid, problem, *plan, o.map.empty());
}

}  // namespace skyroute::cli
