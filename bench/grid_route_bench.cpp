// Every registered route planner through the trajectory stage on the embedded terrain: seeded
// random missions (begin, one point, end, each 60 m above the ground, anywhere within 5.5 km of
// the centre; the same missions for every planner) planned as the mission pipeline plans them:
// the registry's leg planner (legPathPlanner) with the pipeline's default options and budget, and
// each route built into a trajectory for a vehicle with a 30 m turn radius by the pipeline's
// trajectory stage (buildRouteTrajectory with the pipeline's trajectory options, in the given
// mission point mode). One row per planner: how many missions have a route, how many fly, how
// many of those stop at a mission point (pass mode: where passing could not be made to fly) and
// at corners inside the legs (the trajectory stage's last resort), the mean 3D route length of
// those flown; then each failure with its typed status (field and message). --only K flies
// mission K alone.
// docs/benchmarks.md records the output.
//
//   grid_route_bench [--missions N] [--turn-radius M] [--mode pass|stop] [--planner NAME] [--only K]
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench/support/bench_progress.hpp"
#include "service/mission_pipeline.hpp"
#include "service/planner_registry.hpp"
#include "service/route_planner.hpp"
#include "service/world_model.hpp"
#include "terrain/terrain_world.hpp"

namespace {

using namespace skyroute;

struct Outcome {
  bool path = false;
  bool trajectory = false;
  std::size_t stops = 0;
  std::size_t corner_stops = 0;  // the last resort: rests at corners inside the legs
  double length_m = 0.0;
  std::string failure;  // the typed status: "field: message"
};

Outcome fly(const std::shared_ptr<const CollisionWorld>& world, const std::vector<Eigen::Vector3d>& points,
            RoutePlannerKind planner, FixedWaypointMode mode, double turn_radius_m, std::uint64_t seed) {
  Outcome out;
  PipelineOptions pipeline;
  RouteOptions route_options = pipelineReplanOptions(pipeline, pipeline.budget, seed).route;
  route_options.trajectory.fixed_waypoint_mode = mode;
  const LegPathPlanner legs = legPathPlanner(planner, pipeline.grid_legs);
  auto route = legs(world, points, route_options, TerminationCondition());
  if (!route.ok()) {
    out.failure = "legs: " + route.error().describe();
    return out;
  }
  out.path = true;
  for (const RouteLeg& leg : route->legs) {
    for (std::size_t k = 1; k < leg.path_m.size(); ++k) out.length_m += (leg.path_m[k] - leg.path_m[k - 1]).norm();
  }
  VehicleLimits limits;
  limits.min_turn_radius_m = turn_radius_m;
  const Status built = buildRouteTrajectory(world, points, limits, route_options, *route);
  out.trajectory = built.ok();
  if (built.ok()) {
    // Stops the mode asks for are not fallbacks.
    if (mode == FixedWaypointMode::kPass) out.stops = route->point_stops.size();
    for (std::size_t n : route->leg_corner_stops) out.corner_stops += n;
  } else {
    out.failure = built.error().describe();
  }
  return out;
}

struct Row {
  int paths = 0, flown = 0, stopped = 0, corner_stopped = 0;
  double length_m = 0.0;
  std::vector<std::string> failures;
};

}  // namespace

