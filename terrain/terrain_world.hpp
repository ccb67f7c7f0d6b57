// TerrainWorld: DEM -> Heightfield -> CollisionWorld in one call, with the time each step took,
// for the CLI tools, the engine and the benchmarks.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "terrain/collision_world.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

struct TerrainWorld {
  std::shared_ptr<const Dem> dem;
  std::shared_ptr<const Heightfield> heightfield;
  std::shared_ptr<CollisionWorld> collision;
  double load_seconds = 0.0;         // reading and cleaning the raster
  double heightfield_seconds = 0.0;  // frame and lattice
  double collision_seconds = 0.0;    // octree and FCL objects
};

// What a caller sees between the steps: `step` names the step about to start ("heightfield",
// "collision"); returning an error stops the load there with that error (a memory guard refuses
// an octree the machine cannot hold before it is built).
using TerrainLoadObserver = std::function<Status(const std::string& step, const TerrainWorld& so_far)>;

Result<TerrainWorld> loadTerrainWorld(const std::string& dem_path, const CollisionWorldOptions& options,
                                      const DemLoadOptions& dem_options = {},
                                      const TerrainLoadObserver& observer = {});

}  // namespace skyroute
