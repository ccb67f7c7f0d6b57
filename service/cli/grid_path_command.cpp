// `skyroute grid path`: one any-angle or 8-connected path on a Moving AI map with A*, Theta*,
// HAB-PP or Improved HAB-PP; prints length, first-path time and total time, and with --out writes
// {"length": L, "points": [[x, y], ...]} in cell coordinates (cell centres at integers).
// Exit codes are the table's: a blocked or outside end point is a bad option value (2), no path
// (unreachable, or out of time) a failed plan (1), an unreadable map a bad input file (3).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "planning/colony/hab_pp.hpp"
#include "planning/grid/any_angle_search.hpp"
#include "service/cli/cli_parse.hpp"
#include "service/cli/commands.hpp"
#include "service/map_figure.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {

namespace {

const std::string kTool = "grid path";

struct GridPathOptions {
  std::string map;
  std::string from;
  std::string to;
  std::string algo;
  std::uint64_t seed = 1;
  double budget_s = 60.0;
  int window_segments = HabPpParameters{}.output_window_segments;  // HAB-PP output stage
  bool window_given = false;  // --window-segments on the command line
  std::string out;
  std::string png;
};

GridCell parseCell(const std::string& option, const std::string& text) {
  auto cell = parseGridCell(text, option);
  if (!cell) fail(kTool, kExitUsage, cell.error().message);
  return *cell;
}

void checkEndpoint(const GridLayer& grid, const std::string& option, GridCell c) {
  const std::string where = "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")";
  if (!grid.inside(c)) {
    fail(kTool, kExitUsage,
         option + ": " + where + " is outside the map (" + std::to_string(grid.width()) + " x " +
             std::to_string(grid.height()) + ")");
  }
  if (grid.blocked(c)) fail(kTool, kExitUsage, option + ": " + where + " is a blocked cell");
}

void run(const GridPathOptions& o) {
  const GridCell start = parseCell("--from", o.from);
  const GridCell goal = parseCell("--to", o.to);
  if (!(o.budget_s > 0.0)) fail(kTool, kExitUsage, "--budget-s: must be > 0");
  if (o.window_segments < 0) fail(kTool, kExitUsage, "--window-segments: must be >= 0 (0: off)");
  if (o.window_given && o.algo.rfind("hab-pp", 0) != 0) {
    fail(kTool, kExitUsage, "--window-segments: applies to hab-pp and hab-pp-rrt only, not " + o.algo);
  }
  checkOutputPath(kTool, "--out", o.out, {"json"});
  checkOutputPath(kTool, "--png", o.png, {"png"});
  Result<GridLayer> grid = loadMovingAiMap(o.map);
  if (!grid) fail(kTool, kExitBadInput, "--map " + grid.error().describe());
  checkEndpoint(*grid, "--from", start);
  checkEndpoint(*grid, "--to", goal);
  const auto stop = TerminationCondition::after(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(o.budget_s)));

  std::vector<GridCell> path;
  double length = 0.0, first_s = 0.0, total_s = 0.0;
  std::string status;
  bool found = false;
  if (o.algo == "astar" || o.algo == "theta") {
    const AnyAngleResult r = o.algo == "astar" ? gridAStar8(*grid, start, goal, stop) : thetaStar(*grid, start, goal, stop);
    found = r.status == PlannerStatus::kSolved;
    status = std::string(to_string(r.status));
    path = r.path;
    length = r.length_cells;
    first_s = total_s = r.time_s;
  } else {
    HabPpParameters params = o.algo == "hab-pp-rrt" ? HabPpParameters::improved() : HabPpParameters{};
    params.output_window_segments = o.window_segments;
    const HabPpResult r = planHabPp(*grid, start, goal, params, o.seed, stop);
    found = hasPath(r.status);
    status = std::string(to_string(r.status));
    if (!r.message.empty()) status += " (" + r.message + ")";
    path = r.path;
    length = r.length_cells;
    first_s = r.first_path_time_s;
    total_s = r.total_time_s;
  }
  if (!found) fail(kTool, kExitPlanningFailed, "--to: no path from --from to --to with " + o.algo + ": " + status);

  std::printf("algo: %s\nstatus: %s\nlength: %.6f\nfirst path time: %.6f s\ntotal time: %.6f s\npoints: %zu\n",
              o.algo.c_str(), status.c_str(), length, first_s, total_s, path.size());
  if (!o.out.empty()) {
    nlohmann::json j;
    j["length"] = length;
    j["points"] = nlohmann::json::array();
    for (GridCell c : path) j["points"].push_back({c.x, c.y});
    std::ofstream f(o.out);
    f << j.dump() << "\n";
    if (!f.flush()) fail(kTool, kExitUsage, "--out " + o.out + ": cannot write");
  }
  if (!o.png.empty()) {
    MapFigureContent figure;
    char title[160];
    std::snprintf(title, sizeof title, "%s: length %.2f cells", o.algo.c_str(), length);
    figure.title = title;
    FigureLine line{o.algo + " path", {}, Rgb{220, 20, 20}, 3.0};
    for (GridCell c : path) line.points.emplace_back(c.x, c.y);
    figure.lines.push_back(std::move(line));
    figure.markers.push_back({MarkerKind::kStart, Eigen::Vector2d(start.x, start.y)});
    figure.markers.push_back({MarkerKind::kEnd, Eigen::Vector2d(goal.x, goal.y)});
    if (Status saved = saveGridFigure(*grid, false, figure, o.png); !saved.ok()) {
      fail(kTool, kExitUsage, "--png " + saved.error().describe());
    }
  }
}

}  // namespace

