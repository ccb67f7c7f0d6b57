#include "planning/mission/open_tsp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace skyroute {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Status validate(const std::vector<std::vector<double>>& cost) {
  const std::size_t n = cost.size();
  if (n < 2) return make_error(ErrorCode::kInvalidArgument, "cost", "needs at least the begin and the end node");
  for (std::size_t i = 0; i < n; ++i) {
    if (cost[i].size() != n)
      return make_error(ErrorCode::kInvalidArgument, "cost",
                        "row " + std::to_string(i) + " has " + std::to_string(cost[i].size()) + " entries, expected " +
                            std::to_string(n));
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j || j == 0 || i == n - 1) continue;
      if (std::isnan(cost[i][j]) || cost[i][j] < 0.0)
        return make_error(ErrorCode::kInvalidArgument, "cost",
                          "entry [" + std::to_string(i) + "][" + std::to_string(j) + "] is negative or NaN");
    }
  }
  return Status::success();
}

Error unreachable() {
  return make_error(ErrorCode::kUnreachable, "cost", "no finite path visits every mission point between begin and end");
}

// 2-opt (reverse a segment) and Or-opt (move a segment of 1..3 nodes, either direction) on the
// inner nodes until no move improves; costs may be asymmetric, so every move is re-evaluated.
void improve(const std::vector<std::vector<double>>& cost, std::vector<int>& order) {
  const int last = static_cast<int>(order.size()) - 1;  // order[0] = begin, order[last] = end: fixed
  double best = openTspPathCost(cost, order);
  bool improved = true;
  std::vector<int> trial;
  while (improved) {
    improved = false;
    for (int i = 1; i < last && !improved; ++i) {
      for (int j = i + 1; j < last && !improved; ++j) {
        trial = order;
        std::reverse(trial.begin() + i, trial.begin() + j + 1);
        const double c = openTspPathCost(cost, trial);
        if (c < best - 1e-12) {
          order.swap(trial);
          best = c;
          improved = true;
        }
      }
    }
    for (int len = 1; len <= 3 && !improved; ++len) {
      for (int i = 1; i + len - 1 < last && !improved; ++i) {
        std::vector<int> segment(order.begin() + i, order.begin() + i + len);
        std::vector<int> rest(order.begin(), order.begin() + i);
        rest.insert(rest.end(), order.begin() + i + len, order.end());
        for (int reversed = 0; reversed < 2 && !improved; ++reversed) {
          if (reversed) std::reverse(segment.begin(), segment.end());
          for (int k = 1; k < static_cast<int>(rest.size()) && !improved; ++k) {  // insert before rest[k]
            trial = rest;
            trial.insert(trial.begin() + k, segment.begin(), segment.end());
            const double c = openTspPathCost(cost, trial);
            if (c < best - 1e-12) {
              order.swap(trial);
              best = c;
              improved = true;
            }
          }
        }
      }
    }
  }
}

std::vector<int> nearestNeighbour(const std::vector<std::vector<double>>& cost) {
  const int n = static_cast<int>(cost.size());
  std::vector<int> order{0};
  std::vector<char> used(n, 0);
  used[0] = used[n - 1] = 1;
  for (int step = 1; step < n - 1; ++step) {
    int best = -1;
    for (int j = 1; j < n - 1; ++j)
      if (!used[j] && (best < 0 || cost[order.back()][j] < cost[order.back()][best])) best = j;
    used[best] = 1;
    order.push_back(best);
  }
  order.push_back(n - 1);
  return order;
}

std::vector<int> cheapestInsertion(const std::vector<std::vector<double>>& cost) {
  const int n = static_cast<int>(cost.size());
  std::vector<int> order{0, n - 1};
  std::vector<char> used(n, 0);
  used[0] = used[n - 1] = 1;
  for (int step = 1; step < n - 1; ++step) {
    int best_node = -1;
    std::size_t best_pos = 1;
    double best_delta = kInf;
    for (int j = 1; j < n - 1; ++j) {
      if (used[j]) continue;
      for (std::size_t p = 1; p < order.size(); ++p) {
        const double d = cost[order[p - 1]][j] + cost[j][order[p]] - cost[order[p - 1]][order[p]];
        if (best_node < 0 || d < best_delta) {
          best_node = j;
          best_pos = p;
          best_delta = d;
        }
      }
    }
    used[best_node] = 1;
    order.insert(order.begin() + static_cast<long>(best_pos), best_node);
  }
  return order;
}

}  // namespace

