#include "terrain/terrain_world.hpp"

#include <chrono>

namespace skyroute {
namespace {
double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

Result<TerrainWorld> loadTerrainWorld(const std::string& dem_path, const CollisionWorldOptions& options,
                                      const DemLoadOptions& dem_options, const TerrainLoadObserver& observer) {
  TerrainWorld world;
  auto t0 = std::chrono::steady_clock::now();
  auto dem = Dem::load(dem_path, dem_options);
  if (!dem.ok()) return dem.error();
  world.dem = dem.value();
  world.load_seconds = secondsSince(t0);

  if (observer) {
    if (Status go_on = observer("heightfield", world); !go_on.ok()) return go_on.error();
  }
  t0 = std::chrono::steady_clock::now();
  auto heightfield = Heightfield::build(world.dem);
  if (!heightfield.ok()) return heightfield.error();
  world.heightfield = heightfield.value();
  world.heightfield_seconds = secondsSince(t0);

  if (observer) {
    if (Status go_on = observer("collision", world); !go_on.ok()) return go_on.error();
  }
  t0 = std::chrono::steady_clock::now();
  auto collision = CollisionWorld::create(world.heightfield, options);
  if (!collision.ok()) return collision.error();
  world.collision = collision.value();
  world.collision_seconds = secondsSince(t0);
  return world;
}

}  // namespace skyroute
