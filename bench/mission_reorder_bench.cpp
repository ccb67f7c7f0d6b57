// Live re-ordering at mission scale (seed 000's replanning, as the daemon runs it): missions of
// --points mission points on the embedded terrain's order grid (200 x 200 cells of 64 m), flown
// along their order while a feed of moving cylinders changes (--obstacles in force, one replaced
// per update). Each update is answered by MissionReorder::check (the obstacles' cover, the
// incremental repair of the n+1 D* Lite searches, the open TSP from the vehicle) and, for
// comparison, by a from-scratch MMD*L solve of the same state (a copy of the grid, the vehicle's
// cell as begin, the points left), whose order and cost must be the same. Updates are "near" (a
// cylinder on the way to the next point) or "far" (2.5 km or more from every leg left).
//
//   build/bench/mission_reorder_bench [--points 20] [--missions 5] [--updates 40] [--obstacles 4] [--seed 1]
//
// Prints, per kind of update, cell expansions and processor time (mean +- standard deviation, as
// the seed reports them, and the largest), the re-orders, the mismatches with the from-scratch
// solve (must be 0) and the target: an update within 50 ms.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "bench/support/bench_stats.hpp"
#include "planning/mission/mission_planner.hpp"
#include "service/mission_order.hpp"
#include "service/mission_reorder.hpp"
#include "terrain/terrain_world.hpp"

using namespace skyroute;

