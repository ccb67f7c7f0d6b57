#include "planning/fleet/fleet_local_search.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <utility>

namespace skyroute {
namespace {

// Large enough to lose every comparison, small enough that a few of them add up without overflow.
constexpr long long kNoRoute = std::numeric_limits<long long>::max() / 8;
constexpr int kDepot = -1;

struct Tour {
  long long steps = 0;
  std::vector<int> order;
};

struct Solution {
  std::vector<std::vector<int>> sequences;
  std::vector<long long> route_steps;

  long long makespan() const { return *std::max_element(route_steps.begin(), route_steps.end()); }
  long long sum() const { return std::accumulate(route_steps.begin(), route_steps.end(), 0LL); }
};

std::vector<long long> sortedDescending(std::vector<long long> steps) {
  std::sort(steps.begin(), steps.end(), std::greater<>());
  return steps;
}

// Two route times before and after a move, each pair sorted from the longer down. Comparing the
// whole fleet's sorted route times changes only where these differ (the other routes are the same
// on both sides), so the pair decides whether the move improves the objective.
std::pair<long long, long long> pairKey(long long a, long long b) { return {std::max(a, b), std::min(a, b)}; }

// The final order between candidate allocations: makespan, then sum of route times (as the GA
// and the exact solver rank them), then the sorted route times.
bool better(const Solution& x, const Solution& y) {
  const long long mx = x.makespan();
  const long long my = y.makespan();
  if (mx != my) return mx < my;
  const long long sx = x.sum();
  const long long sy = y.sum();
  if (sx != sy) return sx < sy;
  return sortedDescending(x.route_steps) < sortedDescending(y.route_steps);
}

// Held-Karp over every subset of a few tasks for one vehicle: tour(mask) is the least time from
// the depot through the tasks of mask and back; order(mask) walks the parents back. Only tours
// up to `bound` are wanted: a partial path is kept only if its time plus the straight way home
// from its last task stays within the bound (travel times obey the triangle inequality, so no
// completion of a dropped path could), and tour(mask) is kNoRoute where every tour exceeds it or
// the mask holds more tasks than `capacity`.
class SubsetTours {
 public:
  // Returns the work done: subsets visited plus partial paths extended times the tasks.
  std::uint64_t build(const TravelTimeTable& table, int vehicle, const std::vector<int>& tasks, long long bound,
                      int capacity = std::numeric_limits<int>::max()) {
    const int n = static_cast<int>(tasks.size());
    tasks_ = tasks;
    n_ = n;
    const std::size_t masks = std::size_t{1} << n;
    const std::size_t full = masks - 1;
    auto steps = [](int d) { return d == kUnreachableSteps ? kFar : d; };
    out_.resize(static_cast<std::size_t>(n));
    home_.resize(static_cast<std::size_t>(n));
    between_.resize(static_cast<std::size_t>(n * n));
    for (int l = 0; l < n; ++l) {
      out_[l] = steps(table.depotToTask(vehicle, tasks[l]));
      home_[l] = steps(table.taskToDepot(tasks[l], vehicle));
      for (int m = 0; m < n; ++m) between_[l * n + m] = steps(table.taskToTask(tasks[l], tasks[m]));
    }
    // Only the partial paths marked in valid_ are read, so the big tables need no clearing.
    path_.resize(masks * static_cast<std::size_t>(n));
    parent_.resize(masks * static_cast<std::size_t>(n));
    valid_.assign(masks, 0);
    tour_.assign(masks, kNoRoute);
    last_.assign(masks, -1);
    tour_[0] = 0;
    for (int l = 0; l < n; ++l) {
      if (out_[l] + home_[l] > bound) continue;
      const std::size_t single = std::size_t{1} << l;
      path_[single * n + l] = out_[l];
      parent_[single * n + l] = -1;
      valid_[single] = static_cast<std::uint32_t>(single);
    }
    std::uint64_t work = masks * 3;  // the tables' set-up
    for (std::size_t mask = 1; mask < masks; ++mask) {
      const std::uint32_t lasts = valid_[mask];
      if (lasts == 0) continue;
      const bool room = std::popcount(mask) < capacity;
      for (std::uint32_t bits = lasts; bits != 0; bits &= bits - 1) {
        const int last = std::countr_zero(bits);
        const int here = path_[mask * n + last];
        const long long home = here + home_[last];
        if (home < tour_[mask]) {  // strict: the lowest last task on ties
          tour_[mask] = home;
          last_[mask] = last;
        }
        if (!room) continue;
        work += static_cast<std::uint64_t>(n);
        for (std::size_t free = full & ~mask; free != 0; free &= free - 1) {
          const int next = std::countr_zero(free);
          const int there = here + between_[last * n + next];
          if (there + home_[next] > bound) continue;
          const std::size_t to = mask | std::size_t{1} << next;
          const std::size_t cell = to * n + next;
          if (!(valid_[to] >> next & 1U) || there < path_[cell]) {
            path_[cell] = there;
            parent_[cell] = static_cast<signed char>(last);
            valid_[to] |= std::uint32_t{1} << next;
          }
        }
      }
    }
    return work;
  }

