#include "service/cli/mission_grid.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <regex>

#include <nlohmann/json.hpp>

#include "planning/mission/mission_planner.hpp"
#include "service/cli/cli_parse.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "mission";

std::string pointLabel(int point, int count) {
  if (point == 0) return "B";
  if (point == count - 1) return "E";
  return "M" + std::to_string(point);
}

// The planner names points as the request does (begin, points[i], end); the user wrote options.
std::string asOptions(const Error& e) {
  std::string text = e.message;
  for (const auto& [field, option] : {std::pair<std::string, std::string>{"begin", "--from"}, {"end", "--to"}}) {
    if (text.rfind(field + " ", 0) == 0) text = option + text.substr(field.size());
  }
  return std::regex_replace(text, std::regex(R"(\bpoints\[)"), "--via[");
}

GridLayer loadGrid(const MissionGridArgs& args) {
  if (!args.map.empty()) {
    auto loaded = loadMovingAiMap(args.map);
    if (!loaded.ok()) fail(kTool, kExitBadInput, "--map " + loaded.error().describe());
    return std::move(*loaded);
  }
  std::cerr << "loading " << args.dem << " ..." << std::endl;
  auto dem = Dem::load(args.dem);
  if (!dem.ok()) fail(kTool, kExitBadInput, "--dem " + dem.error().describe());
  auto hf = Heightfield::build(*dem);
  if (!hf.ok()) fail(kTool, kExitBadInput, "--dem " + hf.error().describe());
  auto built = buildTerrainGrid(**hf, args.grid_options);
  if (!built.ok()) fail(kTool, kExitUsage, built.error().describe());
  return std::move(*built);
}

GridCell cellOption(const std::string& text, const std::string& option) {
  auto cell = parseGridCell(text, option);
  if (!cell) fail(kTool, kExitUsage, cell.error().message);
  return *cell;
}

nlohmann::json describePlan(const MissionGridArgs& args, MissionAlgorithm algorithm, const GridLayer& grid,
                            const std::vector<GridCell>& all, const MissionPlanner& planner, const MissionOrderPlan& plan) {
  const int count = static_cast<int>(all.size());
  nlohmann::json j;
  j["algo"] = std::string(to_string(algorithm));
  j["grid"] = {{"width", grid.width()}, {"height", grid.height()}, {"cell_size_m", grid.cellSize()},
               {"blocked", grid.blockedCount()}};
  for (int p = 0; p < count; ++p) {
    j["points"].push_back(pointLabel(p, count));
    j["cells"].push_back({all[p].x, all[p].y});
  }
  for (int p : plan.order) j["order"].push_back(pointLabel(p, count));
  j["cost"] = plan.cost;
  if (grid.cellSize() != 1.0) j["cost_m"] = plan.cost * grid.cellSize();
  for (const auto& row : plan.cost_matrix) {
    nlohmann::json r = nlohmann::json::array();
    for (double v : row) r.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    j["cost_matrix"].push_back(r);
  }
  j["legs"] = nlohmann::json::array();
  for (const MissionLeg& leg : plan.legs) {
    nlohmann::json l{{"from", pointLabel(leg.from_point, count)},
                     {"to", pointLabel(leg.to_point, count)},
                     {"cost", leg.cost},
                     {"cells", leg.cells.size()}};
    if (args.with_paths) {
      for (const GridCell& c : leg.cells) l["path"].push_back({c.x, c.y});
    }
    j["legs"].push_back(l);
  }
  j["tsp"] = {{"exact", plan.tsp.exact}, {"time_ms", plan.tsp_time_ms}};
  if (plan.tsp.gap) j["tsp"]["heuristic_gap"] = *plan.tsp.gap;
  j["expansions"] = plan.search.expansions;
  j["queue_ops"] = plan.search.queue_pushes + plan.search.queue_pops;
  j["cost_maps"] = planner.search().costMapCount();
  j["search_time_ms"] = plan.search.time_ms;
  j["time_ms"] = plan.total_time_ms;
  return j;
}

