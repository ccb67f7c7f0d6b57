#include "planning/fleet/fleet_paths.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>

#include "planning/grid/space_time_astar.hpp"

namespace skyroute {

GridCell VehiclePlan::cellAt(int step) const {
  if (cells.empty()) return GridCell{};
  if (step <= 0) return cells.front();
  if (step >= static_cast<int>(cells.size())) return cells.back();
  return cells[static_cast<std::size_t>(step)];
}

std::string_view to_string(FleetPathStatus status) {
  switch (status) {
    case FleetPathStatus::kSolved: return "solved";
    case FleetPathStatus::kUnresolved: return "unresolved conflicts";
    case FleetPathStatus::kStopped: return "stopped";
  }
  return "unknown";
}

namespace {

// One vehicle's route while the conflicts are worked out: waypoints are the depot, its tasks and
// the depot again; reached[k] is the step at which waypoint k is reached.
struct Route {
  std::vector<GridCell> waypoints;
  std::vector<const std::vector<int>*> maps;  // distance map to each waypoint
  std::vector<int> reached;
  std::vector<GridCell> cells;

  int last() const { return static_cast<int>(waypoints.size()) - 1; }
  int finish() const { return static_cast<int>(cells.size()) - 1; }
  GridCell at(int step) const {
    return step >= static_cast<int>(cells.size()) ? cells.back() : cells[static_cast<std::size_t>(step)];
  }
  // Shortest static legs from waypoint `from` (where cells ends) to the end.
  void appendStaticLegs(const GridLayer& grid, int from) {
    for (int k = from + 1; k <= last(); ++k) {
      const auto leg = descendDistanceMap4(grid, *maps[static_cast<std::size_t>(k)], cells.back());
      cells.insert(cells.end(), leg.begin() + 1, leg.end());
      reached[static_cast<std::size_t>(k)] = finish();
    }
  }
};

struct Conflict {
  int a = -1;  // vehicle
  int b = -1;  // vehicle, or vehicle count + obstacle index
  int step = 0;  // the move step -> step + 1
};

class PathResolver {
 public:
  PathResolver(const GridLayer& grid, const FleetProblem& problem, const TravelTimeTable& table,
               const FleetPathOptions& options, const TerminationCondition& stop)
      : grid_(grid), problem_(problem), table_(table), options_(options), stop_(stop), reservations_(grid) {}