double openTspPathCost(const std::vector<std::vector<double>>& cost, const std::vector<int>& order) {
  double total = 0.0;
  for (std::size_t i = 1; i < order.size(); ++i) total += cost[order[i - 1]][order[i]];
  return total;
}

Result<OpenTspResult> solveOpenTspExact(const std::vector<std::vector<double>>& cost) {
  if (Status s = validate(cost); !s) return s.error();
  const int n = static_cast<int>(cost.size());
  const int m = n - 2;
  if (m > 24) return make_error(ErrorCode::kInvalidArgument, "cost", "Held-Karp refuses more than 24 mission points");
  OpenTspResult out;
  out.exact = true;
  if (m == 0) {
    out.order = {0, 1};
    out.cost = cost[0][1];
    if (!(out.cost < kInf)) return unreachable();
    return out;
  }
  // dp[mask * m + j]: cheapest path from begin through exactly the mission nodes in mask, ending
  // at mission node j+1 (bit j of mask set).
  const std::size_t states = std::size_t{1} << m;
  std::vector<double> dp(states * m, kInf);
  std::vector<std::int8_t> prev(states * m, -1);
  for (int j = 0; j < m; ++j) dp[(std::size_t{1} << j) * m + j] = cost[0][j + 1];
  for (std::size_t mask = 1; mask < states; ++mask) {
    for (int j = 0; j < m; ++j) {
      if (!(mask >> j & 1)) continue;
      const double here = dp[mask * m + j];
      if (!(here < kInf)) continue;
      for (int k = 0; k < m; ++k) {
        if (mask >> k & 1) continue;
        const std::size_t next = mask | (std::size_t{1} << k);
        const double c = here + cost[j + 1][k + 1];
        if (c < dp[next * m + k]) {
          dp[next * m + k] = c;
          prev[next * m + k] = static_cast<std::int8_t>(j);
        }
      }
    }
  }
  const std::size_t full = states - 1;
  int best_last = -1;
  double best = kInf;
  for (int j = 0; j < m; ++j) {
    const double c = dp[full * m + j] + cost[j + 1][n - 1];
    if (c < best) {
      best = c;
      best_last = j;
    }
  }
  if (best_last < 0) return unreachable();
  std::vector<int> inner;
  std::size_t mask = full;
  for (int j = best_last; j >= 0;) {
    inner.push_back(j + 1);
    const int p = prev[mask * m + j];
    mask &= ~(std::size_t{1} << j);
    j = p;
  }
  std::reverse(inner.begin(), inner.end());
  out.order.push_back(0);
  out.order.insert(out.order.end(), inner.begin(), inner.end());
  out.order.push_back(n - 1);
  out.cost = best;
  return out;
}

Result<OpenTspResult> solveOpenTspHeuristic(const std::vector<std::vector<double>>& cost) {
  if (Status s = validate(cost); !s) return s.error();
  OpenTspResult out;
  out.exact = false;
  for (std::vector<int> order : {nearestNeighbour(cost), cheapestInsertion(cost)}) {
    improve(cost, order);
    const double c = openTspPathCost(cost, order);
    if (out.order.empty() || c < out.cost) {
      out.order = order;
      out.cost = c;
    }
  }
  if (!(out.cost < kInf)) return unreachable();
  return out;
}

Result<OpenTspResult> solveOpenTsp(const std::vector<std::vector<double>>& cost, const OpenTspOptions& options) {
  if (Status s = validate(cost); !s) return s.error();
  const int m = static_cast<int>(cost.size()) - 2;
  if (m <= options.max_exact_points) {
    Result<OpenTspResult> exact = solveOpenTspExact(cost);
    if (!exact.ok() || !options.compare_heuristic || m < 2) return exact;
    Result<OpenTspResult> heuristic = solveOpenTspHeuristic(cost);
    if (heuristic.ok()) {
      exact->heuristic_cost = heuristic->cost;
      exact->gap = exact->cost > 0.0 ? (heuristic->cost - exact->cost) / exact->cost : 0.0;
    }
    return exact;
  }
  return solveOpenTspHeuristic(cost);
}

}  // namespace skyroute
