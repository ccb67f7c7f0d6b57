#include "terrain/terrain_octree.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <unordered_set>

namespace skyroute {
namespace {

constexpr int kTreeDepth = 16;
constexpr int kTreeMaxVal = 32768;  // OctoMap's key of coordinate 0
constexpr int kNoTerrain = INT_MIN;

// OcTree whose root a builder may create, so the tree can be grown top-down at coarse depths
// (OctoMap's public API only inserts at the finest depth, which would mean hundreds of millions
// of insertions for solid columns at 30 m).
class SolidOcTree final : public octomap::OcTree {
 public:
  explicit SolidOcTree(double resolution) : octomap::OcTree(resolution) {}
  octomap::OcTreeNode* makeRoot() {
    if (root == nullptr) {
      root = new octomap::OcTreeNode();
      ++tree_size;
      size_changed = true;
    }
    return root;
  }
};

// Min and max of the highest solid voxel key per column, over aligned power-of-two blocks of
// columns: level L, block X covers column keys [X << L, (X + 1) << L).
class ColumnPyramid {
 public:
  ColumnPyramid(int kx0, int ky0, int nx, int ny, std::vector<int> tops) {
    levels_.resize(kTreeDepth + 1);
    Level& base = levels_[0];
    base.x0 = kx0;
    base.y0 = ky0;
    base.nx = nx;
    base.ny = ny;
    base.min = tops;
    base.max = std::move(tops);
    for (int l = 1; l <= kTreeDepth; ++l) {
      const Level& below = levels_[l - 1];
      Level& lv = levels_[l];
      lv.x0 = below.x0 >> 1;
      lv.y0 = below.y0 >> 1;
      lv.nx = ((below.x0 + below.nx - 1) >> 1) - lv.x0 + 1;
      lv.ny = ((below.y0 + below.ny - 1) >> 1) - lv.y0 + 1;
      lv.min.assign(static_cast<std::size_t>(lv.nx) * lv.ny, kNoTerrain);
      lv.max.assign(static_cast<std::size_t>(lv.nx) * lv.ny, kNoTerrain);
      for (int j = 0; j < lv.ny; ++j) {
        for (int i = 0; i < lv.nx; ++i) {
          int mn = INT_MAX;
          int mx = kNoTerrain;
          for (int c = 0; c < 4; ++c) {
            const int cx = 2 * (lv.x0 + i) + (c & 1) - below.x0;
            const int cy = 2 * (lv.y0 + j) + (c >> 1) - below.y0;
            if (cx < 0 || cy < 0 || cx >= below.nx || cy >= below.ny) {
              mn = kNoTerrain;  // a missing column: the block cannot be entirely solid
              continue;
            }
            const std::size_t k = static_cast<std::size_t>(cy) * below.nx + cx;
            mn = std::min(mn, below.min[k]);
            mx = std::max(mx, below.max[k]);
          }
          lv.min[static_cast<std::size_t>(j) * lv.nx + i] = mn;
          lv.max[static_cast<std::size_t>(j) * lv.nx + i] = mx;
        }
      }
    }
  }

  // (min, max) top over the block of level l containing column key (kx, ky).
  std::pair<int, int> query(int level, int kx, int ky) const {
    const Level& lv = levels_[level];
    const int i = (kx >> level) - lv.x0;
    const int j = (ky >> level) - lv.y0;
    if (i < 0 || j < 0 || i >= lv.nx || j >= lv.ny) return {kNoTerrain, kNoTerrain};
    const std::size_t k = static_cast<std::size_t>(j) * lv.nx + i;
    return {lv.min[k], lv.max[k]};
  }

 private:
  struct Level {
    int x0 = 0, y0 = 0, nx = 0, ny = 0;
    std::vector<int> min, max;
  };
  std::vector<Level> levels_;
};

enum class BoxFill { kEmpty, kFull, kMixed };

struct Builder {
  SolidOcTree* tree;
  const ColumnPyramid* pyramid;
  float occupied_log_odds;
  int bottom_key;  // lowest solid voxel key: columns are solid from here up to their top

