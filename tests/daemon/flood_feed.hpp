// An obstacle feed for floods and soaks: `count` vertical cylinders (radius 150 m, 500 m tall)
// spread over the terrain's middle with a seeded generator, each sweeping 2 km north and south at
// 30 m/s at the lanes' height, so some cross the lanes of bench/latency_scenario.hpp's vehicles
// and force replans. Replayed in a loop, the same ids come back: the obstacles in force stay
// `count`, however long the flood.
#pragma once

#include <fstream>
#include <random>
#include <string>

#include "service/obstacle_feed.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute::testing {

inline void writeFloodFeed(const std::string& path, const Heightfield& terrain, int count, unsigned seed) {
  std::mt19937 random(seed);
  const Eigen::AlignedBox2d box = terrain.boundsEn();
  std::uniform_real_distribution<double> east(box.min().x() + 0.1 * box.sizes().x(), box.max().x() - 0.1 * box.sizes().x());
  std::uniform_real_distribution<double> north(box.min().y() + 0.15 * box.sizes().y(),
                                               box.max().y() - 0.15 * box.sizes().y());
  std::ofstream out(path);
  out << obstacleFeedHeaderLine() << "\n";
  for (int i = 0; i < count; ++i) {
    const double e = east(random), n = north(random);
    const Eigen::Vector3d from(e, n - 1000.0, terrain.heightAt(e, n) + 300.0);
    FeedEntry entry;
    entry.t_s = 0.001 * i;
    entry.update.obstacle.id = static_cast<std::uint64_t>(i + 1);
    entry.update.obstacle.shape = ObstacleShape::kCylinder;
    entry.update.obstacle.size_m = Eigen::Vector3d(150.0, 0.0, 250.0);
    entry.update.obstacle.center_m = from;
    entry.update.obstacle.motion = BackAndForth{from, from + Eigen::Vector3d(0.0, 2000.0, 0.0), 30.0, 0.0};
    entry.valid_for_s = 600.0;
    out << obstacleFeedEntryLine(entry) << "\n";
  }
}

}  // namespace skyroute::testing