  long long tour(std::size_t mask) const { return tour_[mask]; }

  std::vector<int> order(std::size_t mask) const {
    std::vector<int> out;
    int last = last_[mask];
    while (last >= 0 && mask != 0) {
      out.push_back(tasks_[static_cast<std::size_t>(last)]);
      const int before = parent_[mask * n_ + last];
      mask &= ~(std::size_t{1} << last);
      last = before;
    }
    std::reverse(out.begin(), out.end());
    return out;
  }

 private:
  static constexpr int kFar = std::numeric_limits<int>::max() / 4;  // unreachable; three still add up
  std::vector<int> tasks_;
  int n_ = 0;
  std::vector<int> out_, home_, between_;
  std::vector<int> path_;
  std::vector<signed char> parent_;
  std::vector<std::uint32_t> valid_;  // per mask: the last tasks with a partial path kept
  std::vector<long long> tour_;
  std::vector<int> last_;
};

class LocalSearch {
 public:
  LocalSearch(const FleetProblem& problem, const TravelTimeTable& table, const FleetImprovementOptions& options)
      : problem_(problem), table_(table), options_(options) {
    options_.pair_exact_max_tasks = std::clamp(options_.pair_exact_max_tasks, 0, 16);
    options_.exact_order_max_tasks = std::clamp(options_.exact_order_max_tasks, 0, 16);
    options_.triple_exact_max_tasks = std::clamp(options_.triple_exact_max_tasks, 0, 16);
    // No allocation beats the round trip to the task farthest from every vehicle that can take one.
    for (int j = 0; j < problem.taskCount(); ++j) {
      long long nearest = kNoRoute;
      for (int i = 0; i < problem.vehicleCount(); ++i) {
        if (problem.capacity(i) > 0) nearest = std::min(nearest, leg(i, kDepot, j) + leg(i, j, kDepot));
      }
      lower_bound_ = std::max(lower_bound_, nearest);
    }
  }

  std::uint64_t work() const { return work_; }
  bool exhausted() const { return work_ >= options_.max_work; }

  // Travel time between consecutive stops of `vehicle` (kDepot for its depot).
  long long leg(int vehicle, int from, int to) const {
    int d = 0;
    if (from == kDepot && to == kDepot) return 0;
    if (from == kDepot) d = table_.depotToTask(vehicle, to);
    else if (to == kDepot) d = table_.taskToDepot(from, vehicle);
    else d = table_.taskToTask(from, to);
    return d == kUnreachableSteps ? kNoRoute : d;
  }

  long long routeCost(int vehicle, const std::vector<int>& order) {
    work_ += order.size() + 1;
    long long total = 0;
    int at = kDepot;
    for (int j : order) {
      total += leg(vehicle, at, j);
      at = j;
    }
    total += leg(vehicle, at, kDepot);
    return std::min(total, kNoRoute);
  }

