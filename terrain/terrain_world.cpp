#include "terrain/terrain_world.hpp"

#include <chrono>

namespace skyroute {
namespace {

// Runs one loading stage: the observer hears its name first (and may stop the load), then the
// stage's result goes into member and its duration into seconds.
template <class T, class Build>
Status runStage(const char* name, const TerrainLoadObserver& observer, TerrainWorld& world, T& member, double& seconds,
                Build build) {
  if (observer) {
    if (Status go_on = observer(name, world); !go_on.ok()) return go_on;
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto built = build();
  if (!built.ok()) return built.error();
  member = built.value();
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return Status::success();
}

}  // namespace

Result<TerrainWorld> loadTerrainWorld(const std::string& dem_path, const CollisionWorldOptions& options,
                                      const DemLoadOptions& dem_options, const TerrainLoadObserver& observer) {
  TerrainWorld world;
  auto t0 = std::chrono::steady_clock::now();
  auto dem = Dem::load(dem_path, dem_options);
  if (!dem.ok()) return dem.error();
  world.dem = dem.value();
  world.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (Status s = runStage("heightfield", observer, world, world.heightfield, world.heightfield_seconds,
                          [&] { return Heightfield::build(world.dem); });
      !s.ok())
    return s.error();
  if (Status s = runStage("collision", observer, world, world.collision, world.collision_seconds,
                          [&] { return CollisionWorld::create(world.heightfield, options); });
      !s.ok())
    return s.error();
  return world;
}

}  // namespace skyroute
