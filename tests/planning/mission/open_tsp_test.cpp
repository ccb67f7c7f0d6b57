// Open TSP: Held-Karp against brute force over all permutations; B first and E last; the
// heuristic is never better than the exact answer and reports its gap; bad inputs.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "planning/mission/open_tsp.hpp"

namespace skyroute {
namespace {

using Matrix = std::vector<std::vector<double>>;

Matrix randomMatrix(int m, bool symmetric, std::mt19937& rng) {
  const int n = m + 2;
  std::uniform_real_distribution<double> u(1.0, 100.0);
  Matrix c(n, std::vector<double>(n, 0.0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i != j) c[i][j] = (symmetric && j < i) ? c[j][i] : u(rng);
  return c;
}

double bruteForce(const Matrix& c) {
  const int n = static_cast<int>(c.size());
  std::vector<int> inner(n - 2);
  std::iota(inner.begin(), inner.end(), 1);
  double best = std::numeric_limits<double>::infinity();
  do {
    std::vector<int> order{0};
    order.insert(order.end(), inner.begin(), inner.end());
    order.push_back(n - 1);
    best = std::min(best, openTspPathCost(c, order));
  } while (std::next_permutation(inner.begin(), inner.end()));
  return best;
}

void expectValidOrder(const std::vector<int>& order, int n) {
  ASSERT_EQ(static_cast<int>(order.size()), n);
  EXPECT_EQ(order.front(), 0);
  EXPECT_EQ(order.back(), n - 1);
  EXPECT_EQ(std::set<int>(order.begin(), order.end()).size(), order.size());
}

TEST(OpenTsp, HeldKarpMatchesBruteForce) {
  std::mt19937 rng(99);
  for (int m = 0; m <= 8; ++m) {
    for (int trial = 0; trial < 6; ++trial) {
      const Matrix c = randomMatrix(m, trial % 2 == 0, rng);
      auto r = solveOpenTspExact(c);
      ASSERT_TRUE(r.ok()) << r.error().describe();
      expectValidOrder(r->order, m + 2);
      EXPECT_NEAR(r->cost, bruteForce(c), 1e-9) << "m=" << m;
      EXPECT_NEAR(r->cost, openTspPathCost(c, r->order), 1e-9);
    }
  }
}

TEST(OpenTsp, HeuristicIsValidAndReportsItsGap) {
  std::mt19937 rng(5);
  for (int m = 2; m <= 12; ++m) {
    const Matrix c = randomMatrix(m, true, rng);
    auto r = solveOpenTsp(c);
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r->exact);
    ASSERT_TRUE(r->gap.has_value());
    EXPECT_GE(*r->gap, -1e-12);
    EXPECT_GE(*r->heuristic_cost, r->cost - 1e-9);
    auto h = solveOpenTspHeuristic(c);
    ASSERT_TRUE(h.ok());
    expectValidOrder(h->order, m + 2);
    EXPECT_NEAR(h->cost, openTspPathCost(c, h->order), 1e-9);
  }
}

TEST(OpenTsp, ExactUpToSixteenHeuristicAbove) {
  std::mt19937 rng(8);
  auto r16 = solveOpenTsp(randomMatrix(16, true, rng));
  ASSERT_TRUE(r16.ok());
  EXPECT_TRUE(r16->exact);
  expectValidOrder(r16->order, 18);
  auto r30 = solveOpenTsp(randomMatrix(30, true, rng));
  ASSERT_TRUE(r30.ok());
  EXPECT_FALSE(r30->exact);
  expectValidOrder(r30->order, 32);
}

TEST(OpenTsp, EuclideanPointsOnALineAreVisitedInOrder) {
  // B at 0, E at 10, mission points at 7, 2, 5: the only sensible order is 2, 5, 7.
  const std::vector<double> x{0, 7, 2, 5, 10};
  Matrix c(5, std::vector<double>(5));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) c[i][j] = std::abs(x[i] - x[j]);
  auto r = solveOpenTsp(c);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->order, (std::vector<int>{0, 2, 3, 1, 4}));
  EXPECT_DOUBLE_EQ(r->cost, 10.0);
}

TEST(OpenTsp, BadInputs) {
  EXPECT_EQ(solveOpenTsp(Matrix{{0.0}}).error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(solveOpenTsp(Matrix{{0, 1}, {1}}).error().code, ErrorCode::kInvalidArgument);
  Matrix nan_c{{0, NAN, 1}, {1, 0, 1}, {1, 1, 0}};
  auto r = solveOpenTsp(nan_c);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("[0][1]"), std::string::npos);
  const double inf = std::numeric_limits<double>::infinity();
  Matrix cut{{0, inf, 1}, {inf, 0, inf}, {1, inf, 0}};
  EXPECT_EQ(solveOpenTsp(cut).error().code, ErrorCode::kUnreachable);
  EXPECT_EQ(solveOpenTspHeuristic(cut).error().code, ErrorCode::kUnreachable);
}

}  // namespace
}  // namespace skyroute
