// `skyroute grid path`: one any-angle or 8-connected path on a Moving AI map with A*, Theta*,
// HAB-PP or Improved HAB-PP; prints length, first-path time and total time, and with --out writes
// {"length": L, "points": [[x, y], ...]} in cell coordinates (cell centres at integers).
//
// Exit codes: 0 path found, 1 map file unreadable or malformed, 2 bad argument (names the option),
// 3 no path (blocked endpoint, unreachable goal or out of time), 4 --out not writable.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "planning/colony/hab_pp.hpp"
#include "planning/grid/any_angle_search.hpp"
#include "service/cli/commands.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {

namespace {

struct GridPathOptions {
  std::string map;
  std::string start;
  std::string goal;
  std::string algo;
  std::uint64_t seed = 1;
  double budget_s = 60.0;
  int window_segments = HabPpParameters{}.output_window_segments;  // HAB-PP output stage
  bool window_given = false;  // --window-segments on the command line
  std::string out;
};

[[noreturn]] void fail(int code, const std::string& message) {
  std::cerr << "skyroute grid path: " << message << "\n";
  throw CLI::RuntimeError(code);
}

GridCell parseCell(const std::string& option, const std::string& text) {
  static const std::regex pattern(R"(\s*(-?\d{1,9})\s*,\s*(-?\d{1,9})\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern)) fail(2, option + ": expected X,Y (two integers), got '" + text + "'");
  return GridCell{std::stoi(m[1].str()), std::stoi(m[2].str())};
}

void checkEndpoint(const GridLayer& grid, const std::string& option, GridCell c) {
  const std::string where = "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")";
  if (!grid.inside(c)) {
    fail(2, option + ": " + where + " is outside the map (" + std::to_string(grid.width()) + " x " +
                std::to_string(grid.height()) + ")");
  }
  if (grid.blocked(c)) fail(3, option + ": " + where + " is a blocked cell");
}

void run(const GridPathOptions& o) {
  const GridCell start = parseCell("--start", o.start);
  const GridCell goal = parseCell("--goal", o.goal);
  if (!(o.budget_s > 0.0)) fail(2, "--budget-s: must be > 0");
  if (o.window_segments < 0) fail(2, "--window-segments: must be >= 0 (0: off)");
  if (o.window_given && o.algo.rfind("hab-pp", 0) != 0) {
    fail(2, "--window-segments: applies to hab-pp and hab-pp-rrt only, not " + o.algo);
  }
  Result<GridLayer> grid = loadMovingAiMap(o.map);
  if (!grid) fail(1, "--map: " + grid.error().describe());
  checkEndpoint(*grid, "--start", start);
  checkEndpoint(*grid, "--goal", goal);
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
  if (!found) fail(3, "--goal: no path from --start to --goal with " + o.algo + ": " + status);

  std::printf("algo: %s\nstatus: %s\nlength: %.6f\nfirst path time: %.6f s\ntotal time: %.6f s\npoints: %zu\n",
              o.algo.c_str(), status.c_str(), length, first_s, total_s, path.size());
  if (!o.out.empty()) {
    nlohmann::json j;
    j["length"] = length;
    j["points"] = nlohmann::json::array();
    for (GridCell c : path) j["points"].push_back({c.x, c.y});
    std::ofstream f(o.out);
    f << j.dump() << "\n";
    if (!f.flush()) fail(4, "--out: cannot write " + o.out);
  }
}

}  // namespace

void addGridPathCommand(CLI::App& grid) {
  auto opts = std::make_shared<GridPathOptions>();
  CLI::App* cmd = grid.add_subcommand("path", "One path on a Moving AI map: A*, Theta*, HAB-PP or Improved HAB-PP");
  cmd->add_option("--map", opts->map, "Moving AI .map file")->required();
  cmd->add_option("--start", opts->start, "start cell X,Y (column, row from 0)")->required();
  cmd->add_option("--goal", opts->goal, "goal cell X,Y")->required();
  cmd->add_option("--algo", opts->algo, "astar (8-connected), theta (Theta*), hab-pp, hab-pp-rrt (Improved HAB-PP)")
      ->required()
      ->check(CLI::IsMember({"astar", "theta", "hab-pp", "hab-pp-rrt"}));
  cmd->add_option("--seed", opts->seed, "random seed of the HAB-PP planners")->default_val(1);
  cmd->add_option("--budget-s", opts->budget_s, "time limit in seconds")->default_val(60.0);
  CLI::Option* window = cmd->add_option(
      "--window-segments", opts->window_segments,
      "HAB-PP output stage: re-plan windows of N path segments with Theta* (a local search; 0: off)");
  window->default_val(HabPpParameters{}.output_window_segments);
  cmd->add_option("--out", opts->out, "write {\"length\": L, \"points\": [[x, y], ...]} to this JSON file");
  cmd->callback([opts, window] {
    opts->window_given = window->count() > 0;
    run(*opts);
  });
}

}  // namespace skyroute::cli
