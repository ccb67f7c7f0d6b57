// skyroute mission: plan a multi-point mission on a grid (a Moving AI map or a DEM's flight band):
// the MMD*L (or per-pair D* Lite) cost matrix, the open-TSP visiting order B .. E, and the legs.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "planning/mission/mission_planner.hpp"
#include "service/cli/commands.hpp"
#include "terrain/dem.hpp"
#include "terrain/grid_from_terrain.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {
namespace {

struct MissionArgs {
  std::string map;
  std::string dem;
  std::string begin;
  std::vector<std::string> points;
  std::string end;
  std::string algo = "mmdstar";
  bool paper_moves = false;
  bool json = false;
  bool with_paths = false;
  TerrainGridOptions grid_options;
};

[[noreturn]] void fail(const std::string& message, int code = 2) {
  std::cerr << "skyroute mission: " << message << "\n";
  throw CLI::RuntimeError(code);
}

GridCell parseCell(const std::string& text, const std::string& field) {
  std::istringstream in(text);
  int x = 0, y = 0;
  char comma = 0;
  if (!(in >> x >> comma >> y) || comma != ',' || !(in >> std::ws).eof())
    fail(field + " '" + text + "' is not a cell 'x,y' (column, row)");
  return GridCell{x, y};
}

std::string pointLabel(int point, int count) {
  if (point == 0) return "B";
  if (point == count - 1) return "E";
  return "M" + std::to_string(point);
}

void runMission(const MissionArgs& args) {
  if (args.map.empty() == args.dem.empty()) fail("give exactly one of --map and --dem");
  GridLayer grid;
  if (!args.map.empty()) {
    auto loaded = loadMovingAiMap(args.map);
    if (!loaded.ok()) fail("--map " + loaded.error().describe());
    grid = std::move(*loaded);
  } else {
    auto dem = Dem::load(args.dem);
    if (!dem.ok()) fail("--dem " + dem.error().describe());
    auto hf = Heightfield::build(*dem);
    if (!hf.ok()) fail("--dem " + hf.error().describe());
    auto built = buildTerrainGrid(**hf, args.grid_options);
    if (!built.ok()) fail(built.error().describe());
    grid = std::move(*built);
  }
  const GridCell begin = parseCell(args.begin, "--begin");
  const GridCell end = parseCell(args.end, "--end");
  std::vector<GridCell> missions;
  for (std::size_t i = 0; i < args.points.size(); ++i)
    missions.push_back(parseCell(args.points[i], "--points[" + std::to_string(i) + "]"));

  MissionOptions options;
  options.algorithm = args.algo == "dstar-lite" ? MissionAlgorithm::kDStarLite : MissionAlgorithm::kMmdStarLite;
  if (args.paper_moves) options.moves = GridMoves::paper();
  auto planner = MissionPlanner::create(grid, begin, missions, end, options);
  if (!planner.ok()) fail(planner.error().describe() + " [" + std::string(to_string(planner.error().code)) + "]");
  auto plan = planner->preplan();
  if (!plan.ok()) fail(plan.error().describe() + " [" + std::string(to_string(plan.error().code)) + "]");

  const int count = static_cast<int>(missions.size()) + 2;
  nlohmann::json j;
  j["algo"] = std::string(to_string(options.algorithm));
  j["grid"] = {{"width", grid.width()}, {"height", grid.height()}, {"cell_size_m", grid.cellSize()},
               {"blocked", grid.blockedCount()}};
  nlohmann::json labels = nlohmann::json::array();
  nlohmann::json cells = nlohmann::json::array();
  std::vector<GridCell> all{begin};
  all.insert(all.end(), missions.begin(), missions.end());
  all.push_back(end);
  for (int p = 0; p < count; ++p) {
    labels.push_back(pointLabel(p, count));
    cells.push_back({all[p].x, all[p].y});
  }
  j["points"] = labels;
  j["cells"] = cells;
  nlohmann::json order = nlohmann::json::array();
  for (int p : plan->order) order.push_back(pointLabel(p, count));
  j["order"] = order;
  j["cost"] = plan->cost;
  if (grid.cellSize() != 1.0) j["cost_m"] = plan->cost * grid.cellSize();
  nlohmann::json matrix = nlohmann::json::array();
  for (const auto& row : plan->cost_matrix) {
    nlohmann::json r = nlohmann::json::array();
    for (double v : row) r.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    matrix.push_back(r);
  }
  j["cost_matrix"] = matrix;
  nlohmann::json legs = nlohmann::json::array();
  for (const MissionLeg& leg : plan->legs) {
    nlohmann::json l{{"from", pointLabel(leg.from_point, count)},
                     {"to", pointLabel(leg.to_point, count)},
                     {"cost", leg.cost},
                     {"cells", leg.cells.size()}};
    if (args.with_paths) {
      nlohmann::json path = nlohmann::json::array();
      for (const GridCell& c : leg.cells) path.push_back({c.x, c.y});
      l["path"] = path;
    }
    legs.push_back(l);
  }
  j["legs"] = legs;
  j["tsp"] = {{"exact", plan->tsp.exact}, {"time_ms", plan->tsp_time_ms}};
  if (plan->tsp.gap) j["tsp"]["heuristic_gap"] = *plan->tsp.gap;
  j["expansions"] = plan->search.expansions;
  j["queue_ops"] = plan->search.queue_pushes + plan->search.queue_pops;
  j["cost_maps"] = planner->search().costMapCount();
  j["search_time_ms"] = plan->search.time_ms;
  j["time_ms"] = plan->total_time_ms;
  if (args.json) {
    std::cout << j.dump() << std::endl;
    return;
  }
  std::printf("grid        %d x %d (cell %.1f m), %zu blocked\n", grid.width(), grid.height(), grid.cellSize(),
              grid.blockedCount());
  std::printf("algorithm   %s (%zu g/rhs maps)\n", j["algo"].get<std::string>().c_str(),
              planner->search().costMapCount());
  std::string order_text;
  for (const auto& o : order) order_text += (order_text.empty() ? "" : " -> ") + o.get<std::string>();
  std::printf("order       %s\n", order_text.c_str());
  std::printf("cost        %.4f cells%s\n", plan->cost, grid.cellSize() != 1.0 ? (" (" + std::to_string(plan->cost * grid.cellSize()) + " m)").c_str() : "");
  std::printf("cost matrix (row: from, column: to; '-' not planned)\n      ");
  for (int c = 0; c < count; ++c) std::printf("%10s", pointLabel(c, count).c_str());
  std::printf("\n");
  for (int r = 0; r < count; ++r) {
    std::printf("%6s", pointLabel(r, count).c_str());
    for (int c = 0; c < count; ++c) {
      const double v = plan->cost_matrix[r][c];
      if (std::isfinite(v))
        std::printf("%10.3f", v);
      else
        std::printf("%10s", "-");
    }
    std::printf("\n");
  }
  for (const MissionLeg& leg : plan->legs)
    std::printf("leg %-3s -> %-3s cost %10.3f  %zu cells\n", pointLabel(leg.from_point, count).c_str(),
                pointLabel(leg.to_point, count).c_str(), leg.cost, leg.cells.size());
  std::printf("expansions  %llu (queue operations %llu)\n", static_cast<unsigned long long>(plan->search.expansions),
              static_cast<unsigned long long>(plan->search.queue_pushes + plan->search.queue_pops));
  std::printf("time        %.3f ms (search %.3f ms, TSP %.3f ms, %s)\n", plan->total_time_ms, plan->search.time_ms,
              plan->tsp_time_ms, plan->tsp.exact ? "exact" : "heuristic");
}

}  // namespace