  BoxFill classify(int depth, int x0, int y0, int z0) const {
    const int level = kTreeDepth - depth;
    const int z1 = z0 + (1 << level) - 1;
    const auto [mn, mx] = pyramid->query(level, x0, y0);
    if (mx == kNoTerrain || mx < z0 || z1 < bottom_key) return BoxFill::kEmpty;
    if (mn >= z1 && z0 >= bottom_key) return BoxFill::kFull;
    return BoxFill::kMixed;
  }

  void grow(octomap::OcTreeNode* node, int depth, int x0, int y0, int z0) {
    node->setLogOdds(occupied_log_odds);
    const int half = 1 << (kTreeDepth - depth - 1);
    for (unsigned c = 0; c < 8; ++c) {
      const int cx = x0 + ((c & 1) ? half : 0);
      const int cy = y0 + ((c & 2) ? half : 0);
      const int cz = z0 + ((c & 4) ? half : 0);
      const BoxFill fill = classify(depth + 1, cx, cy, cz);
      if (fill == BoxFill::kEmpty) continue;
      octomap::OcTreeNode* child = tree->createNodeChild(node, c);
      child->setLogOdds(occupied_log_odds);
      if (fill == BoxFill::kMixed) grow(child, depth + 1, cx, cy, cz);
    }
  }
};

}  // namespace

std::size_t estimateOctreePeakBytes(const Heightfield& terrain, double resolution_m) {
  // Measured on NASADEM N44W072 (1 arc-second, 79 x 111 km) at 10-45 m: finer than the DEM's
  // cells, the surface cuts about 2.2 finest voxels per column, each leaf costs 37 B in the
  // finished tree, and building peaks at 1.85x the finished tree (the column tops, the pyramid,
  // OctoMap's growth). 150 B per column holds there within 10 % and over-estimates coarser trees,
  // which merge their leaves.
  constexpr double kPeakBytesPerColumn = 150.0;
  const Eigen::Vector2d size_m = terrain.boundsEn().sizes();
  const double columns = (std::floor(size_m.x() / resolution_m) + 2.0) * (std::floor(size_m.y() / resolution_m) + 2.0);
  return static_cast<std::size_t>(columns * kPeakBytesPerColumn);
}

std::unique_ptr<TerrainOctree> TerrainOctree::build(std::shared_ptr<const Heightfield> terrain,
                                                    const TerrainOctreeOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::unique_ptr<TerrainOctree> out(new TerrainOctree());
  out->terrain_ = terrain;
  out->options_ = options;
  auto tree = std::make_shared<SolidOcTree>(options.resolution_m);

  const Eigen::AlignedBox2d& box = terrain->boundsEn();
  const double res = options.resolution_m;
  const int kx0 = static_cast<int>(std::floor(box.min().x() / res)) + kTreeMaxVal;
  const int ky0 = static_cast<int>(std::floor(box.min().y() / res)) + kTreeMaxVal;
  const int kx1 = static_cast<int>(std::floor(box.max().x() / res)) + kTreeMaxVal;
  const int ky1 = static_cast<int>(std::floor(box.max().y() / res)) + kTreeMaxVal;
  const int nx = kx1 - kx0 + 1;
  const int ny = ky1 - ky0 + 1;
  std::vector<int> tops(static_cast<std::size_t>(nx) * ny, kNoTerrain);
  const double unknown_top = terrain->maxHeightM();
  for (int j = 0; j < ny; ++j) {
    const double north = (ky0 + j - kTreeMaxVal + 0.5) * res;
    for (int i = 0; i < nx; ++i) {
      const double east = (kx0 + i - kTreeMaxVal + 0.5) * res;
      if (!terrain->inside(east, north)) continue;
      double h = terrain->heightAt(east, north);
      if (std::isnan(h)) h = unknown_top;  // unknown ground: solid up to the highest known ground
      h += options.inflation_m;
      // Voxel k is solid when its centre (k - 32768 + 0.5) * res lies under h.
      const double limit = h / res + kTreeMaxVal - 0.5;
      const long long top = static_cast<long long>(std::ceil(limit)) - 1;
      tops[static_cast<std::size_t>(j) * nx + i] = static_cast<int>(std::clamp(top, -1LL, 65535LL));
    }
  }
  ColumnPyramid pyramid(kx0, ky0, nx, ny, std::move(tops));
  // Columns are solid down to a floor a little under the lowest ground, not to the centre of the
  // Earth: nothing flies lower, and a floor keeps the walls at the DEM's edges short.
  const double floor_m = terrain->minHeightM() - 2.0 * res;
  const int bottom_key = static_cast<int>(std::floor(floor_m / res)) + kTreeMaxVal;
  Builder builder{tree.get(), &pyramid, tree->getClampingThresMaxLog(), bottom_key};
  if (builder.classify(0, 0, 0, 0) != BoxFill::kEmpty) {
    if (builder.classify(0, 0, 0, 0) == BoxFill::kFull) {
      tree->makeRoot()->setLogOdds(builder.occupied_log_odds);
    } else {
      builder.grow(tree->makeRoot(), 0, 0, 0, 0);
    }
  }
  out->tree_ = tree;
  out->stats_.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  out->stats_.node_count = tree->size();
  out->stats_.leaf_count = tree->getNumLeafNodes();
  out->stats_.memory_bytes = tree->memoryUsage();
  return out;
}

bool TerrainOctree::occupied(const Eigen::Vector3d& p_m) const {
  const octomap::OcTreeNode* node = tree_->search(p_m.x(), p_m.y(), p_m.z());
  return node != nullptr && tree_->isNodeOccupied(node);
}

bool TerrainOctree::terrainOccupiesVoxel(const Eigen::Vector3d& center_m) const {
  if (!terrain_->inside(center_m.x(), center_m.y())) return false;
  double h = terrain_->heightAt(center_m.x(), center_m.y());
  if (std::isnan(h)) h = terrain_->maxHeightM();
  return center_m.z() < h + options_.inflation_m;
}

void TerrainOctree::addObstacle(const Obstacle& obstacle, double t_s) {
  removeObstacle(obstacle.id);
  const Eigen::Vector3d c = obstacle.centerAt(t_s);
  const double r = obstacle.boundingRadius();
  const octomap::OcTreeKey lo = tree_->coordToKey(c.x() - r, c.y() - r, c.z() - r);
  const octomap::OcTreeKey hi = tree_->coordToKey(c.x() + r, c.y() + r, c.z() + r);
  auto& keys = obstacle_voxels_[obstacle.id];
  octomap::OcTree* mutable_tree = tree_.get();
  const float occupied = mutable_tree->getClampingThresMaxLog();
  for (unsigned kz = lo[2]; kz <= hi[2]; ++kz) {
    for (unsigned ky = lo[1]; ky <= hi[1]; ++ky) {
      for (unsigned kx = lo[0]; kx <= hi[0]; ++kx) {
        const octomap::OcTreeKey key(kx, ky, kz);
        const octomap::point3d p = tree_->keyToCoord(key);
        const Eigen::Vector3d centre(p.x(), p.y(), p.z());
        if (!obstacle.contains(centre, t_s) || terrainOccupiesVoxel(centre)) continue;
        mutable_tree->setNodeValue(key, occupied, true);
        keys.push_back(key);
      }
    }
  }
  mutable_tree->updateInnerOccupancy();
}

bool TerrainOctree::removeObstacle(std::uint64_t id) {
  auto it = obstacle_voxels_.find(id);
  if (it == obstacle_voxels_.end()) return false;
  octomap::OcTree* mutable_tree = tree_.get();
  std::unordered_set<octomap::OcTreeKey, octomap::OcTreeKey::KeyHash> removed(it->second.begin(), it->second.end());
  // Mark the voxels free rather than deleting them: OctoMap 1.9's deleteNode can free a node whose
  // (empty) children array is still allocated, which its own assertions reject.
  const float free_log_odds = mutable_tree->getClampingThresMinLog();
  for (const auto& key : it->second) mutable_tree->setNodeValue(key, free_log_odds, true);
  obstacle_voxels_.erase(it);
  // Voxels another obstacle also covers stay occupied.
  const float occupied = mutable_tree->getClampingThresMaxLog();
  for (const auto& [other_id, keys] : obstacle_voxels_) {
    for (const auto& key : keys) {
      if (removed.count(key)) mutable_tree->setNodeValue(key, occupied, true);
    }
  }
  mutable_tree->updateInnerOccupancy();
  return true;
}

}  // namespace skyroute
