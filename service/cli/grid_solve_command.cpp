// skyroute grid solve: every problem of a Moving AI scenario with one of the grid searches, one
// JSON line per problem in the scenario's order, then a summary line. Exits 1 only when a cost is
// wrong: a problem left unsolved, or (with the benchmark's own move rules) a cost that differs
// from the scenario's optimal length.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "planning/grid/dstar_lite.hpp"
#include "planning/grid/grid_search.hpp"
#include "planning/mission/mmdstar_lite.hpp"
#include "service/cli/cli_parse.hpp"
#include "service/cli/commands.hpp"
#include "terrain/movingai.hpp"

namespace skyroute::cli {
namespace {

const std::string kTool = "grid solve";

// The floating error of a scenario's optimal length, relative to it. The generator of the Moving
// AI files printed with six significant digits summed the diagonals with sqrt(2) in single
// precision (1.41421354, 2.4e-8 short), so a length is up to 1.7e-8 of itself short before it is
// printed: 655.2935060 was printed "655.293" (655.2934990 rounded), 6e-6 beyond half a unit.
// 2e-8 covers that and the double sums of the files printed with eight decimals (1e-9 relative).
constexpr double kScenarioRelativeError = 2e-8;

struct SolveArgs {
  std::string map;
  std::string scen;
  std::string algo = "astar";
  std::optional<std::size_t> limit;  // none: every problem
  bool paper_moves = false;
};

void runSolve(const SolveArgs& args) {
  auto grid = loadMovingAiMap(args.map);
  if (!grid.ok()) fail(kTool, kExitBadInput, "--map " + grid.error().describe());
  auto problems = loadMovingAiScenario(args.scen);
  if (!problems.ok()) fail(kTool, kExitBadInput, "--scen " + problems.error().describe());
  const GridMoves moves = args.paper_moves ? GridMoves::paper() : GridMoves{};
  const std::size_t count = std::min(problems->size(), args.limit.value_or(problems->size()));

  // mmdstar: problems that share a goal (consecutively) share one g/rhs map, as MMD*L does.
  std::unique_ptr<SharedGoalSearch> shared;
  std::size_t solved = 0, mismatches = 0, failures = 0;
  double max_error = 0.0, total_ms = 0.0;
  long first_mismatch = -1;  // index of the first problem whose cost differs from the scenario's
  std::uint64_t total_expansions = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const MovingAiProblem& pr = (*problems)[i];
    PlannerStatus status;
    double cost = kInfiniteCost;
    SearchStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    if (args.algo == "astar" || args.algo == "dijkstra") {
      const GridPath p = args.algo == "astar" ? astarSearch(*grid, pr.start, pr.goal, moves)
                                              : dijkstraSearch(*grid, pr.start, pr.goal, moves);
      status = p.status;
      cost = p.cost;
      stats = p.stats;
    } else if (args.algo == "dstar-lite") {
      DStarLite search(*grid, pr.start, pr.goal, moves);
      status = search.computeShortestPath();
      cost = search.cost();
      stats = search.stats();
    } else {
      if (!shared || !(shared->goal() == pr.goal)) shared = std::make_unique<SharedGoalSearch>(*grid, pr.goal, moves);
      const SearchStats before = shared->stats();
      status = shared->solveFrom(pr.start);
      cost = shared->cost(pr.start);
      stats = shared->stats();
      stats.expansions -= before.expansions;
      stats.queue_pushes -= before.queue_pushes;
      stats.queue_pops -= before.queue_pops;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json j;
    j["index"] = i;
    j["start"] = {pr.start.x, pr.start.y};
    j["goal"] = {pr.goal.x, pr.goal.y};
    j["status"] = std::string(to_string(status));
    if (std::isfinite(cost))
      j["cost"] = cost;
    else
      j["cost"] = nullptr;
    j["optimal"] = pr.optimal_length;
    j["tolerance"] = pr.optimal_tolerance;
    j["expansions"] = stats.expansions;
    j["queue_ops"] = stats.queue_pushes + stats.queue_pops;
    j["time_ms"] = ms;
    std::cout << j.dump() << "\n";
    total_ms += ms;
    total_expansions += stats.expansions;
    if (status != PlannerStatus::kSolved) {
      ++failures;
      continue;
    }
    ++solved;
    // Only the benchmark's own move rules are comparable with its optimal lengths, and only to
    // the digits each line printed its length with (half a unit in the last one), plus the
    // floating error of the lengths (kScenarioRelativeError).
    const double err = std::abs(cost - pr.optimal_length);
    if (!args.paper_moves) {
      max_error = std::max(max_error, err);
      if (err > pr.optimal_tolerance + kScenarioRelativeError * std::max(1.0, pr.optimal_length)) {
        ++mismatches;
        if (first_mismatch < 0) first_mismatch = static_cast<long>(i);
      }
    }
  }
  nlohmann::json summary;
  summary["summary"] = true;
  summary["algo"] = args.algo;
  summary["map"] = args.map;
  summary["scen"] = args.scen;
  summary["problems"] = count;
  summary["solved"] = solved;
  summary["failed"] = failures;
  summary["mismatches"] = args.paper_moves ? nlohmann::json(nullptr) : nlohmann::json(mismatches);
  summary["max_abs_error"] = args.paper_moves ? nlohmann::json(nullptr) : nlohmann::json(max_error);
  summary["expansions"] = total_expansions;
  summary["time_ms"] = total_ms;
  std::cout << summary.dump() << std::endl;
  if (!args.paper_moves) {
    std::cerr << "largest error against the scenario's optimal lengths: " << max_error << " ("
              << (mismatches == 0 ? "every cost agrees to the printed digits"
                                  : std::to_string(mismatches) + " costs differ beyond the printed digits, the first "
                                                                 "at problem " + std::to_string(first_mismatch))
              << ")\n";
  }
  if (failures > 0 || mismatches > 0) {
    fail(kTool, kExitPlanningFailed,
         std::to_string(failures + mismatches) + " of " + std::to_string(count) + " costs are wrong (" +
             std::to_string(failures) + " unsolved, " + std::to_string(mismatches) +
             " off the scenario's optimal lengths)");
  }
}

}  // namespace

void addGridSolveCommand(CLI::App& grid) {
  auto args = std::make_shared<SolveArgs>();
  CLI::App* cmd = grid.add_subcommand(
      "solve", "Solve every problem of a Moving AI scenario; one JSON line per problem, then a summary");
  cmd->add_option("--map", args->map, "Moving AI .map file")->required();
  cmd->add_option("--scen", args->scen, "Moving AI .scen file (version 1)")->required();
  cmd->footer(helpFooter({"skyroute grid solve --map room-32-32-4.map --scen room-32-32-4-random-1.scen --algo mmdstar "
                          "--limit 100"}));
  cmd->add_option("--algo", args->algo, "astar | dijkstra | dstar-lite | mmdstar")
      ->check(CLI::IsMember({"astar", "dijkstra", "dstar-lite", "mmdstar"}))
      ->capture_default_str();
  cmd->add_option("--limit", args->limit, "solve only the first N problems (default: all)");
  cmd->add_flag("--paper-moves", args->paper_moves,
                "diagonal cost 1.4 and the Chebyshev heuristic, as in the MMD*L paper (costs then differ from the "
                "scenario's optimal lengths, which are not checked)");
  cmd->callback([args]() { runSolve(*args); });
}

}  // namespace skyroute::cli
