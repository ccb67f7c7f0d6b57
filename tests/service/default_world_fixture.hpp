// A fixture on the embedded default terrain: the heightfield loads once per suite, each test gets
// a fresh world model, and mission points are placed at a height above the ground.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include <Eigen/Core>

#include "service/mission_types.hpp"
#include "service/world_model.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute::testing {

class DefaultWorldTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    heightfield_ = defaultTerrainHeightfield();
    ASSERT_TRUE(heightfield_) << "data/default_terrain.tif did not load";
  }

  void SetUp() override {
    auto model = WorldModel::create(heightfield_, WorldModelOptions{}, "default_terrain");
    ASSERT_TRUE(model.ok());
    world_ = *model;
  }

  // A point above the ground by agl_m at east/north metres from the terrain centre.
  MissionPointData enu(double e, double n, double agl_m) const {
    return MissionPointData::enu(Eigen::Vector3d(e, n, heightfield_->heightAt(e, n) + agl_m));
  }
  // The same point given in WGS84.
  MissionPointData geo(double e, double n, double agl_m) const {
    const GeoPoint g = heightfield_->frame().toGeo(enu(e, n, agl_m).enu_m);
    return MissionPointData::wgs84(g.lat_deg, g.lon_deg, g.alt_amsl_m);
  }

  static inline std::shared_ptr<const Heightfield> heightfield_;
  std::shared_ptr<WorldModel> world_;
};

}  // namespace skyroute::testing
