// `skyroute fleet`: several vehicles, many tasks (GMTPA, seed 002). Allocates the tasks (greedy
// Algorithm 1, the GA baseline or the exact solver), builds collision-free time-stamped paths,
// verifies them, prints the allocation, makespan and times, and optionally writes
//   --out: {"makespan": N, "vehicles": [{"depot": [x, y], "tasks": [[x, y], ...],
//           "path": [[t, x, y], ...]}, ...]}   with one path entry per step 0 .. makespan
//   --png: the grid with each vehicle's route in its own colour (GDAL MEM -> PNG).
//
// Exit codes: 0 planned, 1 map or DEM unreadable, 2 bad argument (names the option or item),
// 3 no plan (blocked or unreachable task or depot, conflicts not resolved), 4 output not writable.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <cpl_conv.h>
#include <gdal_priv.h>
#include <nlohmann/json.hpp>

#include "planning/fleet/fleet_planner.hpp"
#include "service/cli/commands.hpp"
#include "terrain/dem.hpp"
#include "terrain/grid_from_terrain.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {

namespace {

struct FleetOptions {
  std::string map;
  std::string dem;
  std::string vehicles;
  std::string tasks;
  std::string algo = "greedy";
  std::uint64_t seed = 1;
  int capacity = 0;
  double budget_s = 60.0;
  double cell_size_m = 90.0;
  double ceiling_m = 1500.0;
  double clearance_m = 30.0;
  std::string out;
  std::string png;
};

[[noreturn]] void fail(int code, const std::string& message) {
  std::cerr << "skyroute fleet: " << message << "\n";
  throw CLI::RuntimeError(code);
}

// "X,Y;X,Y;..." (spaces allowed, a trailing ';' tolerated).
std::vector<GridCell> parseCells(const std::string& option, const std::string& text) {
  static const std::regex pattern(R"(\s*(-?\d{1,9})\s*,\s*(-?\d{1,9})\s*)");
  std::vector<GridCell> cells;
  std::stringstream in(text);
  std::string item;
  int index = 0;
  while (std::getline(in, item, ';')) {
    ++index;
    if (item.find_first_not_of(" \t") == std::string::npos) continue;
    std::smatch m;
    if (!std::regex_match(item, m, pattern)) {
      fail(2, option + ": item " + std::to_string(index) + " '" + item + "' is not X,Y (two integers)");
    }
    cells.push_back(GridCell{std::stoi(m[1].str()), std::stoi(m[2].str())});
  }
  if (cells.empty()) fail(2, option + ": no cells given (expected X,Y;X,Y;...)");
  return cells;
}

int exitCodeFor(ErrorCode code) {
  switch (code) {
    case ErrorCode::kFileNotFound:
    case ErrorCode::kNotARaster:
    case ErrorCode::kParseError:
    case ErrorCode::kNoCrs:
    case ErrorCode::kBandAmbiguous:
    case ErrorCode::kAllNodata:
    case ErrorCode::kAbsurdHeights: return 1;
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kOutsideMap: return 2;
    default: return 3;
  }
}

// Distinct colours for up to a dozen vehicles, then hues around the wheel.
std::array<std::uint8_t, 3> vehicleColour(int i) {
  static const std::array<std::array<std::uint8_t, 3>, 12> kPalette = {{
      {228, 26, 28}, {55, 126, 184}, {77, 175, 74}, {152, 78, 163}, {255, 127, 0}, {166, 86, 40},
      {247, 129, 191}, {0, 170, 170}, {180, 180, 0}, {0, 0, 140}, {120, 0, 0}, {0, 100, 0}}};
  if (i < static_cast<int>(kPalette.size())) return kPalette[static_cast<std::size_t>(i)];
  const double h = std::fmod(i * 0.618033988749895, 1.0) * 6.0;
  const double f = h - std::floor(h);
  const auto v = [](double x) { return static_cast<std::uint8_t>(std::clamp(x, 0.0, 1.0) * 220.0); };
  switch (static_cast<int>(h)) {
    case 0: return {v(1), v(f), 0};
    case 1: return {v(1 - f), v(1), 0};
    case 2: return {0, v(1), v(f)};
    case 3: return {0, v(1 - f), v(1)};
    case 4: return {v(f), 0, v(1)};
    default: return {v(1), 0, v(1 - f)};
  }
}

// Draws the grid (free white, blocked grey), every route as a line of cell centres in the
// vehicle's colour, depots as filled squares and tasks as hollow squares in the colour of the
// vehicle that does them. north_up: grid y grows north (terrain grids), so image rows flip.
void writePng(const std::string& path, const GridLayer& grid, const FleetProblem& problem, const FleetPlan& plan,
              bool north_up) {
  const int scale = std::clamp(1200 / std::max(grid.width(), grid.height()), 2, 24);
  const int w = grid.width() * scale;
  const int h = grid.height() * scale;
  std::array<std::vector<std::uint8_t>, 3> band;
  for (auto& b : band) b.assign(static_cast<std::size_t>(w) * h, 255);
  auto put = [&](int px, int py, std::array<std::uint8_t, 3> c) {
    if (px < 0 || py < 0 || px >= w || py >= h) return;
    for (int k = 0; k < 3; ++k) band[k][static_cast<std::size_t>(py) * w + px] = c[static_cast<std::size_t>(k)];
  };
  auto rowOf = [&](int y) { return north_up ? grid.height() - 1 - y : y; };
  auto centre = [&](GridCell c) { return std::pair{c.x * scale + scale / 2, rowOf(c.y) * scale + scale / 2}; };
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (!grid.blocked({x, y})) continue;
      for (int dy = 0; dy < scale; ++dy) {
        for (int dx = 0; dx < scale; ++dx) put(x * scale + dx, rowOf(y) * scale + dy, {110, 110, 110});
      }
    }
  }
  const int half = std::max(1, scale / 3);
  auto square = [&](GridCell c, std::array<std::uint8_t, 3> colour, bool filled) {
    const auto [cx, cy] = centre(c);
    for (int dy = -half; dy <= half; ++dy) {
      for (int dx = -half; dx <= half; ++dx) {
        if (filled || std::abs(dx) == half || std::abs(dy) == half) put(cx + dx, cy + dy, colour);
      }
    }
  };
  const int thick = std::max(0, scale / 8);
  for (const VehiclePlan& v : plan.paths.vehicles) {
    const auto colour = vehicleColour(v.vehicle);
    for (std::size_t t = 1; t < v.cells.size(); ++t) {
      const auto [x0, y0] = centre(v.cells[t - 1]);
      const auto [x1, y1] = centre(v.cells[t]);
      for (int s = 0; s <= scale; ++s) {  // moves are axis-aligned: a straight run of pixels
        const int px = x0 + (x1 - x0) * s / scale;
        const int py = y0 + (y1 - y0) * s / scale;
        for (int d = -thick; d <= thick; ++d) put(px + (y0 == y1 ? 0 : d), py + (y0 == y1 ? d : 0), colour);
      }
    }
    square(problem.vehicles[static_cast<std::size_t>(v.vehicle)].depot, colour, true);
    for (int j : v.tasks) square(problem.tasks[static_cast<std::size_t>(j)].cell, colour, false);
  }

  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
  if (mem == nullptr || png == nullptr) fail(4, "--png: GDAL has no MEM or PNG driver");
  std::unique_ptr<GDALDataset> canvas(mem->Create("", w, h, 3, GDT_Byte, nullptr));
  if (!canvas) fail(4, "--png: cannot create an in-memory image of " + std::to_string(w) + " x " + std::to_string(h));
  for (int k = 0; k < 3; ++k) {
    if (canvas->GetRasterBand(k + 1)->RasterIO(GF_Write, 0, 0, w, h, band[static_cast<std::size_t>(k)].data(), w, h,
                                               GDT_Byte, 0, 0) != CE_None) {
      fail(4, "--png: writing the in-memory image failed: " + std::string(CPLGetLastErrorMsg()));
    }
  }
  std::unique_ptr<GDALDataset> written(png->CreateCopy(path.c_str(), canvas.get(), FALSE, nullptr, nullptr, nullptr));
  if (!written) fail(4, "--png: cannot write " + path + ": " + std::string(CPLGetLastErrorMsg()));
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
  if (!file) fail(4, "--out: cannot write " + path);
  file << doc.dump() << "\n";
  if (!file) fail(4, "--out: writing " + path + " failed");
}

