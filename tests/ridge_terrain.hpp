// Synthetic terrains for the flyable-region and leg-region tests: a flat plain cut north to south
// by a ridge several cells wide, with a pass (a lower stretch) at chosen rows, on a UTM grid of
// 30 m cells, built into a heightfield and a collision world under a ceiling.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "terrain/collision_world.hpp"
#include "terrain/dem.hpp"
#include "terrain/heightfield.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute::testing {

struct RidgeSpec {
  int size = 60;              // cells each way
  double plain_m = 100.0;
  int ridge_first_col = 28;   // the ridge spans these columns, every row
  int ridge_last_col = 32;
  double ridge_m = 1000.0;
  int pass_first_row = -1;    // rows where the ridge is only pass_m high (none when first > last)
  int pass_last_row = -2;
  double pass_m = 200.0;
  bool void_ridge = false;    // the ridge is unknown terrain (NaN) instead of high ground
};

inline std::vector<float> ridgeHeights(const RidgeSpec& s) {
  std::vector<float> h(static_cast<std::size_t>(s.size) * s.size, static_cast<float>(s.plain_m));
  for (int row = 0; row < s.size; ++row) {
    const bool pass = row >= s.pass_first_row && row <= s.pass_last_row;
    for (int col = s.ridge_first_col; col <= s.ridge_last_col; ++col) {
      float& cell = h[static_cast<std::size_t>(row) * s.size + col];
      if (s.void_ridge) {
        cell = pass ? static_cast<float>(s.plain_m) : std::numeric_limits<float>::quiet_NaN();
      } else {
        cell = static_cast<float>(pass ? s.pass_m : s.ridge_m);
      }
    }
  }
  return h;
}

struct SyntheticWorld {
  std::shared_ptr<const Heightfield> terrain;
  std::shared_ptr<CollisionWorld> world;
};

inline SyntheticWorld syntheticWorld(int size, std::vector<float> heights, double ceiling_m, double clearance_m = 30.0) {
  SyntheticWorld out;
  auto dem = Dem::fromArray(size, size, std::move(heights), {500000.0, 30.0, 0.0, 5200000.0, 0.0, -30.0},
                            epsgWkt(32633), "synthetic");
  EXPECT_TRUE(dem.ok()) << dem.error().describe();
  if (!dem.ok()) return out;
  auto hf = Heightfield::build(*dem);
  EXPECT_TRUE(hf.ok()) << hf.error().describe();
  if (!hf.ok()) return out;
  CollisionWorldOptions options;
  options.vehicle_radius_m = 5.0;
  options.min_clearance_m = clearance_m;
  options.ceiling_m = ceiling_m;
  options.build_octree = false;
  auto world = CollisionWorld::create(*hf, options);
  EXPECT_TRUE(world.ok()) << world.error().describe();
  if (!world.ok()) return out;
  out.terrain = *hf;
  out.world = *world;
  return out;
}

inline SyntheticWorld ridgeWorld(const RidgeSpec& s, double ceiling_m) {
  return syntheticWorld(s.size, ridgeHeights(s), ceiling_m);
}

}  // namespace skyroute::testing
