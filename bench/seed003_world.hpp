// The world the seed-003 benchmarks fly in: the N44W072 tile of ../shared/data with the scenario's
// world options (service/moving_obstacle_scenario.hpp, which also places the seed's square and
// obstacles on it). Header only: SKYROUTE_SHARED_DATA_DIR is defined per benchmark.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"

namespace skyroute::bench {

// The loaded world, or nothing after printing why on stderr.
inline std::optional<TerrainWorld> loadSeed003World() {
  const std::string dem = std::string(SKYROUTE_SHARED_DATA_DIR) + "/dem/N44W072.hgt";
  auto world = loadTerrainWorld(dem, seed003ScenarioWorldOptions());
  if (!world.ok()) {
    std::fprintf(stderr, "%s: %s\n", dem.c_str(), world.error().describe().c_str());
    return std::nullopt;
  }
  return std::move(world.value());
}

// The world with the scenario's obstacles in it, and the scenario (its start, goal and obstacles).
struct Seed003Flight {
  TerrainWorld world;
  MovingObstacleScenario scenario;
};
inline std::optional<Seed003Flight> loadSeed003Flight() {
  auto world = loadSeed003World();
  if (!world) return std::nullopt;
  MovingObstacleScenario scenario = seed003Table1Scenario(*world->heightfield);
  for (const Obstacle& o : scenario.obstacles) world->collision->upsertObstacle(o);
  return Seed003Flight{std::move(*world), std::move(scenario)};
}

}  // namespace skyroute::bench
