// Open travelling salesman path: from node 0 (the begin point B) through every node 1..m (the
// mission points) to node m+1 (the end E), minimising the sum of (possibly asymmetric) edge costs.
// Exact by Held-Karp dynamic programming up to `max_exact_points` mission points (O(2^m m^2));
// above that a heuristic: nearest-neighbour and cheapest-insertion construction, then 2-opt and
// Or-opt local search. Where both run, the heuristic's gap to the exact cost is reported.
#pragma once

#include <optional>
#include <vector>

#include "planning/core/result.hpp"

namespace skyroute {

struct OpenTspOptions {
  int max_exact_points = 16;     // Held-Karp up to this many mission points (memory 2^m * m doubles)
  bool compare_heuristic = true; // also run the heuristic where Held-Karp runs, to report its gap
};

struct OpenTspResult {
  std::vector<int> order;  // every node 0..m+1 in visiting order: 0 first, m+1 last
  double cost = 0.0;
  bool exact = false;
  std::optional<double> heuristic_cost;  // when the heuristic ran next to Held-Karp
  std::optional<double> gap;             // (heuristic - exact) / exact, when both ran
};

// cost[i][j]: cost from node i to node j, square (m+2)x(m+2); entries the path cannot use (into 0,
// out of m+1, the diagonal) are ignored. Errors: kInvalidArgument (not square, fewer than 2 nodes,
// a NaN or negative cost), kUnreachable (no finite path through every node).
Result<OpenTspResult> solveOpenTsp(const std::vector<std::vector<double>>& cost, const OpenTspOptions& options = {});

// The parts, for tests and benchmarks.
Result<OpenTspResult> solveOpenTspExact(const std::vector<std::vector<double>>& cost);
Result<OpenTspResult> solveOpenTspHeuristic(const std::vector<std::vector<double>>& cost);
double openTspPathCost(const std::vector<std::vector<double>>& cost, const std::vector<int>& order);

}  // namespace skyroute