void addMissionCommand(CLI::App& app) {
  auto args = std::make_shared<MissionArgs>();
  CLI::App* cmd = app.add_subcommand("mission", "Order and plan a multi-point mission B -> mission points -> E on a grid");
  cmd->add_option("--map", args->map, "Moving AI .map file");
  cmd->add_option("--dem", args->dem, "DEM raster; the grid is its flight band");
  cmd->add_option("--begin", args->begin, "begin cell x,y")->required();
  cmd->add_option("--points", args->points, "mission cells x,y ...");
  cmd->add_option("--end", args->end, "end cell x,y")->required();
  cmd->add_option("--algo", args->algo, "mmdstar | dstar-lite")->check(CLI::IsMember({"mmdstar", "dstar-lite"}));
  cmd->add_flag("--paper-moves", args->paper_moves, "diagonal cost 1.4 and the Chebyshev heuristic (the paper's)");
  cmd->add_flag("--json", args->json, "one JSON object instead of text");
  cmd->add_flag("--paths", args->with_paths, "include every leg's cells in the JSON");
  cmd->add_option("--cell-size-m", args->grid_options.cell_size_m, "--dem: grid cell edge, metres")->capture_default_str();
  cmd->add_option("--ceiling-m", args->grid_options.flight_ceiling_m, "--dem: top of the flight band, metres AMSL")
      ->capture_default_str();
  cmd->add_option("--clearance-m", args->grid_options.min_clearance_m, "--dem: height above ground required, metres")
      ->capture_default_str();
  cmd->callback([args]() { runMission(*args); });
}

}  // namespace skyroute::cli