void run(const FleetOptions& o) {
  if (o.map.empty() == o.dem.empty()) fail(2, "give exactly one of --map FILE.map and --dem FILE");
  const auto allocator = parseFleetAllocator(o.algo);
  if (!allocator) fail(2, "--algo: '" + o.algo + "' is not one of greedy, ga, exact");
  if (o.capacity < 0) fail(2, "--capacity: must be >= 0 (0: no limit)");
  if (!(o.budget_s > 0.0)) fail(2, "--budget-s: must be > 0");

  GridLayer grid;
  bool north_up = false;
  if (!o.map.empty()) {
    auto loaded = loadMovingAiMap(o.map);
    if (!loaded) fail(exitCodeFor(loaded.error().code), "--map: " + loaded.error().describe());
    grid = std::move(loaded).value();
  } else {
    auto dem = Dem::load(o.dem);
    if (!dem) fail(exitCodeFor(dem.error().code), "--dem: " + dem.error().describe());
    auto terrain = Heightfield::build(dem.value());
    if (!terrain) fail(exitCodeFor(terrain.error().code), "--dem: " + terrain.error().describe());
    TerrainGridOptions go;
    go.cell_size_m = o.cell_size_m;
    go.flight_ceiling_m = o.ceiling_m;
    go.min_clearance_m = o.clearance_m;
    auto built = buildTerrainGrid(*terrain.value(), go);
    if (!built) fail(2, "--dem: " + built.error().describe());
    grid = std::move(built).value();
    north_up = true;
  }

  FleetProblem problem;
  const std::vector<GridCell> depots = parseCells("--vehicles", o.vehicles);
  const std::vector<GridCell> tasks = parseCells("--tasks", o.tasks);
  for (std::size_t i = 0; i < depots.size(); ++i) problem.vehicles.push_back({std::to_string(i), depots[i], o.capacity});
  for (std::size_t j = 0; j < tasks.size(); ++j) problem.tasks.push_back({std::to_string(j), tasks[j]});

  FleetPlannerOptions options;
  options.allocator = *allocator;
  options.ga.seed = o.seed;
  const auto plan = planFleet(grid, problem, options, TerminationCondition::afterMilliseconds(o.budget_s * 1e3));
  if (!plan) {
    const Error& e = plan.error();
    // Items are named by index: "vehicle 2", "task 5" refer to the order on the command line.
    fail(exitCodeFor(e.code), (e.field.rfind("vehicle", 0) == 0 ? "--vehicles: " : e.field.rfind("task", 0) == 0 ? "--tasks: " : "") +
                                  e.describe());
  }

  std::cout << "grid " << grid.width() << " x " << grid.height() << ", " << problem.vehicleCount() << " vehicles, "
            << problem.taskCount() << " tasks, allocation " << to_string(*allocator) << "\n";
  for (const VehiclePlan& v : plan->paths.vehicles) {
    const GridCell d = problem.vehicles[static_cast<std::size_t>(v.vehicle)].depot;
    std::cout << "vehicle " << v.vehicle << " at (" << d.x << ", " << d.y << "): tasks";
    if (v.tasks.empty()) std::cout << " none";
    for (std::size_t k = 0; k < v.tasks.size(); ++k) {
      const GridCell c = problem.tasks[static_cast<std::size_t>(v.tasks[k])].cell;
      std::cout << " " << v.tasks[k] << "(" << c.x << ", " << c.y << ")@" << v.task_steps[k];
    }
    std::cout << ", home at step " << v.finish_step << "\n";
  }
  std::cout << "makespan " << plan->makespan() << " steps (allocation estimate " << plan->allocation.makespan_steps
            << "), sum of costs " << plan->paths.sum_of_steps << "\n"
            << "conflicts resolved " << plan->paths.conflicts_resolved << " (" << plan->paths.detours << " detours, "
            << plan->paths.waits << " waits), conflict-free: " << (plan->check.ok() ? "yes" : "no") << "\n";
  std::printf("time: travel times %.3f ms, allocation %.3f ms, paths %.3f ms, total %.3f ms\n",
              plan->table_time_s * 1e3, plan->allocation.time_s * 1e3, plan->paths.time_s * 1e3,
              plan->total_time_s * 1e3);
  if (!o.out.empty()) writeJson(o.out, problem, *plan);
  if (!o.png.empty()) writePng(o.png, grid, problem, *plan, north_up);
}

}  // namespace

