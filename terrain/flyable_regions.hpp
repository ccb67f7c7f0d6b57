// FlyableRegions: which parts of the terrain a vehicle can reach from one another while staying
// at least the clearance above the ground and under the ceiling, so that "no path" can be proven
// instead of guessed after a search, and so a planner can see in advance that a leg must leave
// its usual sampling corridor (a pass round a ridge).
//
// The world's terrain is the bilinear surface on the DEM grid, so a flyable point (ground <=
// threshold = ceiling - clearance) lies in a grid square whose lowest corner is at most the
// threshold, and a continuous path only moves between squares that share an edge or a corner.
// The squares are min-pooled into blocks of pool x pool (a block is as low as its lowest flyable
// square; a square with an unknown corner never is), so the 8-connected regions of the blocks at
// or below the threshold contain every flyable path: start and goal in different regions is a
// proof that no path exists. The converse does not hold (a gap between two blocks may be too
// narrow, obstacles are not counted): being connected only says a path may exist.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "terrain/heightfield.hpp"

namespace skyroute {

class FlyableRegions {
 public:
  // terrain: the surface the world checks against (the dilated one with a terrain margin);
  // threshold_m: the highest ground a vehicle may fly over (ceiling - clearance). The blocks are
  // the smallest pool (>= 1) that keeps them at most max_blocks.
  static FlyableRegions build(const Heightfield& terrain, double threshold_m, std::size_t max_blocks = 1u << 20);

  double thresholdM() const { return threshold_m_; }
  int pool() const { return pool_; }
  int blocksWide() const { return width_; }
  int blocksHigh() const { return height_; }
  int regionCount() const { return regions_; }

  // The block of an ENU point: nothing outside the DEM's grid.
  std::optional<Eigen::Vector2i> blockAt(const Eigen::Vector2d& en_m) const;
  // Lowest ground of a block's flyable squares (+inf when every square touches unknown terrain).
  float blockFloorM(const Eigen::Vector2i& block) const { return floor_[index(block)]; }
  // 0: the block is not flyable; otherwise its region's number (1..regionCount()).
  std::int32_t regionOf(const Eigen::Vector2i& block) const { return label_[index(block)]; }

  // False is a proof that no flyable path joins a and b (outside the grid counts as not flyable).
  bool connected(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const;
  // False is a proof that no flyable path joins a and b without leaving box_en_m.
  bool connectedWithin(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m,
                       const Eigen::AlignedBox2d& box_en_m) const;
  // The lowest threshold at which a and b's blocks are connected (the bottleneck of the best way
  // between them over the blocks' floors): a lower bound on the ground any flyable path between
  // them must pass over. Nothing when unknown terrain separates them at every height.
  std::optional<double> lowestConnectingGroundM(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const;
  // The shortest 8-connected way through flyable blocks from a's block to b's (A*, lengths in
  // metres at the DEM's cell size, a block flyable only in part counted four times as long), as
  // the ENU box round it and the two points: where a search that must find the way round a
  // ridge should look. Nothing when they are not connected.
  std::optional<Eigen::AlignedBox2d> shortestWayBox(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const;
  // The same way as points: each block's centre (east, north) and its floor (up), from a's block
  // to b's (a block flyable only in part: its lowest grid point instead of its centre). Empty when
  // they are not connected.
  std::vector<Eigen::Vector3d> shortestWay(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const;
  // A way from a corner of a's grid square to a corner of b's along the DEM's grid, every grid
  // point on it at most max_ground_m, and a diagonal only across a square whose four corners are:
  // the ground under it is then at most max_ground_m everywhere (the surface is bilinear), so
  // flown that high plus the clearance it keeps the clearance. The shortest such way (A* over the
  // DEM's grid points, a few arrays as large as the DEM for its time), collinear steps merged; ENU
  // points. Empty when there is none (the blocks may connect where no such way does).
  std::vector<Eigen::Vector2d> gridWay(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m,
                                       double max_ground_m) const;

 private:
  FlyableRegions() = default;
  std::size_t index(const Eigen::Vector2i& b) const {
    return static_cast<std::size_t>(b.y()) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(b.x());
  }
  bool flyable(std::size_t i) const { return label_[i] != 0; }
  // A* over the flyable blocks: the blocks of the way from a's to b's, b's first; empty if none.
  std::vector<std::size_t> wayBlocks(const Eigen::Vector2d& a_en_m, const Eigen::Vector2d& b_en_m) const;
  // The DEM cell (column, row) of a block's lowest known grid point.
  Eigen::Vector2i lowestCell(std::size_t block) const;

  const Heightfield* terrain_ = nullptr;  // for pixel <-> ENU; the owner keeps it alive
  double threshold_m_ = 0.0;
  int pool_ = 1;
  int squares_wide_ = 0;  // grid squares (between cell centres) of the DEM
  int squares_high_ = 0;
  int width_ = 0;  // blocks
  int height_ = 0;
  double block_east_m_ = 1.0;  // a block's mean ground size (for path lengths)
  double block_north_m_ = 1.0;
  std::vector<float> floor_;
  std::vector<float> top_;  // highest ground of the block (+inf with an unknown square)
  std::vector<std::int32_t> label_;
  int regions_ = 0;
};

}  // namespace skyroute