int main(int argc, char** argv) {
  int missions = 120;
  double turn_radius_m = 30.0;
  FixedWaypointMode mode = FixedWaypointMode::kPass;
  std::vector<const RoutePlannerInfo*> planners;
  int only = -1;  // one mission alone
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--missions" && i + 1 < argc) {
      missions = std::atoi(argv[++i]);
    } else if (a == "--turn-radius" && i + 1 < argc) {
      turn_radius_m = std::atof(argv[++i]);
    } else if (a == "--mode" && i + 1 < argc && parseFixedWaypointMode(argv[i + 1])) {
      mode = *parseFixedWaypointMode(argv[++i]);
    } else if (a == "--only" && i + 1 < argc) {
      only = std::atoi(argv[++i]);
    } else if (a == "--planner" && i + 1 < argc) {
      const RoutePlannerInfo* found = nullptr;
      if (auto unknown = findRoutePlanner(argv[++i], &found)) {
        std::fprintf(stderr, "%s\n", unknown->describe().c_str());
        return 2;
      }
      planners.push_back(found);
    } else {
      std::fprintf(stderr, "usage: grid_route_bench [--missions N] [--turn-radius M] [--mode pass|stop] [--planner NAME] [--only K]\n");
      return 2;
    }
  }
  if (planners.empty()) {
    for (const RoutePlannerInfo& p : routePlanners()) planners.push_back(&p);
  }
  // As the engine sees it: the world model's collision world for a 30 m clearance.
  CollisionWorldOptions options;
  options.build_octree = false;
  auto loaded = loadTerrainWorld(std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif", options);
  if (!loaded.ok()) {
    std::fprintf(stderr, "%s\n", loaded.error().describe().c_str());
    return 1;
  }
  auto model = WorldModel::create(loaded->heightfield, WorldModelOptions{}, "default_terrain");
  if (!model.ok()) return 1;
  auto clearance_world = (*model)->worldFor(30.0, 5000.0);
  if (!clearance_world.ok()) return 1;
  const std::shared_ptr<const CollisionWorld> world = *clearance_world;
  const Heightfield& terrain = *loaded->heightfield;
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> coordinate_m(-5500.0, 5500.0);
  std::vector<std::vector<Eigen::Vector3d>> mission_points;
  int blocked = 0;
  for (int k = 0; k < missions; ++k) {
    std::vector<Eigen::Vector3d> points;
    for (int j = 0; j < 3; ++j) {
      const double e = coordinate_m(rng), n = coordinate_m(rng);
      points.emplace_back(e, n, terrain.heightAt(e, n) + 60.0);
    }
    if (!world->isSegmentValid(points[0], points[1]) || !world->isSegmentValid(points[1], points[2])) ++blocked;
    mission_points.push_back(std::move(points));
  }
  std::vector<Row> rows(planners.size());
  skyroute::bench::BenchProgress progress("grid_route_bench", mission_points.size() * planners.size());
  for (std::size_t p = 0; p < planners.size(); ++p) {
    for (int k = 0; k < missions; ++k) {
      if (only >= 0 && k != only) continue;
      if (only >= 0 && p == 0) {
        for (const Eigen::Vector3d& q : mission_points[static_cast<std::size_t>(k)])
          std::printf("mission %d point ENU %.1f %.1f %.1f\n", k, q.x(), q.y(), q.z());
      }
      const Outcome o = fly(world, mission_points[static_cast<std::size_t>(k)], planners[p]->kind, mode, turn_radius_m,
                            1 + static_cast<std::uint64_t>(k));
      progress.done(std::string(planners[p]->name) + " mission " + std::to_string(k));
      Row& row = rows[p];
      row.paths += o.path ? 1 : 0;
      row.flown += o.trajectory ? 1 : 0;
      row.stopped += o.stops > 0 ? 1 : 0;
      row.corner_stopped += o.corner_stops > 0 ? 1 : 0;
      row.length_m += o.trajectory ? o.length_m : 0.0;
      if (!o.trajectory) row.failures.push_back("mission " + std::to_string(k) + ": " + o.failure);
    }
  }
  std::printf("%d random missions (%d with a blocked straight leg); vehicle turn radius %.0f m; mission_point_mode %s\n\n",
              missions, blocked, turn_radius_m, std::string(to_string(mode)).c_str());
  std::printf("| planner | routes | trajectories | stop at a point | stop at leg corners | mean route length of those flown, m |\n"
              "|---|---|---|---|---|---|\n");
  for (std::size_t p = 0; p < planners.size(); ++p) {
    const Row& r = rows[p];
    std::printf("| %s | %d/%d | %d/%d | %d | %d | %.1f |\n", std::string(planners[p]->name).c_str(), r.paths, missions,
                r.flown, missions, r.stopped, r.corner_stopped, r.flown > 0 ? r.length_m / r.flown : 0.0);
  }
  for (std::size_t p = 0; p < planners.size(); ++p) {
    if (rows[p].failures.empty()) continue;
    std::printf("\nfailures of %s:\n", std::string(planners[p]->name).c_str());
    for (const std::string& why : rows[p].failures) std::printf("  %s\n", why.substr(0, 400).c_str());
  }
  return 0;
}
