#include "terrain/grid_layer.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include <sstream>

#include <gtest/gtest.h>

#include "terrain/movingai.hpp"
#include "tests/test_data.hpp"

namespace skyroute {
namespace {

// Reference line of sight, by plain geometry: every closed cell square the segment touches
// (interior, edge or corner) must be free. Slab clipping per cell of the bounding box.
bool segmentTouchesCell(double ax, double ay, double bx, double by, int cx, int cy) {
  double t0 = 0.0;
  double t1 = 1.0;
  const double d[2] = {bx - ax, by - ay};
  const double a[2] = {ax, ay};
  const double lo[2] = {cx - 0.5, cy - 0.5};
  const double hi[2] = {cx + 0.5, cy + 0.5};
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k];
    double tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 + 1e-12;
}

bool denseLineOfSight(const GridLayer& g, GridCell a, GridCell b) {
  for (int y = std::min(a.y, b.y); y <= std::max(a.y, b.y); ++y)
    for (int x = std::min(a.x, b.x); x <= std::max(a.x, b.x); ++x)
      if (g.blocked(GridCell{x, y}) && segmentTouchesCell(a.x, a.y, b.x, b.y, x, y)) return false;
  return true;
}

TEST(GridLayer, UpdatesReportExactlyTheChangedCells) {
  GridLayer g(10, 8, 30.0, Eigen::Vector2d(100.0, 200.0));
  const std::vector<GridCell> wall{{1, 1}, {2, 1}, {3, 1}};
  EXPECT_EQ(g.setStaticBlocked(wall, true).size(), 3u);
  EXPECT_TRUE(g.setStaticBlocked(wall, true).empty());  // already blocked: nothing changed
  const std::vector<GridCell> cover{{3, 1}, {4, 1}};
  const auto added = g.addObstacleCover(cover);
  ASSERT_EQ(added.size(), 1u);
  EXPECT_EQ(added[0], (GridCell{4, 1}));
  const auto removed = g.removeObstacleCover(cover);
  ASSERT_EQ(removed.size(), 1u);  // (3,1) stays blocked by the static layer
  EXPECT_EQ(removed[0], (GridCell{4, 1}));
  EXPECT_TRUE(g.blocked(GridCell{3, 1}));
  EXPECT_TRUE(g.blocked(GridCell{-1, 0}));
  EXPECT_EQ(g.blockedCount(), 3u);
}

// cropped: the box's cells keep their blocked state (static and obstacle layers), cells beyond the
// grid come out blocked, and each crop cell sits where its source cell sits in ENU.
TEST(GridLayer, CroppedKeepsCellsAndPlace) {
  GridLayer g(10, 8, 30.0, Eigen::Vector2d(100.0, 200.0));
  g.setStaticBlocked(std::vector<GridCell>{{3, 2}, {6, 5}}, true);
  g.addObstacleCover(std::vector<GridCell>{{4, 4}});
  const GridLayer c = g.cropped(GridCell{3, 2}, 9, 4);  // x 3..11 (beyond the grid from 10), y 2..5
  ASSERT_EQ(c.width(), 9);
  ASSERT_EQ(c.height(), 4);
  for (int y = 0; y < c.height(); ++y) {
    for (int x = 0; x < c.width(); ++x) {
      const GridCell source{3 + x, 2 + y};
      EXPECT_EQ(c.blocked(GridCell{x, y}), g.blocked(source)) << x << "," << y;
      if (g.inside(source)) {
        EXPECT_LT((c.cellCenter(GridCell{x, y}) - g.cellCenter(source)).norm(), 1e-9);
      }
    }
  }
  EXPECT_TRUE(c.blocked(GridCell{0, 0}));  // (3, 2), static
  EXPECT_TRUE(c.blocked(GridCell{1, 2}));  // (4, 4), obstacle
  EXPECT_TRUE(c.blocked(GridCell{8, 0}));  // (11, 2), beyond the grid
  EXPECT_EQ(c.blockedCount(), 3u + 2u * 4u);
}

TEST(GridLayer, CellAndEnuRoundTrip) {
  GridLayer g(10, 8, 30.0, Eigen::Vector2d(100.0, 200.0));
  const GridCell c{7, 5};
  const Eigen::Vector2d p = g.cellCenter(c);
  EXPECT_DOUBLE_EQ(p.x(), 100.0 + 7 * 30.0);
  EXPECT_EQ(g.cellAt(p + Eigen::Vector2d(14.0, -14.0)).value(), c);
  EXPECT_FALSE(g.cellAt(Eigen::Vector2d(0.0, 0.0)).has_value());
}

TEST(GridLayer, LineOfSightMatchesDenseReference) {
  std::mt19937 rng(7);
  GridLayer g(24, 24);
  std::vector<GridCell> blocked;
  std::bernoulli_distribution coin(0.15);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x)
      if (coin(rng)) blocked.push_back({x, y});
  g.setStaticBlocked(blocked, true);
  std::uniform_int_distribution<int> pick(0, 23);
  int visible = 0;
  for (int i = 0; i < 3000; ++i) {
    const GridCell a{pick(rng), pick(rng)};
    const GridCell b{pick(rng), pick(rng)};
    const bool expected = denseLineOfSight(g, a, b);
    ASSERT_EQ(g.lineOfSight(a, b), expected) << a.x << "," << a.y << " -> " << b.x << "," << b.y;
    visible += expected ? 1 : 0;
  }
  EXPECT_GT(visible, 100);  // the sample covers both answers
}