void addGridPathCommand(CLI::App& grid) {
  auto opts = std::make_shared<GridPathOptions>();
  CLI::App* cmd = grid.add_subcommand("path", "One path on a Moving AI map: A*, Theta*, HAB-PP or Improved HAB-PP");
  cmd->add_option("--map", opts->map, "Moving AI .map file")->required();
  cmd->footer(helpFooter({"skyroute grid path --map room-32-32-4.map --from 1,1 --to 30,30 --algo theta --out path.json"}));
  cmd->add_option("--from", opts->from, "start cell X,Y (column, row from 0)");
  cmd->add_option("--to", opts->to, "goal cell X,Y");
  // The names before --from and --to, kept for one release (hidden).
  cmd->add_option("--start", opts->from, "old name of --from")->group("");
  cmd->add_option("--goal", opts->to, "old name of --to")->group("");
  cmd->add_option("--algo", opts->algo, "astar (8-connected), theta (Theta*), hab-pp, hab-pp-rrt (Improved HAB-PP)")
      ->required()
      ->check(CLI::IsMember({"astar", "theta", "hab-pp", "hab-pp-rrt"}));
  cmd->add_option("--seed", opts->seed, "random seed of the HAB-PP planners")->default_val(1);
  cmd->add_option("--budget-s", opts->budget_s, "time limit in seconds")->default_val(60.0);
  CLI::Option* window = cmd->add_option(
      "--window-segments", opts->window_segments,
      "HAB-PP output stage: re-plan windows of N path segments with Theta* (a local search; 0: off)");
  window->default_val(HabPpParameters{}.output_window_segments);
  cmd->add_option("--png", opts->png, "draw the map around the path, with start, end, scale and legend, to this PNG");
  cmd->add_option("--out", opts->out, "write {\"length\": L, \"points\": [[x, y], ...]} to this JSON file");
  cmd->callback([opts, window] {
    if (opts->from.empty() || opts->to.empty()) fail(kTool, kExitUsage, "give --from X,Y and --to X,Y");
    opts->window_given = window->count() > 0;
    run(*opts);
  });
}

}  // namespace skyroute::cli