void printPlan(const GridLayer& grid, const nlohmann::json& j, const MissionOrderPlan& plan) {
  const int count = static_cast<int>(plan.cost_matrix.size());
  std::printf("grid        %d x %d (cell %.1f m), %zu blocked\n", grid.width(), grid.height(), grid.cellSize(),
              grid.blockedCount());
  std::printf("algorithm   %s (%d g/rhs maps)\n", j["algo"].get<std::string>().c_str(), j["cost_maps"].get<int>());
  std::string order_text;
  for (const auto& o : j["order"]) order_text += (order_text.empty() ? "" : " -> ") + o.get<std::string>();
  std::printf("order       %s\n", order_text.c_str());
  std::printf("cost        %.4f cells", plan.cost);
  if (grid.cellSize() != 1.0) std::printf(" (%.1f m)", plan.cost * grid.cellSize());
  std::printf("\ncost matrix (row: from, column: to; '-' not planned)\n      ");
  for (int c = 0; c < count; ++c) std::printf("%10s", pointLabel(c, count).c_str());
  std::printf("\n");
  for (int r = 0; r < count; ++r) {
    std::printf("%6s", pointLabel(r, count).c_str());
    for (int c = 0; c < count; ++c) {
      const double v = plan.cost_matrix[r][c];
      if (std::isfinite(v)) {
        std::printf("%10.3f", v);
      } else {
        std::printf("%10s", "-");
      }
    }
    std::printf("\n");
  }
  for (const MissionLeg& leg : plan.legs) {
    std::printf("leg %-3s -> %-3s cost %10.3f  %zu cells\n", pointLabel(leg.from_point, count).c_str(),
                pointLabel(leg.to_point, count).c_str(), leg.cost, leg.cells.size());
  }
  std::printf("expansions  %llu (queue operations %llu)\n", static_cast<unsigned long long>(plan.search.expansions),
              static_cast<unsigned long long>(plan.search.queue_pushes + plan.search.queue_pops));
  std::printf("time        %.3f ms (search %.3f ms, TSP %.3f ms, %s)\n", plan.total_time_ms, plan.search.time_ms,
              plan.tsp_time_ms, plan.tsp.exact ? "exact" : "heuristic");
}

}  // namespace

void runMissionOnGrid(const MissionGridArgs& args) {
  if (args.from.empty() || args.to.empty()) fail(kTool, kExitUsage, "give --from X,Y and --to X,Y (and any --via)");
  std::vector<GridCell> all{cellOption(args.from, "--from")};
  for (std::size_t i = 0; i < args.via.size(); ++i) all.push_back(cellOption(args.via[i], "--via[" + std::to_string(i) + "]"));
  all.push_back(cellOption(args.to, "--to"));
  const GridLayer grid = loadGrid(args);

  MissionOptions options;
  options.algorithm = args.algo == "dstar-lite" ? MissionAlgorithm::kDStarLite : MissionAlgorithm::kMmdStarLite;
  if (args.paper_moves) options.moves = GridMoves::paper();
  const std::vector<GridCell> missions(all.begin() + 1, all.end() - 1);
  auto planner = MissionPlanner::create(grid, all.front(), missions, all.back(), options);
  if (!planner.ok()) {
    const Error& e = planner.error();
    // A point outside the grid, blocked or repeated is a bad option value; a cut-off one a failed plan.
    const int code = e.code == ErrorCode::kUnreachable ? kExitPlanningFailed : kExitUsage;
    fail(kTool, code, asOptions(e) + " [" + std::string(to_string(e.code)) + "]");
  }
  auto plan = planner->preplan();
  if (!plan.ok()) fail(kTool, kExitPlanningFailed, asOptions(plan.error()) + " [" + std::string(to_string(plan.error().code)) + "]");
  const nlohmann::json j = describePlan(args, options.algorithm, grid, all, *planner, *plan);
  if (args.json) {
    std::cout << j.dump() << std::endl;
  } else {
    printPlan(grid, j, *plan);
  }
}

}  // namespace skyroute::cli
