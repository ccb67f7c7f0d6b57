// GridMotionValidator (bench/support/grid_motion_validator): a GridLayer as a MotionValidator. Checked
// against GridLayer::lineOfSight between cell centres, against an independent clipping test for
// arbitrary endpoints, and by running RRT* and LOSPO on a grid.
#include "bench/support/grid_motion_validator.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "planning/grid/any_angle_search.hpp"
#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "tests/planning/any_angle_reference.hpp"
#include "tests/planning/hab_maps.hpp"

namespace skyroute {
namespace {

// A seeded grid with about `blocked_share` of its cells blocked, in a shifted, scaled frame so the
// metre <-> cell conversion is exercised too.
GridLayer randomGrid(unsigned seed, int w, int h, double blocked_share) {
  GridLayer g(w, h, 2.5, Eigen::Vector2d(-40.0, 17.0));
  std::mt19937 rng(seed);
  std::bernoulli_distribution blocked(blocked_share);
  std::vector<GridCell> cells;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (blocked(rng)) cells.push_back(GridCell{x, y});
    }
  }
  g.setStaticBlocked(cells, true);
  return g;
}

// Independent reference: every cell whose closed square the (x, y) shadow of a-b touches is free.
bool referenceMotion(const GridLayer& g, const GridMotionValidator& v, const Eigen::Vector3d& a_m,
                     const Eigen::Vector3d& b_m) {
  const Eigen::Vector2d a = v.toCell(a_m), b = v.toCell(b_m);
  for (int y = static_cast<int>(std::floor(std::min(a.y(), b.y()))) - 1; y <= std::max(a.y(), b.y()) + 1; ++y) {
    for (int x = static_cast<int>(std::floor(std::min(a.x(), b.x()))) - 1; x <= std::max(a.x(), b.x()) + 1; ++x) {
      if (testing::segmentTouchesCell(a.x(), a.y(), b.x(), b.y(), GridCell{x, y}) && g.blocked(GridCell{x, y})) {
        return false;
      }
    }
  }
  return true;
}

TEST(GridMotionValidator, BetweenCellCentresEqualsGridLineOfSight) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const GridLayer g = randomGrid(seed, 30, 22, 0.2);
    const GridMotionValidator v(g);
    std::mt19937 rng(seed * 31);
    std::uniform_int_distribution<int> x(0, g.width() - 1), y(0, g.height() - 1);
    int visible = 0, hidden = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      const GridCell a{x(rng), y(rng)}, b{x(rng), y(rng)};
      if (g.blocked(a) || g.blocked(b)) continue;
      const bool los = g.lineOfSight(a, b);
      (los ? visible : hidden)++;
      const Eigen::Vector2d pa = g.cellCenter(a), pb = g.cellCenter(b);
      EXPECT_EQ(v.isMotionValid(Eigen::Vector3d(pa.x(), pa.y(), 0.0), Eigen::Vector3d(pb.x(), pb.y(), 0.2)), los)
          << "(" << a.x << "," << a.y << ")-(" << b.x << "," << b.y << ")";
    }
    EXPECT_GT(visible, 50);  // both outcomes were exercised
    EXPECT_GT(hidden, 50);
  }
}

TEST(GridMotionValidator, ArbitraryEndpointsMatchAClippingReference) {
  const GridLayer g = randomGrid(9, 25, 25, 0.15);
  const GridMotionValidator v(g);
  const Eigen::AlignedBox3d box = v.samplingBounds();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto draw = [&] {
    return Eigen::Vector3d(box.min().x() + u(rng) * box.sizes().x(), box.min().y() + u(rng) * box.sizes().y(), 0.0);
  };
  int valid = 0, invalid = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Eigen::Vector3d a = draw(), b = draw();
    if (!v.isStateValid(a) || !v.isStateValid(b)) continue;
    const bool expected = referenceMotion(g, v, a, b);
    (expected ? valid : invalid)++;
    EXPECT_EQ(v.isMotionValid(a, b), expected);
  }
  EXPECT_GT(valid, 50);
  EXPECT_GT(invalid, 50);
}

TEST(GridMotionValidator, CornersBordersAndTheBand) {
  // Cell (1, 0) blocked: the corner (0.5, 0.5) touches it.
  const GridLayer g = GridLayer::fromRows({".#.", "...", "..."});
  const GridMotionValidator v(g, -1.0, 2.0);
  auto p = [](double x, double y, double z = 0.0) { return Eigen::Vector3d(x, y, z); };
  EXPECT_FALSE(v.isMotionValid(p(0, 0), p(1, 1)));           // through the corner of the blocked cell
  EXPECT_TRUE(v.isMotionValid(p(0, 0.1), p(0.9, 1)));        // 0.07 cells clear of that corner
  EXPECT_FALSE(v.isMotionValid(p(0, 0), p(2, 0)));           // straight through it
  EXPECT_TRUE(v.isMotionValid(p(0, 2), p(2, 2)));
  EXPECT_TRUE(v.isStateValid(p(0.2, 0.3)));
  EXPECT_FALSE(v.isStateValid(p(1, 0)));                     // over the blocked cell
  EXPECT_FALSE(v.isStateValid(p(0.5, 0)));                   // on its border
  EXPECT_FALSE(v.isStateValid(p(-0.7, 1)));                  // outside the grid
  EXPECT_FALSE(v.isStateValid(p(0, 2, 2.5)));                // above the band
  EXPECT_FALSE(v.isMotionValid(p(0, 2, 0), p(2, 2, -1.5)));  // ends below the band
  const Eigen::AlignedBox3d box = v.samplingBounds();
  EXPECT_EQ(box.min(), p(0, 0, -1));
  EXPECT_EQ(box.max(), p(2, 2, 2));
}

TEST(GridMotionValidator, RrtStarAndLospoPlanValidPathsOnTheGrid) {
  for (const testing::KnownMap& m : testing::knownMaps()) {
    const GridMotionValidator v(m.grid);
    RrtStarOptions o;
    o.seed = 3;
    o.max_step_m = 6.0;
    auto plan = RrtStar(v, o).plan(Eigen::Vector3d(m.start.x, m.start.y, 0.0), Eigen::Vector3d(m.goal.x, m.goal.y, 0.0),
                                   TerminationCondition().withIterationBudget(3000));
    ASSERT_TRUE(plan.ok()) << plan.error().describe();
    ASSERT_TRUE(plan->solved()) << m.name;
    std::vector<Eigen::Vector3d> flat = plan->path_m;
    for (Eigen::Vector3d& q : flat) q.z() = 0.0;  // the 2D path: still valid, no longer
    auto shortened = lospo(v, flat, LospoOptions{.spacing_m = 0.5, .max_passes = 4});
    ASSERT_TRUE(shortened.ok()) << shortened.error().describe();
    const std::vector<Eigen::Vector3d>& path = shortened->path_m;
    for (std::size_t i = 1; i < path.size(); ++i) {
      EXPECT_TRUE(referenceMotion(m.grid, v, path[i - 1], path[i])) << m.name << " segment " << i - 1;
    }
    // Vertices off cell centres may pass closer to the obstacle corners than Theta*'s cell-centre
    // vertices can (6 % shorter on the narrow corridor), never by much.
    const double theta = thetaStar(m.grid, m.start, m.goal, TerminationCondition{}).length_cells;
    EXPECT_LE(shortened->length_m, plan->length_m + 1e-9) << m.name;
    EXPECT_LT(shortened->length_m, 1.03 * theta) << m.name;
    EXPECT_GT(shortened->length_m, 0.9 * theta) << m.name;
  }
}

}  // namespace
}  // namespace skyroute
