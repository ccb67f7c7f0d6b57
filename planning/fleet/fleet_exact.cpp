#include "planning/fleet/fleet_exact.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <limits>

namespace skyroute {
namespace {

constexpr int kInf = std::numeric_limits<int>::max() / 4;

// Held-Karp over the tasks for one vehicle: tour[mask] = least depot -> mask -> depot time.
// With keep_order, also returns the visiting order of `want`.
std::vector<int> tourCosts(const TravelTimeTable& table, int vehicle, int nt, int capacity, std::uint64_t& cells,
                           int want = -1, std::vector<int>* order = nullptr) {
  const std::size_t masks = std::size_t{1} << nt;
  auto d = [](int steps) { return steps == kUnreachableSteps ? kInf : steps; };
  // path[mask * nt + last]: least time from the depot through every task of mask, ending at last.
  std::vector<int> path(masks * nt, kInf);
  for (int j = 0; j < nt; ++j) path[(std::size_t{1} << j) * nt + j] = d(table.depotToTask(vehicle, j));
  for (std::size_t mask = 1; mask < masks; ++mask) {
    if (std::popcount(mask) > capacity) continue;
    for (int last = 0; last < nt; ++last) {
      const int here = path[mask * nt + last];
      if (!(mask >> last & 1) || here >= kInf) continue;
      for (int next = 0; next < nt; ++next) {
        if (mask >> next & 1) continue;
        ++cells;
        const int step = d(table.taskToTask(last, next));
        if (step >= kInf) continue;
        int& there = path[(mask | std::size_t{1} << next) * nt + next];
        there = std::min(there, here + step);
      }
    }
  }
  std::vector<int> tour(masks, kInf);
  tour[0] = 0;
  for (std::size_t mask = 1; mask < masks; ++mask) {
    if (std::popcount(mask) > capacity) continue;
    for (int last = 0; last < nt; ++last) {
      if (!(mask >> last & 1) || path[mask * nt + last] >= kInf) continue;
      const int back = d(table.taskToDepot(last, vehicle));
      if (back < kInf) tour[mask] = std::min(tour[mask], path[mask * nt + last] + back);
    }
  }
  if (order != nullptr && want > 0) {
    // Walk back from the best last task (lowest index on ties).
    std::size_t mask = static_cast<std::size_t>(want);
    int last = -1;
    for (int j = 0; j < nt; ++j) {
      if ((mask >> j & 1) && path[mask * nt + j] < kInf &&
          path[mask * nt + j] + d(table.taskToDepot(j, vehicle)) == tour[mask]) {
        last = j;
        break;
      }
    }
    while (last >= 0) {
      order->push_back(last);
      const std::size_t rest = mask & ~(std::size_t{1} << last);
      if (rest == 0) break;
      int prev = -1;
      for (int j = 0; j < nt; ++j) {
        if ((rest >> j & 1) && path[rest * nt + j] < kInf &&
            path[rest * nt + j] + d(table.taskToTask(j, last)) == path[mask * nt + last]) {
          prev = j;
          break;
        }
      }
      mask = rest;
      last = prev;
    }
    std::reverse(order->begin(), order->end());
  }
  return tour;
}

}  // namespace

Result<FleetAllocation> allocateExact(const FleetProblem& problem, const TravelTimeTable& table,
                                      const FleetExactOptions& options, const TerminationCondition& stop) {
  const auto start = std::chrono::steady_clock::now();
  const int nu = problem.vehicleCount();
  const int nt = problem.taskCount();
  if (nt > options.max_tasks || nt > 20) {
    return make_error(ErrorCode::kInvalidArgument, "tasks",
                      "the exact solver handles at most " + std::to_string(std::min(options.max_tasks, 20)) +
                          " tasks, got " + std::to_string(nt));
  }
  FleetAllocation out;
  out.algorithm = "exact";
  const std::size_t masks = std::size_t{1} << nt;
  const std::size_t full = masks - 1;

  std::vector<std::vector<int>> tour(static_cast<std::size_t>(nu));
  for (int i = 0; i < nu; ++i) {
    tour[i] = tourCosts(table, i, nt, problem.capacity(i), out.evaluations);
    if (stop.shouldStop()) {
      const auto reason = stop.reason();
      return make_error(reason == TerminationCondition::Reason::kCancelled ? ErrorCode::kCancelled : ErrorCode::kTimeout,
                        "exact", "exact allocation stopped: " + std::string(to_string(reason)));
    }
  }

  // best[i][mask]: least (makespan, sum) packed as makespan * 2^32 + sum, for vehicles 0..i
  // sharing the tasks of mask; pick[i][mask]: the subset vehicle i takes.
  auto pack = [](long long makespan, long long sum) { return (makespan << 32) + sum; };
  constexpr long long kNone = std::numeric_limits<long long>::max();
  std::vector<std::vector<long long>> best(static_cast<std::size_t>(nu), std::vector<long long>(masks, kNone));
  std::vector<std::vector<std::uint32_t>> pick(static_cast<std::size_t>(nu), std::vector<std::uint32_t>(masks, 0));
  for (std::size_t mask = 0; mask < masks; ++mask) {
    if (tour[0][mask] < kInf) {
      best[0][mask] = pack(tour[0][mask], tour[0][mask]);
      pick[0][mask] = static_cast<std::uint32_t>(mask);
    }
  }
  for (int i = 1; i < nu; ++i) {
    for (std::size_t mask = 0; mask < masks; ++mask) {
      long long here = kNone;
      std::uint32_t chosen = 0;
      for (std::size_t sub = mask;; sub = (sub - 1) & mask) {
        ++out.evaluations;
        const long long rest = best[i - 1][mask ^ sub];
        const int own = tour[i][sub];
        if (rest != kNone && own < kInf) {
          const long long makespan = std::max<long long>(rest >> 32, own);
          const long long value = pack(makespan, (rest & 0xffffffffLL) + own);
          if (value < here) {
            here = value;
            chosen = static_cast<std::uint32_t>(sub);
          }
        }
        if (sub == 0) break;
      }
      best[i][mask] = here;
      pick[i][mask] = chosen;
    }
    if (stop.shouldStop()) {
      const auto reason = stop.reason();
      return make_error(reason == TerminationCondition::Reason::kCancelled ? ErrorCode::kCancelled : ErrorCode::kTimeout,
                        "exact", "exact allocation stopped: " + std::string(to_string(reason)));
    }
  }
  if (best[nu - 1][full] == kNone) {
    return make_error(ErrorCode::kUnreachable, "tasks",
                      "no split of the tasks lets every vehicle reach its tasks within its capacity");
  }
  out.sequences.assign(static_cast<std::size_t>(nu), {});
  std::size_t mask = full;
  for (int i = nu - 1; i >= 0; --i) {
    const std::size_t sub = pick[i][mask];
    std::uint64_t ignored = 0;
    if (sub != 0) tourCosts(table, i, nt, problem.capacity(i), ignored, static_cast<int>(sub), &out.sequences[i]);
    mask ^= sub;
  }
  refreshAllocationCosts(table, out);
  out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace skyroute