  // `order` with task j inserted where it lengthens the route least (the first such position).
  std::vector<int> insertCheapest(int vehicle, std::vector<int> order, int j) {
    work_ += order.size() + 1;
    std::size_t best_k = 0;
    long long best_rise = kNoRoute;
    for (std::size_t k = 0; k <= order.size(); ++k) {
      const int prev = k == 0 ? kDepot : order[k - 1];
      const int next = k == order.size() ? kDepot : order[k];
      const long long rise = leg(vehicle, prev, j) + leg(vehicle, j, next) - leg(vehicle, prev, next);
      if (rise < best_rise) {
        best_rise = rise;
        best_k = k;
      }
    }
    order.insert(order.begin() + static_cast<long>(best_k), j);
    return order;
  }

  // The best order found for `tasks` on `vehicle`, never longer than the given order: up to
  // exact_order_max_tasks tasks the optimum whenever that is within `bound` (callers only use
  // tours within it), above that 2-opt and Or-opt from the given order.
  Tour bestTour(int vehicle, std::vector<int> tasks, long long bound = kNoRoute) {
    if (tasks.empty()) return {0, {}};
    if (static_cast<int>(tasks.size()) > options_.exact_order_max_tasks) return improveOrder(vehicle, std::move(tasks));
    const long long given = routeCost(vehicle, tasks);
    std::vector<int> sorted = tasks;
    std::sort(sorted.begin(), sorted.end());
    work_ += scratch_[0].build(table_, vehicle, sorted, std::min(given - 1, bound));
    const std::size_t all = (std::size_t{1} << sorted.size()) - 1;
    if (scratch_[0].tour(all) < given) return {scratch_[0].tour(all), scratch_[0].order(all)};
    return {given, std::move(tasks)};
  }

  // Improving changes until none is left, the makespan reaches the lower bound or the budget ends:
  // pairs first (exact re-split, or relocations and swaps for pairs too loaded for it), then at a
  // pair optimum three-way re-splits with the longest route.
  void descend(Solution& s, int& moves) {
    const int nu = problem_.vehicleCount();
    version_.assign(static_cast<std::size_t>(nu), 0);
    checked_.assign(static_cast<std::size_t>(nu * nu), {-1, -1});
    checked_triples_.clear();
    std::vector<int> by_length(static_cast<std::size_t>(nu));
    while (!exhausted() && s.makespan() > lower_bound_) {  // at the bound the makespan is optimal
      std::iota(by_length.begin(), by_length.end(), 0);
      std::stable_sort(by_length.begin(), by_length.end(),
                       [&](int x, int y) { return s.route_steps[x] > s.route_steps[y]; });
      bool improved = false;
      for (std::size_t ia = 0; ia < by_length.size() && !improved && !exhausted(); ++ia) {
        for (std::size_t ib = ia + 1; ib < by_length.size() && !improved && !exhausted(); ++ib) {
          improved = improvePair(s, by_length[ia], by_length[ib]);
        }
      }
      // At a pair optimum: three-way re-splits that include a longest route.
      const int longest = by_length.front();
      for (std::size_t ib = 1; ib < by_length.size() && !improved && !exhausted(); ++ib) {
        for (std::size_t ic = ib + 1; ic < by_length.size() && !improved && !exhausted(); ++ic) {
          improved = improveTriple(s, longest, by_length[ib], by_length[ic]);
        }
      }
      if (!improved) return;
      ++moves;
    }
  }

 private:
  void apply(Solution& s, int v, Tour&& t) {
    s.sequences[v] = std::move(t.order);
    s.route_steps[v] = t.steps;
    ++version_[v];
  }

  // The best change between vehicles a and b, applied if it improves their pair of route times:
  // the exact re-split when they hold few tasks together, else relocations and swaps. Skipped
  // when neither vehicle changed since the pair was last tried (nothing new to find).
  bool improvePair(Solution& s, int a, int b) {
    const int nu = problem_.vehicleCount();
    auto& seen = checked_[static_cast<std::size_t>(std::min(a, b) * nu + std::max(a, b))];
    auto versions = [&] { return a < b ? std::pair{version_[a], version_[b]} : std::pair{version_[b], version_[a]}; };
    if (seen == versions()) return false;
    seen = versions();
    const bool small =
        static_cast<int>(s.sequences[a].size() + s.sequences[b].size()) <= options_.pair_exact_max_tasks;
    const std::optional<std::pair<Tour, Tour>> change = small ? resplit(s, a, b) : relocateOrSwap(s, a, b);
    if (!change) return false;
    apply(s, a, Tour(change->first));
    apply(s, b, Tour(change->second));
    seen = versions();
    return true;
  }

