// Where a leg's RRT* samples, in growing steps, and when it need not search at all. A fixed
// corridor round the leg misses a pass that lies beyond it (the leg would come back "no path"
// while a detour exists); sampling the whole terrain for every leg dilutes the samples of the
// common short one. So a leg is tried first in its corridor (exactly as before when the terrain
// lets a path stay inside it), then in the box round the shortest way through the flyable
// regions (FlyableRegions) grown by the same margin, and last over the whole terrain. When the
// flyable regions prove that no path joins the leg's ends, there is no step at all.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "terrain/collision_world.hpp"

namespace skyroute {

class LegSamplingRegions {
 public:
  // a_m, b_m: the leg's ends (valid points of the world); margin_m: the corridor's margin.
  LegSamplingRegions(const CollisionWorld& world, const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                     double margin_m);

  // False: proven that no flyable path joins the ends below the ceiling (no step to try).
  bool connected() const { return connected_; }
  // When not connected: the lowest ceiling under which the terrain could let them join (the
  // bottleneck ground plus the clearance; a lower bound, the blocks being coarser than the DEM).
  // Nothing when unknown terrain or the map's edge separates them at every height.
  std::optional<double> lowestConnectingCeilingM() const;

  // The next sampling region to try (a box spanning every height, bigger than every one before),
  // nothing after the whole terrain. The first step is the corridor whenever a path may lie in it.
  std::optional<Eigen::AlignedBox3d> next();
  // From the second step on: the shortest way through the flyable regions, its points at the
  // lowest flyable height of their block (empty for the corridor), and how far apart they lie, for
  // RRT*'s guided samples (RrtStarOptions::guide_m).
  const std::vector<Eigen::Vector3d>& guide() const { return guide_; }
  double guideSpacingM() const { return guide_spacing_m_; }
  // A way flown just under the ceiling: a, straight up, the flyable regions' grid way
  // (FlyableRegions::gridWay: ground at most ceiling - clearance under every piece), above b,
  // straight down to b. Clear of the terrain by construction but for the pieces at the ends, which
  // cross a and b's grid squares; the caller checks every piece (ends, obstacles, zones). A path
  // that needs no search, for when a random one is slow to come on a winding way round a range.
  // Empty without a guide or a grid way (costs one more A* over the blocks and one over the cells
  // near the way).
  std::vector<Eigen::Vector3d> wayUnderCeiling() const;
  // Regions handed out so far, and whether the last was the whole terrain.
  int tried() const { return tried_; }
  bool wholeTerrainTried() const { return whole_tried_; }

 private:
  const CollisionWorld& world_;
  Eigen::Vector3d a_m_, b_m_;
  double margin_m_;
  bool connected_ = false;
  int step_ = 0;  // 0 corridor, 1 shortest way, 2 whole terrain, 3 done
  int tried_ = 0;
  bool whole_tried_ = false;
  std::vector<Eigen::AlignedBox2d> given_;  // clipped to the terrain
  std::vector<Eigen::Vector3d> guide_;
  double guide_spacing_m_ = 0.0;
};

}  // namespace skyroute