TEST(GridLayer, DiagonalThroughCornerNeedsBothSidesFree) {
  GridLayer g(3, 3);
  const std::vector<GridCell> one{{1, 0}};
  g.setStaticBlocked(one, true);
  EXPECT_FALSE(g.lineOfSight({0, 0}, {1, 1}));
  EXPECT_TRUE(g.lineOfSight({0, 1}, {1, 2}));
}

TEST(MovingAi, LoadsMapAndScenario) {
  SKYROUTE_REQUIRE_SHARED(map_path, "movingai/Boston_0_256.map");
  const auto map = loadMovingAiMap(map_path);
  ASSERT_TRUE(map.ok()) << map.error().describe();
  EXPECT_EQ(map->width(), 256);
  EXPECT_EQ(map->height(), 256);
  EXPECT_GT(map->blockedCount(), 1000u);
  const auto scen = loadMovingAiScenario(map_path + ".scen");
  ASSERT_TRUE(scen.ok()) << scen.error().describe();
  EXPECT_EQ(scen->size(), 950u);
  for (const auto& p : *scen) {
    EXPECT_TRUE(map->passable(p.start));
    EXPECT_TRUE(map->passable(p.goal));
  }
}

TEST(MovingAi, MalformedFilesNameTheLine) {
  const std::string path = ::testing::TempDir() + "/bad.map";
  FILE* f = fopen(path.c_str(), "w");
  fputs("type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n", f);
  fclose(f);
  const auto map = loadMovingAiMap(path);
  ASSERT_FALSE(map.ok());
  EXPECT_EQ(map.error().code, ErrorCode::kParseError);
  EXPECT_NE(map.error().message.find("line 6"), std::string::npos) << map.error().message;
  EXPECT_EQ(loadMovingAiMap("/nonexistent.map").error().code, ErrorCode::kFileNotFound);
}

TEST(MovingAi, AHeaderAloneAllocatesNothing) {
  // 10^10 cells declared, one row given: the grid was allocated before the rows were read.
  std::istringstream in("type octile\nheight 100000\nwidth 100000\nmap\n....\n");
  const auto map = parseMovingAiMap(in, "huge.map");
  ASSERT_FALSE(map.ok());
  EXPECT_NE(map.error().message.find("row shorter than the width"), std::string::npos) << map.error().message;
}

}  // namespace
}  // namespace skyroute