  // The best split of three vehicles' tasks among them (every split, exact tours), applied if it
  // improves their three route times; skipped as improvePair skips.
  bool improveTriple(Solution& s, int a, int b, int c) {
    std::array<int, 3> v{a, b, c};
    std::sort(v.begin(), v.end());
    const std::array<int, 3> versions{version_[v[0]], version_[v[1]], version_[v[2]]};
    const std::size_t nu = static_cast<std::size_t>(problem_.vehicleCount());
    auto [entry, added] = checked_triples_.try_emplace(
        (static_cast<std::uint64_t>(v[0]) * nu + static_cast<std::uint64_t>(v[1])) * nu + static_cast<std::uint64_t>(v[2]),
        std::array<int, 3>{-1, -1, -1});
    auto& seen = entry->second;
    if (!added && seen == versions) return false;
    seen = versions;
    std::vector<int> tasks;
    for (int i : v) tasks.insert(tasks.end(), s.sequences[i].begin(), s.sequences[i].end());
    const int n = static_cast<int>(tasks.size());
    if (n == 0 || n > options_.triple_exact_max_tasks) return false;
    std::sort(tasks.begin(), tasks.end());
    const long long bound = std::max({s.route_steps[v[0]], s.route_steps[v[1]], s.route_steps[v[2]]});
    for (int k = 0; k < 3; ++k) work_ += scratch_[k].build(table_, v[k], tasks, bound, problem_.capacity(v[k]));
    auto key3 = [](long long x, long long y, long long z) {
      std::array<long long, 3> k{x, y, z};
      std::sort(k.begin(), k.end(), std::greater<>());
      return k;
    };
    auto best = key3(s.route_steps[v[0]], s.route_steps[v[1]], s.route_steps[v[2]]);
    const std::size_t full = (std::size_t{1} << n) - 1;
    std::optional<std::pair<std::size_t, std::size_t>> best_split;
    // A split can only win if none of its tours exceeds the best split's longest so far.
    for (std::size_t m0 = 0; m0 <= full; ++m0) {
      const long long t0 = scratch_[0].tour(m0);
      if (t0 > best[0]) continue;
      const std::size_t rest = full ^ m0;
      // Every m1 within rest, from rest itself down to the empty set.
      for (std::size_t m1 = rest;; m1 = (m1 - 1) & rest) {
        ++work_;
        const long long t1 = scratch_[1].tour(m1);
        if (t1 <= best[0]) {
          const long long t2 = scratch_[2].tour(rest ^ m1);
          if (t2 <= best[0]) {
            const auto key = key3(t0, t1, t2);
            if (key < best) {  // strict: on a tie the first split met stays
              best = key;
              best_split = std::pair{m0, m1};
            }
          }
        }
        if (m1 == 0) break;
      }
    }
    if (!best_split) return false;
    const auto [m0, m1] = *best_split;
    const std::size_t masks[3] = {m0, m1, full ^ m0 ^ m1};
    for (int k = 0; k < 3; ++k) apply(s, v[k], Tour{scratch_[k].tour(masks[k]), scratch_[k].order(masks[k])});
    seen = {version_[v[0]], version_[v[1]], version_[v[2]]};
    return true;
  }

