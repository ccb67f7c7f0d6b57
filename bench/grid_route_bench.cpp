// HAB-PP routes through the trajectory stage on the embedded terrain: seeded random missions
// (begin, one point, end, each 60 m above the ground, anywhere within 5.5 km of the centre) whose
// straight legs are not all clear are planned as the mission pipeline plans them: the registry's
// hab-pp leg planner (legPathPlanner) with the pipeline's default options and budget, the output
// stage's windowed re-planning off (0) and on (3 segments), and each route is built into a
// trajectory for a vehicle with a 30 m turn radius by the pipeline's trajectory stage
// (buildRouteTrajectory with the pipeline's trajectory options). Prints how many routes
// and trajectories come out, the mean 3D route length over the missions both settings fly, and
// the trajectory stage's failure reasons. docs/benchmarks/habpp.md records the output.
//
//   grid_route_bench [--missions N] [--turn-radius M]
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
  double length_m = 0.0;
  std::string failure;  // the trajectory stage's reason, cut to its kind
};

Outcome fly(const std::shared_ptr<const CollisionWorld>& world, const std::vector<Eigen::Vector3d>& points,
            int window_segments, double turn_radius_m, std::uint64_t seed) {
  Outcome out;
  PipelineOptions pipeline;
  pipeline.grid_legs.output_window_segments = window_segments;
  const RouteOptions route_options = pipelineReplanOptions(pipeline, pipeline.budget, seed).route;
  const LegPathPlanner legs = legPathPlanner(RoutePlannerKind::kHabPp, pipeline.grid_legs);
  auto route = legs(world, points, route_options, TerminationCondition());
  if (!route.ok()) return out;
  out.path = true;
  for (const RouteLeg& leg : route->legs) {
    for (std::size_t k = 1; k < leg.path_m.size(); ++k) out.length_m += (leg.path_m[k] - leg.path_m[k - 1]).norm();
  }
  VehicleLimits limits;
  limits.min_turn_radius_m = turn_radius_m;
  const Status built = buildRouteTrajectory(world, points, limits, route_options, *route);
  out.trajectory = built.ok();
  if (!built.ok()) {
    const std::string why = built.error().describe();
    // The kind of failure, from the trajectory stage's message.
    for (const char* kind : {"(fixed)", "cannot be rounded", "still turns too tightly", "stretching", "descent_rate",
                             "climb_rate"}) {
      if (why.find(kind) != std::string::npos) {
        out.failure = kind;
        break;
      }
    }
    if (out.failure == "(fixed)") out.failure = "a corner at a mission point (pass-through) cannot be rounded";
    if (out.failure.empty()) out.failure = why.substr(0, 100);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int missions = 120;
  double turn_radius_m = 30.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--missions" && i + 1 < argc) missions = std::atoi(argv[++i]);
    else if (a == "--turn-radius" && i + 1 < argc) turn_radius_m = std::atof(argv[++i]);
    else {
      std::fprintf(stderr, "usage: grid_route_bench [--missions N] [--turn-radius M]\n");
      return 2;
    }
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
  const int windows[2] = {0, 3};
  int tried = 0, paths[2] = {0, 0}, trajectories[2] = {0, 0}, both = 0;
  double length_m[2] = {0.0, 0.0};
  std::map<std::string, int> failures[2];
  skyroute::bench::BenchProgress progress("grid_route_bench", static_cast<std::size_t>(missions));
  for (int k = 0; k < missions; ++k) {
    if (k > 0) progress.done("mission " + std::to_string(k - 1));
    std::vector<Eigen::Vector3d> points;
    for (int j = 0; j < 3; ++j) {
      const double e = coordinate_m(rng), n = coordinate_m(rng);
      points.emplace_back(e, n, terrain.heightAt(e, n) + 60.0);
    }
    if (world->isSegmentValid(points[0], points[1]) && world->isSegmentValid(points[1], points[2])) continue;
    ++tried;
    Outcome o[2];
    for (int w = 0; w < 2; ++w) {
      o[w] = fly(world, points, windows[w], turn_radius_m, 1 + static_cast<std::uint64_t>(k));
      paths[w] += o[w].path ? 1 : 0;
      trajectories[w] += o[w].trajectory ? 1 : 0;
      if (o[w].path && !o[w].trajectory) ++failures[w][o[w].failure];
    }
    if (o[0].trajectory && o[1].trajectory) {
      ++both;
      for (int w = 0; w < 2; ++w) length_m[w] += o[w].length_m;
    }
  }
  std::printf("%d random missions, %d with a blocked straight leg; vehicle turn radius %.0f m\n\n", missions, tried,
              turn_radius_m);
  std::printf("| output windows | routes | trajectories | mean route length over the %d both fly, m |\n|---|---|---|---|\n",
              both);
  for (int w = 0; w < 2; ++w) {
    std::printf("| %d segments | %d/%d | %d/%d | %.1f |\n", windows[w], paths[w], tried, trajectories[w], paths[w],
                both > 0 ? length_m[w] / both : 0.0);
  }
  for (int w = 0; w < 2; ++w) {
    std::printf("\ntrajectory failures with %d-segment windows:\n", windows[w]);
    for (const auto& [why, count] : failures[w]) std::printf("  %2d x %s\n", count, why.c_str());
  }
  return 0;
}
