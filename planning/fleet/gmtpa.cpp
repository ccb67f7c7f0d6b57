#include "planning/fleet/gmtpa.hpp"

#include <algorithm>
#include <chrono>
#include <tuple>

namespace skyroute {

Result<FleetAllocation> allocateGreedy(const FleetProblem& problem, const TravelTimeTable& table) {
  const auto start = std::chrono::steady_clock::now();
  const int nu = problem.vehicleCount();
  const int nt = problem.taskCount();
  FleetAllocation out;
  out.algorithm = "greedy";
  out.sequences.assign(static_cast<std::size_t>(nu), {});
  std::vector<long long> route(static_cast<std::size_t>(nu), 0);  // T_i
  long long t_max = 0;
  std::vector<bool> assigned(static_cast<std::size_t>(nt), false);

  // Travel time between consecutive stops; -1 stands for the vehicle's depot.
  auto leg = [&](int vehicle, int from, int to) -> long long {
    int d = 0;
    if (from < 0 && to < 0) d = 0;
    else if (from < 0) d = table.depotToTask(vehicle, to);
    else if (to < 0) d = table.taskToDepot(from, vehicle);
    else d = table.taskToTask(from, to);
    return d == kUnreachableSteps ? -1 : d;
  };

  for (int round = 0; round < nt; ++round) {
    // (c_ijk, own rise, j, i, -k) compared lexicographically: on a full tie the later position,
    // so a task passed on the way is done when passed, not on a second visit.
    std::tuple<long long, long long, int, int, int> best{-1, -1, -1, -1, -1};
    bool found = false;
    for (int j = 0; j < nt; ++j) {
      if (assigned[j]) continue;
      for (int i = 0; i < nu; ++i) {
        const auto& seq = out.sequences[i];
        const int n_i = static_cast<int>(seq.size());
        if (n_i >= problem.capacity(i)) continue;
        for (int k = 0; k <= n_i; ++k) {
          const int prev = k == 0 ? -1 : seq[k - 1];
          const int next = k == n_i ? -1 : seq[k];
          const long long in = leg(i, prev, j);
          const long long outl = leg(i, j, next);
          const long long skip = leg(i, prev, next);
          ++out.evaluations;
          if (in < 0 || outl < 0 || skip < 0) continue;
          const long long rise = in + outl - skip;
          const long long cost = std::max(route[i] + rise, t_max) - t_max;
          const auto key = std::make_tuple(cost, rise, j, i, -k);
          if (!found || key < best) {
            best = key;
            found = true;
          }
        }
      }
    }
    if (!found) {
      int j = 0;
      while (assigned[j]) ++j;
      return make_error(ErrorCode::kUnreachable, "task " + problem.tasks[j].id,
                        "cannot be given to any vehicle that reaches it and has room left");
    }
    const auto [cost, rise, j, i, minus_k] = best;
    const int k = -minus_k;
    out.sequences[i].insert(out.sequences[i].begin() + k, j);
    route[i] += rise;
    t_max = std::max(t_max, route[i]);
    assigned[j] = true;
  }
  refreshAllocationCosts(table, out);
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace skyroute