  // The best split of vehicles a's and b's tasks between the two (every subset, exact tours), if
  // it improves the pair.
  std::optional<std::pair<Tour, Tour>> resplit(const Solution& s, int a, int b) {
    std::vector<int> tasks = s.sequences[a];
    tasks.insert(tasks.end(), s.sequences[b].begin(), s.sequences[b].end());
    std::sort(tasks.begin(), tasks.end());
    const int n = static_cast<int>(tasks.size());
    if (n == 0) return std::nullopt;
    // A better split has both tours within the pair's current longer one.
    const long long bound = std::max(s.route_steps[a], s.route_steps[b]);
    work_ += scratch_[0].build(table_, a, tasks, bound, problem_.capacity(a));
    work_ += scratch_[1].build(table_, b, tasks, bound, problem_.capacity(b));
    const std::size_t full = (std::size_t{1} << n) - 1;
    work_ += full + 1;
    auto best = pairKey(s.route_steps[a], s.route_steps[b]);
    std::optional<std::size_t> best_mask;
    for (std::size_t mask = 0; mask <= full; ++mask) {
      const auto key = pairKey(scratch_[0].tour(mask), scratch_[1].tour(full ^ mask));
      if (key < best) {  // strict: on a tie the first split (lowest mask) stays
        best = key;
        best_mask = mask;
      }
    }
    if (!best_mask) return std::nullopt;
    const std::size_t m = *best_mask;
    return std::pair{Tour{scratch_[0].tour(m), scratch_[0].order(m)}, Tour{scratch_[1].tour(full ^ m), scratch_[1].order(full ^ m)}};
  }

  // The best relocation of one task (either way) or swap of two tasks between a and b, each route
  // re-ordered, if it improves the pair.
  std::optional<std::pair<Tour, Tour>> relocateOrSwap(const Solution& s, int a, int b) {
    const long long pair_max = std::max(s.route_steps[a], s.route_steps[b]);
    auto best = pairKey(s.route_steps[a], s.route_steps[b]);
    std::optional<std::pair<Tour, Tour>> out;
    auto consider = [&](Tour&& ta, Tour&& tb) {
      const auto key = pairKey(ta.steps, tb.steps);
      if (key < best) {  // strict: on a tie the move met first stays
        best = key;
        out = std::pair{std::move(ta), std::move(tb)};
      }
    };
    // Moves task x of `from` (vehicle f) to vehicle t; the pair's tours come back as (from, to).
    auto relocate = [&](int f, int t, std::size_t x) -> std::optional<std::pair<Tour, Tour>> {
      const int j = s.sequences[f][x];
      if (static_cast<int>(s.sequences[t].size()) >= problem_.capacity(t)) return std::nullopt;
      // Adding a task never shortens a route (travel times obey the triangle inequality), and a
      // route through j is at least the round trip to j: skip moves that must lose.
      if (std::max(s.route_steps[t], leg(t, kDepot, j) + leg(t, j, kDepot)) > pair_max) return std::nullopt;
      std::vector<int> rest = s.sequences[f];
      rest.erase(rest.begin() + static_cast<long>(x));
      return std::pair{bestTour(f, std::move(rest), pair_max), bestTour(t, insertCheapest(t, s.sequences[t], j), pair_max)};
    };
    for (std::size_t x = 0; x < s.sequences[a].size() && !exhausted(); ++x) {
      if (auto m = relocate(a, b, x)) consider(std::move(m->first), std::move(m->second));
    }
    for (std::size_t y = 0; y < s.sequences[b].size() && !exhausted(); ++y) {
      if (auto m = relocate(b, a, y)) consider(std::move(m->second), std::move(m->first));
    }
    for (std::size_t x = 0; x < s.sequences[a].size() && !exhausted(); ++x) {
      std::vector<int> rest_a = s.sequences[a];
      rest_a.erase(rest_a.begin() + static_cast<long>(x));
      for (std::size_t y = 0; y < s.sequences[b].size(); ++y) {
        std::vector<int> rest_b = s.sequences[b];
        rest_b.erase(rest_b.begin() + static_cast<long>(y));
        consider(bestTour(a, insertCheapest(a, rest_a, s.sequences[b][y]), pair_max),
                 bestTour(b, insertCheapest(b, std::move(rest_b), s.sequences[a][x]), pair_max));
      }
    }
    return out;
  }