namespace {

using skyroute::bench::Sample;
using skyroute::bench::quantile;
using skyroute::bench::processCpuMs;
using skyroute::bench::threadCpuMs;



struct Kind {
  const char* name = "";
  Sample inc_exp, inc_ms, inc_wall_ms, scratch_exp, scratch_ms;
  int updates = 0, repaired = 0, reorders = 0, mismatches = 0, cut_off = 0;
  int unchecked = 0;  // no place found for the obstacle
};

double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

int main(int argc, char** argv) {
  int points = 20, missions = 5, updates = 40, in_force = 4;
  unsigned seed = 1;
  MissionOrderOptions order_options;
  MissionReorderOptions reorder_options;
  for (int i = 1; i < argc; ++i) {
    auto value = [&]() { return i + 1 < argc ? std::atoi(argv[++i]) : 0; };
    if (!std::strcmp(argv[i], "--points")) points = value();
    else if (!std::strcmp(argv[i], "--missions")) missions = value();
    else if (!std::strcmp(argv[i], "--updates")) updates = value();
    else if (!std::strcmp(argv[i], "--obstacles")) in_force = std::max(1, value());
    else if (!std::strcmp(argv[i], "--seed")) seed = static_cast<unsigned>(value());
    else if (!std::strcmp(argv[i], "--fresh") && i + 1 < argc) order_options.fresh_plan_fraction = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--defer")) order_options.defer_goal_maps = value() != 0;
    else if (!std::strcmp(argv[i], "--threads")) reorder_options.repair_threads = value();
    else if (!std::strcmp(argv[i], "--symmetric")) order_options.symmetric_pairs = value() != 0;
    else {
      std::fprintf(stderr, "usage: mission_reorder_bench [--points N] [--missions N] [--updates N] [--obstacles N] [--seed S] [--fresh F] [--defer 0|1] [--threads N] [--symmetric 0|1]\n");
      return 2;
    }
  }
  CollisionWorldOptions world_options;
  world_options.build_octree = false;
  auto loaded = loadTerrainWorld(std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif", world_options);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.error().describe().c_str());
    return 1;
  }
  const Heightfield& terrain = *loaded->heightfield;
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto anywhere = [&] {
    return Eigen::Vector2d(box.min().x() + 0.05 * box.sizes().x() + 0.9 * box.sizes().x() * unit(rng),
                           box.min().y() + 0.05 * box.sizes().y() + 0.9 * box.sizes().y() * unit(rng));
  };
  auto above = [&](const Eigen::Vector2d& en) { return Eigen::Vector3d(en.x(), en.y(), terrain.heightAt(en.x(), en.y()) + 200.0); };

  Kind near;
  Kind far;
  near.name = "near";
  far.name = "far";
  Sample pre_exp, pre_ms;
  double worst_ms = 0.0;      // wall
  double worst_cpu_ms = 0.0;  // every thread
  double worst_search_ms = 0.0, worst_tsp_ms = 0.0;  // the largest update's repair and TSP, wall
  const double speed_mps = 20.0, step_s = 15.0;
  for (int mission = 0; mission < missions; ++mission) {
    // Points the order grid can carry (MMD*L, not the Euclidean fallback).
    MissionOrder order;
    std::vector<Eigen::Vector3d> pts;
    for (int attempt = 0; attempt < 50; ++attempt) {
      pts.clear();
      for (int k = 0; k < points + 2; ++k) pts.push_back(above(anywhere()));
      const double t0 = threadCpuMs();
      auto o = orderMissionPoints(terrain, pts, 30.0, 5000.0, false, order_options);
      const double ms = threadCpuMs() - t0;
      if (o.ok() && o->method == "mmdstar") {
        order = *o;
        pre_exp.add(static_cast<double>(o->expansions));
        pre_ms.add(ms);
        break;
      }
    }
    if (order.method != "mmdstar") {
      std::fprintf(stderr, "mission %d: no points the order grid carries\n", mission);
      return 1;
    }
    const double cell_m = order.cell_size_m;
    std::unique_ptr<MissionReorder> reorder = MissionReorder::create(order.search, reorder_options, 5.0);
    std::vector<int> reached;
    std::vector<int> flying(order.order.begin() + 1, order.order.end());
    Eigen::Vector2d vehicle = pts.front().head<2>();
    std::vector<Obstacle> near_obstacles, far_obstacles;  // two feeds, each replacing its oldest
    double now_s = 0.0;
    for (int u = 0; u < updates && flying.size() > 1; ++u) {
      // The vehicle flies on along the order; the points it passes are reached.
      double left_m = speed_mps * step_s;
      while (left_m > 0.0 && flying.size() > 1) {
        const Eigen::Vector2d target = pts[static_cast<std::size_t>(flying.front())].head<2>();
        const double d = (target - vehicle).norm();
        if (d > left_m) {
          vehicle += left_m * (target - vehicle) / d;
          left_m = 0.0;
        } else {
          vehicle = target;
          left_m -= d;
          reached.push_back(flying.front());
          flying.erase(flying.begin());
        }
      }
      now_s += step_s;
      // One obstacle of the feed replaced: near the next leg or far from every leg left.
      const bool is_near = u % 2 == 0;
      Obstacle o;
      o.id = static_cast<std::uint64_t>(u);
      o.shape = ObstacleShape::kCylinder;
      const double radius = 150.0 + 250.0 * unit(rng);
      o.size_m = Eigen::Vector3d(radius, radius, 1000.0);
      Eigen::Vector2d at;
      const double heading = 2.0 * M_PI * unit(rng);
      const Eigen::Vector2d track = 1500.0 * Eigen::Vector2d(std::cos(heading), std::sin(heading));
      const double speed_mps_obstacle = 30.0 * unit(rng);
      // Clear of the vehicle by 300 m over the sweep and of every point over its whole track: an
      // obstacle on a point cuts it off (no order at all: the bench measures repairs), one on the
      // vehicle is the flight replanner's business.
      auto clear_of_points = [&](const Eigen::Vector2d& c) {
        const Eigen::Vector2d end = c + (speed_mps_obstacle > 0.0 ? track : Eigen::Vector2d::Zero());
        if (segmentDistance(vehicle, c, c + track.normalized() * speed_mps_obstacle * MissionReorderOptions{}.sweep_s) <
            radius + 300.0) {
          return false;
        }
        for (const Eigen::Vector3d& p : pts)
          if (segmentDistance(p.head<2>(), c, end) < radius + 300.0) return false;
        return true;
      };
      if (is_near) {
        const Eigen::Vector2d next = pts[static_cast<std::size_t>(flying.front())].head<2>();
        bool found = false;
        const Eigen::Vector2d side = Eigen::Vector2d(-(next - vehicle).y(), (next - vehicle).x()).normalized();
        for (int attempt = 0; attempt < 300 && !found; ++attempt) {
          at = vehicle + (0.1 + 0.8 * unit(rng)) * (next - vehicle) + (600.0 * unit(rng) - 300.0) * side;
          found = clear_of_points(at);
        }
        if (!found) {
          ++near.unchecked;
          continue;
        }
      } else {
        bool found = false;
        for (int attempt = 0; attempt < 500 && !found; ++attempt) {
          at = anywhere();
          double closest = (at - vehicle).norm();
          Eigen::Vector2d from = vehicle;
          for (int p : flying) {
            const Eigen::Vector2d to = pts[static_cast<std::size_t>(p)].head<2>();
            closest = std::min(closest, segmentDistance(at, from, to));
            from = to;
          }
          found = closest >= 2500.0 && clear_of_points(at);
        }
        if (!found) {
          ++far.unchecked;
          continue;
        }
      }
      const Eigen::Vector3d start(at.x(), at.y(), terrain.heightAt(at.x(), at.y()));
      o.motion = BackAndForth{start, start + Eigen::Vector3d(track.x(), track.y(), 0.0), speed_mps_obstacle, now_s};
      std::vector<Obstacle>& feed = is_near ? near_obstacles : far_obstacles;
      if (static_cast<int>(feed.size()) >= in_force) feed.erase(feed.begin());
      feed.push_back(o);
      std::vector<Obstacle> obstacles = near_obstacles;
      obstacles.insert(obstacles.end(), far_obstacles.begin(), far_obstacles.end());

      Kind& kind = is_near ? near : far;
      ++kind.updates;
      const auto wall0 = std::chrono::steady_clock::now();
      const double cpu0 = processCpuMs();
      const ReorderCheck check = reorder->check(obstacles, now_s, reached, above(vehicle), flying);
      const double cpu_ms = processCpuMs() - cpu0;
      const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
      if (wall_ms > worst_ms) {
        worst_search_ms = check.search.time_ms;
        worst_tsp_ms = check.tsp_time_ms;
      }
      worst_ms = std::max(worst_ms, wall_ms);
      worst_cpu_ms = std::max(worst_cpu_ms, cpu_ms);
      if (!check.repaired) {
        if (check.failure) ++kind.cut_off;  // a point cut off: the repair waits
        continue;
      }
      ++kind.repaired;
      kind.inc_exp.add(static_cast<double>(check.search.expansions));
      kind.inc_ms.add(cpu_ms);
      kind.inc_wall_ms.add(wall_ms);
      if (check.failure) {
        if (kind.cut_off < 3) std::fprintf(stderr, "%s update %d: %s\n", kind.name, u, check.failure->describe().c_str());
        ++kind.cut_off;
        continue;
      }
      // From scratch on the same grid, from the cell the searches placed the vehicle in.
      const MissionSearch& searches = reorder->planner().search();
      GridLayer grid = reorder->grid();
      std::vector<GridCell> mission_cells;
      std::vector<int> numbering{searches.vehiclePoint()};
      for (int p : searches.remainingMissions()) {
        mission_cells.push_back(order.search->cells[static_cast<std::size_t>(p)]);
        numbering.push_back(p);
      }
      numbering.push_back(searches.endPoint());
      const double s0 = threadCpuMs();
      auto planner = MissionPlanner::create(grid, searches.vehicleCell(), mission_cells, order.search->cells.back());
      if (!planner.ok()) {
        --kind.repaired;  // e.g. the vehicle in a point's cell: no from-scratch twin
        kind.inc_exp.v.pop_back();
        kind.inc_ms.v.pop_back();
        kind.inc_wall_ms.v.pop_back();
        continue;
      }
      OpenTspOptions tsp;
      tsp.max_exact_points = MissionReorder::kExactPoints;
      tsp.compare_heuristic = false;
      planner->setTspOptions(tsp);
      auto plan = planner->preplan();
      const double scratch_ms = threadCpuMs() - s0;
      if (!plan.ok()) {
        ++kind.mismatches;
        continue;
      }
      kind.scratch_exp.add(static_cast<double>(plan->search.expansions));
      kind.scratch_ms.add(scratch_ms);
      std::vector<int> scratch_order;
      for (int p : plan->order) scratch_order.push_back(numbering[static_cast<std::size_t>(p)]);
      const double scratch_cost_m = plan->cost * cell_m;
      const bool same_cost = std::abs(scratch_cost_m - check.new_cost_m) <= 1e-6 * std::max(1.0, scratch_cost_m);
      // A kept order (no saving of a cell) may differ from the scratch order by less than a cell.
      const bool same_order = check.reordered() ? scratch_order == check.new_order
                                                : check.old_cost_m - scratch_cost_m <= MissionReorderOptions{}.min_gain_cells * cell_m + 1e-6;
      if (!same_cost || !same_order) ++kind.mismatches;
      if (check.reordered()) {
        ++kind.reorders;
        flying.assign(check.new_order.begin() + 1, check.new_order.end());
      }
    }
  }
  std::printf("mission_reorder_bench: %d missions of %d points on the embedded terrain's order grid, %d updates each "
              "(%d obstacles in force per feed), seed %u, fresh_plan_fraction %.2f, defer_goal_maps %d, repair threads %d, symmetric pairs %d\n\n",
              missions, points, updates, in_force, seed, order_options.fresh_plan_fraction, order_options.defer_goal_maps ? 1 : 0,
              reorder_options.repair_threads, order_options.symmetric_pairs ? 1 : 0);
  std::printf("preplanning (order stage): %.0f +- %.0f expansions, %.1f +- %.1f ms\n\n", pre_exp.mean(), pre_exp.stddev(),
              pre_ms.mean(), pre_ms.stddev());
  std::printf("| update | updates (not placed) | repaired | incremental expansions | incremental ms (cpu, all threads) | p95 / max ms | wall ms p95 / max | from-scratch expansions "
              "| from-scratch ms (cpu) | expansions saved | reorders | no order | mismatches |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Kind* k : {&near, &far}) {
    const double saved = k->scratch_exp.mean() > 0 ? 1.0 - k->inc_exp.mean() / k->scratch_exp.mean() : 0.0;
    std::printf("| %s | %d (%d) | %d | %.0f +- %.0f (max %.0f) | %.2f +- %.2f | %.1f / %.1f | %.1f / %.1f | %.0f +- %.0f | %.1f +- %.1f | %.1f %% | %d | %d | %d |\n",
                k->name, k->updates, k->unchecked, k->repaired, k->inc_exp.mean(), k->inc_exp.stddev(), k->inc_exp.max(), k->inc_ms.mean(),
                k->inc_ms.stddev(), k->inc_ms.p95(), k->inc_ms.max(), k->inc_wall_ms.p95(), k->inc_wall_ms.max(), k->scratch_exp.mean(), k->scratch_exp.stddev(), k->scratch_ms.mean(),
                k->scratch_ms.stddev(), 100.0 * saved, k->reorders, k->cut_off, k->mismatches);
  }
  std::printf("\nlargest update (cover + repair + TSP): %.2f ms wall (target: 50 ms) %s (repair %.2f, TSP %.2f); "
              "largest processor time %.2f ms\n",
              worst_ms, worst_ms <= 50.0 ? "MET" : "MISSED", worst_search_ms, worst_tsp_ms, worst_cpu_ms);
  return near.mismatches + far.mismatches == 0 ? 0 : 3;
}
