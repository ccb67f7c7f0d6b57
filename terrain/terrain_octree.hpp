// TerrainOctree: the terrain as an OctoMap OcTree of solid columns (every voxel whose centre is
// under the ground is occupied; no hollow shell), built top-down straight into a shared_ptr:
// boxes entirely under the terrain become one coarse occupied leaf, boxes entirely above it are
// never created, and only boxes the surface passes through are split to the finest resolution.
// Obstacles can be rasterised into it and removed again (restoring the terrain's voxels).
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <octomap/OcTree.h>

#include "terrain/heightfield.hpp"
#include "terrain/obstacle.hpp"

namespace skyroute {

struct TerrainOctreeOptions {
  double resolution_m = 30.0;
  double inflation_m = 0.0;  // terrain raised by this clearance margin
};

struct TerrainOctreeStats {
  double build_seconds = 0.0;
  std::size_t leaf_count = 0;
  std::size_t node_count = 0;
  std::size_t memory_bytes = 0;
};

// The peak memory building the octree of `terrain` at resolution_m takes, in bytes, before any of
// it is allocated: a guard refuses a resolution the machine cannot hold instead of swapping for a
// minute. An upper estimate, proportional to the number of resolution_m columns over the terrain.
std::size_t estimateOctreePeakBytes(const Heightfield& terrain, double resolution_m);

class TerrainOctree {
 public:
  static std::unique_ptr<TerrainOctree> build(std::shared_ptr<const Heightfield> terrain,
                                              const TerrainOctreeOptions& options);

  std::shared_ptr<const octomap::OcTree> tree() const { return tree_; }
  const TerrainOctreeStats& stats() const { return stats_; }
  double resolution() const { return options_.resolution_m; }

  // Whether the voxel containing p is occupied (terrain or obstacle).
  bool occupied(const Eigen::Vector3d& p_m) const;
  // Whether the terrain alone fills the voxel whose centre is c (the build rule).
  bool terrainOccupiesVoxel(const Eigen::Vector3d& center_m) const;

  // Rasterise an obstacle at time t_s (voxels whose centre lies inside it). Re-adding an id
  // replaces it. Not safe concurrently with readers: the CollisionWorld serialises writers.
  void addObstacle(const Obstacle& obstacle, double t_s = 0.0);
  bool removeObstacle(std::uint64_t id);

 private:
  TerrainOctree() = default;
  std::shared_ptr<octomap::OcTree> tree_;
  std::shared_ptr<const Heightfield> terrain_;
  TerrainOctreeOptions options_;
  TerrainOctreeStats stats_;
  std::unordered_map<std::uint64_t, std::vector<octomap::OcTreeKey>> obstacle_voxels_;
};

}  // namespace skyroute