void addFleetCommand(CLI::App& app) {
  auto opts = std::make_shared<FleetOptions>();
  CLI::App* cmd = app.add_subcommand("fleet", "Several vehicles, many tasks: GMTPA allocation and collision-free paths");
  cmd->add_option("--map", opts->map, "Moving AI .map file (x = column, y = row from the top)");
  cmd->add_option("--dem", opts->dem, "DEM file: plan on its grid layer at the flight band (x east, y north)");
  cmd->add_option("--vehicles", opts->vehicles, "vehicle depots X,Y;X,Y;...")->required();
  cmd->add_option("--tasks", opts->tasks, "task cells X,Y;X,Y;...")->required();
  cmd->add_option("--algo", opts->algo, "allocation: greedy (GMTPA Algorithm 1), ga (genetic baseline), exact")
      ->default_val("greedy");
  cmd->add_option("--seed", opts->seed, "random seed of the genetic algorithm")->default_val(1);
  cmd->add_option("--capacity", opts->capacity, "most tasks per vehicle (0: no limit)")->default_val(0);
  cmd->add_option("--budget-s", opts->budget_s, "time limit in seconds")->default_val(60.0);
  cmd->add_option("--cell-size", opts->cell_size_m, "--dem: grid cell edge in metres")->default_val(90.0);
  cmd->add_option("--ceiling", opts->ceiling_m, "--dem: top of the flight band in metres AMSL")->default_val(1500.0);
  cmd->add_option("--clearance", opts->clearance_m, "--dem: least height above ground in metres")->default_val(30.0);
  cmd->add_option("--out", opts->out, "write the plan as JSON (makespan, per vehicle depot, tasks and [t, x, y] path)");
  cmd->add_option("--png", opts->png, "draw the routes, one colour per vehicle, into this PNG");
  cmd->callback([opts]() { run(*opts); });
}

}  // namespace skyroute::cli