  FleetPaths run(const FleetAllocation& allocation) {
    const auto started = std::chrono::steady_clock::now();
    FleetPaths out;
    const int nu = problem_.vehicleCount();
    routes_.resize(static_cast<std::size_t>(nu));
    for (int i = 0; i < nu; ++i) {
      Route& r = routes_[static_cast<std::size_t>(i)];
      const GridCell depot = problem_.vehicles[static_cast<std::size_t>(i)].depot;
      r.waypoints.push_back(depot);
      r.maps.push_back(&table_.mapToDepot(i));
      for (int j : allocation.sequences[static_cast<std::size_t>(i)]) {
        r.waypoints.push_back(problem_.tasks[static_cast<std::size_t>(j)].cell);
        r.maps.push_back(&table_.mapToTask(j));
      }
      if (r.waypoints.size() > 1) {
        r.waypoints.push_back(depot);
        r.maps.push_back(&table_.mapToDepot(i));
      }
      r.reached.assign(r.waypoints.size(), 0);
      r.cells = {depot};
      r.appendStaticLegs(grid_, 0);
      reservations_.reservePath(i, 0, r.cells, true);
    }
    for (std::size_t k = 0; k < problem_.moving_obstacles.size(); ++k) {
      const MovingObstacle& o = problem_.moving_obstacles[k];
      for (int s = o.start_step; s < o.endStep(); ++s) reservations_.reserveCellAt(nu + static_cast<int>(k), *o.cellAt(s), s);
    }

    const int budget = options_.max_resolutions > 0 ? options_.max_resolutions
                                                     : 100 + 50 * nu + 10 * problem_.taskCount();
    out.status = FleetPathStatus::kSolved;
    int s = 0;
    while (s < endStep()) {
      const std::optional<Conflict> c = firstConflict(s);
      if (!c) {
        ++s;
        continue;
      }
      if (stop_.shouldStop()) {
        out.status = FleetPathStatus::kStopped;
        out.detail = "stopped while resolving conflicts at step " + std::to_string(s);
        break;
      }
      if (out.conflicts_resolved >= budget) {
        out.status = FleetPathStatus::kUnresolved;
        out.detail = "gave up after " + std::to_string(budget) + " conflicts; the last at step " +
                     std::to_string(c->step + 1) + " between " + name(c->a) + " and " + name(c->b);
        break;
      }
      ++out.conflicts_resolved;
      s = resolve(*c, out);  // paths changed from this step on: look again from there
    }

    for (int i = 0; i < nu; ++i) {
      Route& r = routes_[static_cast<std::size_t>(i)];
      while (r.cells.size() >= 2 && r.cells[r.cells.size() - 1] == r.cells[r.cells.size() - 2] &&
             r.finish() > r.reached.back()) {
        r.cells.pop_back();
      }
      VehiclePlan v;
      v.vehicle = i;
      v.tasks = allocation.sequences[static_cast<std::size_t>(i)];
      v.cells = r.cells;
      v.task_steps.assign(r.reached.begin() + 1, r.reached.end() - (r.waypoints.size() > 1 ? 1 : 0));
      v.finish_step = r.finish();
      out.makespan_steps = std::max(out.makespan_steps, v.finish_step);
      out.sum_of_steps += v.finish_step;
      out.vehicles.push_back(std::move(v));
    }
    out.expansions = expansions_;
    out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return out;
  }

 private:
  int vehicleCount() const { return static_cast<int>(routes_.size()); }
  std::string name(int agent) const {
    if (agent < vehicleCount()) return "vehicle " + problem_.vehicles[static_cast<std::size_t>(agent)].id;
    return "moving obstacle " + problem_.moving_obstacles[static_cast<std::size_t>(agent - vehicleCount())].id;
  }
  // Past this step nothing moves any more: every vehicle is home and every obstacle gone.
  int endStep() const {
    int end = 0;
    for (const Route& r : routes_) end = std::max(end, r.finish());
    for (const MovingObstacle& o : problem_.moving_obstacles) end = std::max(end, o.endStep());
    return end;
  }
  int makespan() const {
    int m = 0;
    for (const Route& r : routes_) m = std::max(m, r.finish());
    return m;
  }

  std::optional<Conflict> firstConflict(int s) const {
    const int nu = vehicleCount();
    for (int a = 0; a < nu; ++a) {
      const GridCell a0 = routes_[a].at(s);
      const GridCell a1 = routes_[a].at(s + 1);
      for (int b = a + 1; b < nu; ++b) {
        const GridCell b0 = routes_[b].at(s);
        const GridCell b1 = routes_[b].at(s + 1);
        if (a1 == b1 || (a0 == b1 && a1 == b0)) return Conflict{a, b, s};
      }
      for (std::size_t k = 0; k < problem_.moving_obstacles.size(); ++k) {
        const MovingObstacle& o = problem_.moving_obstacles[k];
        const auto o0 = o.cellAt(s);
        const auto o1 = o.cellAt(s + 1);
        if ((o1 && *o1 == a1) || (o0 && o1 && *o0 == a1 && *o1 == a0)) return Conflict{a, nu + static_cast<int>(k), s};
      }
    }
    return std::nullopt;
  }

  // Slack: how far below the current makespan a vehicle finishes. Parked-for-good vehicles
  // have the most, so they move aside first.
  std::vector<int> yieldOrder(const Conflict& c) const {
    std::vector<int> order{c.a};
    if (c.b < vehicleCount()) order.push_back(c.b);
    const int m = makespan();
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
      const int sx = m - routes_[x].finish();
      const int sy = m - routes_[y].finish();
      if (sx != sy) return sx > sy;
      return x > y;  // equal slack: the later vehicle yields
    });
    return order;
  }

