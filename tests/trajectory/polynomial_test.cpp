// Polynomial7: derivatives against central finite differences and against hand-differentiated
// monomials; time scaling by the segment duration.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "trajectory/polynomial.hpp"

namespace skyroute {
namespace {

TEST(Polynomial7, MonomialDerivativesMatchHandComputed) {
  // x = tau^7: derivatives 7 tau^6, 42 tau^5, 210 tau^4, 840 tau^3 ... 5040 at order 7, 0 at 8.
  Polynomial7::Coefficients c{};
  c[7] = 1.0;
  const Polynomial7 p(c);
  const double tau = 0.6;
  EXPECT_NEAR(p.evaluateTau(tau, 0), std::pow(tau, 7), 1e-15);
  EXPECT_NEAR(p.evaluateTau(tau, 1), 7 * std::pow(tau, 6), 1e-14);
  EXPECT_NEAR(p.evaluateTau(tau, 3), 210 * std::pow(tau, 4), 1e-12);
  EXPECT_NEAR(p.evaluateTau(tau, 4), 840 * std::pow(tau, 3), 1e-12);
  EXPECT_NEAR(p.evaluateTau(tau, 7), 5040.0, 1e-9);
  EXPECT_EQ(p.evaluateTau(tau, 8), 0.0);
}

TEST(Polynomial7, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coef(-10.0, 10.0);
  for (int trial = 0; trial < 20; ++trial) {
    Polynomial7::Coefficients c;
    for (double& a : c) a = coef(rng);
    const Polynomial7 p(c);
    const double duration = 0.5 + trial;  // seconds
    const double h = 1e-4;                // in tau
    for (double tau : {0.1, 0.37, 0.8}) {
      for (int n = 1; n <= 4; ++n) {
        const double fd_tau = (p.evaluateTau(tau + h, n - 1) - p.evaluateTau(tau - h, n - 1)) / (2 * h);
        EXPECT_NEAR(p.evaluateTau(tau, n), fd_tau, 1e-5 * (1.0 + std::abs(fd_tau))) << "n=" << n;
        // In time: d/dt = (1/T) d/dtau.
        const double fd_time = (p.evaluateTime(tau + h, n - 1, duration) - p.evaluateTime(tau - h, n - 1, duration)) /
                               (2 * h * duration);
        EXPECT_NEAR(p.evaluateTime(tau, n, duration), fd_time, 1e-5 * (1.0 + std::abs(fd_time)));
      }
    }
  }
}

TEST(Polynomial7, NamedDerivativeIsTheOrder) {
  Polynomial7::Coefficients c{};
  c[2] = 3.0;  // x = 3 tau^2, T = 2 s: x'' = 6 / 4 = 1.5 m/s^2
  const Polynomial7 p(c);
  EXPECT_DOUBLE_EQ(p.evaluateTime(0.3, Derivative::kAcceleration, 2.0), 1.5);
  EXPECT_EQ(to_string(Derivative::kSnap), "snap");
}

}  // namespace
}  // namespace skyroute