  // 2-opt (reverse a stretch) and Or-opt (move a stretch of 1-3 tasks) by first improvement. The
  // deltas assume symmetric travel times (an undirected grid); the result is re-measured and the
  // given order kept unless it really got shorter.
  Tour improveOrder(int vehicle, std::vector<int> order) {
    const std::vector<int> original = order;
    const long long given = routeCost(vehicle, order);
    const int n = static_cast<int>(order.size());
    auto node = [&](int k) { return k < 0 || k >= n ? kDepot : order[k]; };
    auto d = [&](int k1, int k2) { return leg(vehicle, node(k1), node(k2)); };
    bool improved = true;
    while (improved && !exhausted()) {
      improved = false;
      work_ += static_cast<std::uint64_t>(n) * n * 4;
      for (int i = 0; i < n && !improved; ++i) {
        for (int k = i + 1; k < n && !improved; ++k) {
          if (d(i - 1, k) + d(i, k + 1) < d(i - 1, i) + d(k, k + 1)) {
            std::reverse(order.begin() + i, order.begin() + k + 1);
            improved = true;
          }
        }
      }
      for (int len = 1; len <= 3 && !improved; ++len) {
        for (int i = 0; i + len <= n && !improved; ++i) {
          const int e = i + len - 1;
          const long long removed = d(i - 1, e + 1) - d(i - 1, i) - d(e, e + 1);
          for (int q = -1; q < n && !improved; ++q) {
            if (q >= i - 1 && q <= e) continue;  // between q and q + 1, outside the stretch
            const long long added = leg(vehicle, node(q), node(i)) + leg(vehicle, node(e), node(q + 1)) - d(q, q + 1);
            if (removed + added < 0) {
              if (q < i) std::rotate(order.begin() + q + 1, order.begin() + i, order.begin() + e + 1);
              else std::rotate(order.begin() + i, order.begin() + e + 1, order.begin() + q + 1);
              improved = true;
            }
          }
        }
      }
    }
    const long long now = routeCost(vehicle, order);
    return now < given ? Tour{now, std::move(order)} : Tour{given, original};
  }

  const FleetProblem& problem_;
  const TravelTimeTable& table_;
  FleetImprovementOptions options_;
  SubsetTours scratch_[3];
  std::vector<int> version_;                      // per vehicle: bumped on every change
  std::vector<std::pair<int, int>> checked_;      // per pair: the versions last tried
  std::unordered_map<std::uint64_t, std::array<int, 3>> checked_triples_;  // per sorted triple: versions last tried
  std::uint64_t work_ = 0;
  long long lower_bound_ = 0;  // on the makespan of any allocation
};

}  // namespace

FleetAllocation improveAllocation(const FleetProblem& problem, const TravelTimeTable& table,
                                  const FleetAllocation& start, const FleetImprovementOptions& options,
                                  FleetImprovementReport* report) {
  const auto started = std::chrono::steady_clock::now();
  FleetImprovementReport local_report;
  FleetImprovementReport& rep = report != nullptr ? *report : local_report;
  rep = FleetImprovementReport{};
  rep.start_makespan_steps = start.makespan_steps;
  const int nu = problem.vehicleCount();
  if (!options.enabled || nu == 0 || static_cast<int>(start.sequences.size()) != nu) return start;
  for (int i = 0; i < nu; ++i) {
    if (routeSteps(table, i, start.sequences[i]) == kUnreachableSteps) return start;
  }

  LocalSearch search(problem, table, options);
  Solution input;
  input.sequences = start.sequences;
  for (int i = 0; i < nu; ++i) input.route_steps.push_back(search.routeCost(i, input.sequences[i]));

  // First every route in its best order, then the descent.
  Solution current = input;
  for (int i = 0; i < nu; ++i) {
    Tour t = search.bestTour(i, current.sequences[i]);
    current.sequences[i] = std::move(t.order);
    current.route_steps[i] = t.steps;
  }
  search.descend(current, rep.moves);
  Solution best = better(current, input) ? current : input;

  rep.work = search.work();
  rep.budget_exhausted = search.exhausted();
  FleetAllocation out = start;
  out.sequences = best.sequences;
  refreshAllocationCosts(table, out);
  out.algorithm = start.algorithm + "+improvement";
  out.evaluations += search.work();
  out.time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return out;
}

}  // namespace skyroute