  bool detour(int v, int s) {
    Route& r = routes_[static_cast<std::size_t>(v)];
    int k = 1;
    while (k <= r.last() && r.reached[static_cast<std::size_t>(k)] <= s) ++k;
    if (r.last() == 0) k = 0;       // no tasks: the only waypoint is home
    else if (k > r.last()) k = r.last();  // already home: stay home
    SpaceTimeQuery q;
    q.self = v;
    q.start = r.at(s);
    q.start_step = s;
    q.goal = r.waypoints[static_cast<std::size_t>(k)];
    q.park_at_goal = k == r.last();
    q.heuristic = r.maps[static_cast<std::size_t>(k)];
    q.max_expansions = options_.max_expansions_per_search;
    const SpaceTimePath found = planSpaceTime(grid_, reservations_, q, stop_);
    expansions_ += found.expansions;
    if (!found.found()) return false;
    r.cells.resize(static_cast<std::size_t>(s) + 1, r.cells.back());  // home until s when parked
    r.cells.insert(r.cells.end(), found.cells.begin() + 1, found.cells.end());
    r.reached[static_cast<std::size_t>(k)] = r.finish();
    r.appendStaticLegs(grid_, k);
    rereserve(v);
    return true;
  }

  bool wait(int v, int s) {
    Route& r = routes_[static_cast<std::size_t>(v)];
    if (s >= r.finish()) return false;  // home for good: waiting changes nothing
    r.cells.insert(r.cells.begin() + s + 1, r.cells[static_cast<std::size_t>(s)]);
    for (int& step : r.reached) {
      if (step > s) ++step;
    }
    rereserve(v);
    return true;
  }

  void rereserve(int v) {
    reservations_.clearAgent(v);
    reservations_.reservePath(v, 0, routes_[static_cast<std::size_t>(v)].cells, true);
  }

  // Returns the first step at which a path changed (the conflict's step when none did).
  int resolve(const Conflict& c, FleetPaths& out) {
    const std::vector<int> order = yieldOrder(c);
    const auto pair = std::make_pair(c.a, c.b);
    const int seen = ++pair_conflicts_[pair];
    // A detour from the conflict's step first; when the vehicle is already cornered there, from a
    // few steps earlier (e.g. a parked vehicle must reach a niche before the other arrives).
    auto try_detours = [&]() -> std::optional<int> {
      for (int back = 0; back <= options_.max_backtrack_steps && c.step - back >= 0; ++back) {
        for (int v : order) {
          if (detour(v, c.step - back)) return c.step - back;
        }
      }
      return std::nullopt;
    };
    if (seen <= options_.max_detours_per_pair) {
      if (auto from = try_detours()) {
        ++out.detours;
        return *from;
      }
    }
    for (int v : order) {
      if (wait(v, c.step)) {
        ++out.waits;
        return c.step;
      }
    }
    // Nobody can wait (all involved are home for good): detour regardless of the count.
    if (auto from = try_detours()) {
      ++out.detours;
      return *from;
    }
    return c.step;
  }

  const GridLayer& grid_;
  const FleetProblem& problem_;
  const TravelTimeTable& table_;
  FleetPathOptions options_;
  const TerminationCondition& stop_;
  CellTimeReservations reservations_;
  std::vector<Route> routes_;
  std::map<std::pair<int, int>, int> pair_conflicts_;
  std::uint64_t expansions_ = 0;
};

}  // namespace

FleetPaths buildFleetPaths(const GridLayer& grid, const FleetProblem& problem, const TravelTimeTable& table,
                           const FleetAllocation& allocation, const FleetPathOptions& options,
                           const TerminationCondition& stop) {
  PathResolver resolver(grid, problem, table, options, stop);
  return resolver.run(allocation);
}

}  // namespace skyroute
