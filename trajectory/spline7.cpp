#include "trajectory/spline7.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

namespace skyroute {
namespace {

using Matrix8 = Eigen::Matrix<double, 8, 8>;
using Vector8 = Eigen::Matrix<double, 8, 1>;
constexpr int kEndOrders = 4;  // position, velocity, acceleration, jerk at each end of a segment

// Hermite matrix: rows are derivative n (0..3) at tau = 0, then at tau = 1; columns coefficients.
// Its inverse maps end derivatives (in tau) to coefficients.
const Matrix8& hermiteInverse() {
  static const Matrix8 inverse = [] {
    Matrix8 a = Matrix8::Zero();
    for (int n = 0; n < kEndOrders; ++n) {
      a(n, n) = Polynomial7::fallingFactorial(n, n);
      for (int k = n; k < 8; ++k) a(kEndOrders + n, k) = Polynomial7::fallingFactorial(k, n);
    }
    return Matrix8(a.inverse());
  }();
  return inverse;
}

// Gram matrix of the 4th tau-derivatives of the monomials on [0, 1].
const Matrix8& snapGram() {
  static const Matrix8 gram = [] {
    Matrix8 q = Matrix8::Zero();
    for (int i = 4; i < 8; ++i)
      for (int j = 4; j < 8; ++j)
        q(i, j) = Polynomial7::fallingFactorial(i, 4) * Polynomial7::fallingFactorial(j, 4) / (i + j - 7);
    return q;
  }();
  return gram;
}

// Snap cost in terms of the end derivatives in tau: K = Hinv^T Q Hinv.
const Matrix8& snapCostInTau() {
  static const Matrix8 k = [] {
    const Matrix8& h = hermiteInverse();
    return Matrix8(h.transpose() * snapGram() * h);
  }();
  return k;
}

bool finite3(const Eigen::Vector3d& v) { return v.allFinite(); }

Status checkWaypointsAndDurations(const std::vector<Eigen::Vector3d>& waypoints,
                                  const std::vector<double>& durations_s) {
  if (waypoints.size() < 2)
    return make_error(ErrorCode::kInvalidArgument, "waypoints",
                      "need at least 2 waypoints, got " + std::to_string(waypoints.size()));
  for (std::size_t i = 0; i < waypoints.size(); ++i)
    if (!finite3(waypoints[i]))
      return make_error(ErrorCode::kInvalidArgument, "waypoints[" + std::to_string(i) + "]",
                        "coordinate is NaN or infinite");
  if (durations_s.size() + 1 != waypoints.size())
    return make_error(ErrorCode::kInvalidArgument, "durations_s",
                      "need one duration per segment (" + std::to_string(waypoints.size() - 1) + "), got " +
                          std::to_string(durations_s.size()));
  for (std::size_t i = 0; i < durations_s.size(); ++i)
    if (!std::isfinite(durations_s[i]) || durations_s[i] <= 0.0)
      return make_error(ErrorCode::kInvalidArgument, "durations_s[" + std::to_string(i) + "]",
                        "must be positive and finite, got " + std::to_string(durations_s[i]));
  return Status::success();
}

// Physical end derivatives of one axis: [p0, v0, a0, j0, p1, v1, a1, j1] -> segment polynomial.
Polynomial7 hermitePolynomial(const Vector8& physical, double duration_s) {
  Vector8 in_tau = physical;
  for (int n = 0; n < kEndOrders; ++n) {
    const double scale = std::pow(duration_s, n);
    in_tau(n) *= scale;
    in_tau(kEndOrders + n) *= scale;
  }
  const Vector8 c = hermiteInverse() * in_tau;
  Polynomial7::Coefficients coefficients;
  for (int k = 0; k < 8; ++k) coefficients[k] = c(k);
  return Polynomial7(coefficients);
}

Eigen::Vector3d knotValue(const KnotDerivatives& k, int n) {
  switch (n) {
    case 1: return k.velocity_mps;
    case 2: return k.acceleration_mps2;
    default: return k.jerk_mps3;
  }
}

}  // namespace

Result<std::vector<Segment>> hermiteSpline(const std::vector<Eigen::Vector3d>& waypoints,
                                           const std::vector<double>& durations_s,
                                           const std::vector<KnotDerivatives>& knots) {
  if (Status s = checkWaypointsAndDurations(waypoints, durations_s); !s) return s.error();
  if (knots.size() != waypoints.size())
    return make_error(ErrorCode::kInvalidArgument, "knots", "need one entry per waypoint");
  std::vector<Segment> segments(durations_s.size());
  for (std::size_t s = 0; s < segments.size(); ++s) {
    segments[s].duration_s = durations_s[s];
    for (int axis = 0; axis < 3; ++axis) {
      Vector8 physical;
      physical(0) = waypoints[s](axis);
      physical(kEndOrders) = waypoints[s + 1](axis);
      for (int n = 1; n < kEndOrders; ++n) {
        physical(n) = knotValue(knots[s], n)(axis);
        physical(kEndOrders + n) = knotValue(knots[s + 1], n)(axis);
      }
      segments[s].axes[axis] = hermitePolynomial(physical, durations_s[s]);
    }
  }
  return segments;
}

Result<std::vector<Segment>> solveMinimumSnapSpline(const std::vector<Eigen::Vector3d>& waypoints,
                                                    const std::vector<double>& durations_s,
                                                    const SplineBoundary& boundary) {
  if (Status s = checkWaypointsAndDurations(waypoints, durations_s); !s) return s.error();
  const std::pair<const char*, const Eigen::Vector3d*> ends[] = {
      {"boundary.start.velocity_mps", &boundary.start.velocity_mps},
      {"boundary.start.acceleration_mps2", &boundary.start.acceleration_mps2},
      {"boundary.start.jerk_mps3", &boundary.start.jerk_mps3},
      {"boundary.end.velocity_mps", &boundary.end.velocity_mps},
      {"boundary.end.acceleration_mps2", &boundary.end.acceleration_mps2},
      {"boundary.end.jerk_mps3", &boundary.end.jerk_mps3}};
  for (const auto& [name, value] : ends)
    if (!finite3(*value)) return make_error(ErrorCode::kInvalidArgument, name, "is NaN or infinite");

  const int segments = static_cast<int>(durations_s.size());
  const int knots = segments + 1;
  std::vector<KnotDerivatives> derivatives(static_cast<std::size_t>(knots));
  derivatives.front() = {boundary.start.velocity_mps, boundary.start.acceleration_mps2, boundary.start.jerk_mps3};
  derivatives.back() = {boundary.end.velocity_mps, boundary.end.acceleration_mps2, boundary.end.jerk_mps3};

  if (segments > 1) {
    // Variables per axis: knot i, order n in 0..3 at global index 4 i + n. Free: orders 1..3 of the
    // interior knots, numbered 3 (i - 1) + (n - 1). Everything else is fixed.
    const int free_count = 3 * (knots - 2);
    auto free_index = [&](int knot, int n) { return (knot >= 1 && knot <= knots - 2 && n >= 1) ? 3 * (knot - 1) + (n - 1) : -1; };
    auto fixed_value = [&](int knot, int n, int axis) -> double {
      if (n == 0) return waypoints[static_cast<std::size_t>(knot)](axis);
      return knotValue(derivatives[static_cast<std::size_t>(knot)], n)(axis);
    };

    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(segments) * 36);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free_count, 3);
    const Matrix8& k_tau = snapCostInTau();
    for (int s = 0; s < segments; ++s) {
      const double t = durations_s[static_cast<std::size_t>(s)];
      // Segment cost in physical end derivatives: K(a, b) T^(n_a + n_b - 7).
      for (int a = 0; a < 8; ++a) {
        const int knot_a = s + a / kEndOrders, n_a = a % kEndOrders;
        const int fa = free_index(knot_a, n_a);
        if (fa < 0) continue;
        for (int b = 0; b < 8; ++b) {
          const int knot_b = s + b / kEndOrders, n_b = b % kEndOrders;
          const double h = k_tau(a, b) * std::pow(t, n_a + n_b - 7);
          const int fb = free_index(knot_b, n_b);
          if (fb >= 0) {
            triplets.emplace_back(fa, fb, h);
          } else {
            for (int axis = 0; axis < 3; ++axis) rhs(fa, axis) -= h * fixed_value(knot_b, n_b, axis);
          }
        }
      }
    }
    Eigen::SparseMatrix<double> hessian(free_count, free_count);
    hessian.setFromTriplets(triplets.begin(), triplets.end());
    // Symmetric Jacobi scaling: velocities, accelerations and jerks differ by orders of magnitude
    // in this system (powers of the durations); scaling keeps the factorisation well conditioned.
    Eigen::VectorXd scale(free_count);
    for (int i = 0; i < free_count; ++i) {
      const double d = hessian.coeff(i, i);
      if (!(d > 0.0) || !std::isfinite(d))
        return make_error(ErrorCode::kInvalidArgument, "durations_s",
                          "the durations make the spline system singular (too short or too long)");
      scale(i) = 1.0 / std::sqrt(d);
    }
    Eigen::SparseMatrix<double> scaled = scale.asDiagonal() * hessian * scale.asDiagonal();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    solver.compute(scaled);
    if (solver.info() != Eigen::Success)
      return make_error(ErrorCode::kInternal, "durations_s", "spline system factorisation failed");
    const Eigen::MatrixXd scaled_rhs = scale.asDiagonal() * rhs;
    const Eigen::MatrixXd solution = scale.asDiagonal() * solver.solve(scaled_rhs);
    if (solver.info() != Eigen::Success || !solution.allFinite())
      return make_error(ErrorCode::kInternal, "durations_s", "spline system solve failed");
    for (int knot = 1; knot <= knots - 2; ++knot) {
      KnotDerivatives& k = derivatives[static_cast<std::size_t>(knot)];
      for (int axis = 0; axis < 3; ++axis) {
        k.velocity_mps(axis) = solution(free_index(knot, 1), axis);
        k.acceleration_mps2(axis) = solution(free_index(knot, 2), axis);
        k.jerk_mps3(axis) = solution(free_index(knot, 3), axis);
      }
    }
  }
  return hermiteSpline(waypoints, durations_s, derivatives);
}

double snapCost(const std::vector<Segment>& segments) {
  const Matrix8& q = snapGram();
  double total = 0.0;
  for (const Segment& segment : segments) {
    for (const Polynomial7& p : segment.axes) {
      Vector8 c;
      for (int k = 0; k < 8; ++k) c(k) = p.coefficients()[static_cast<std::size_t>(k)];
      total += c.dot(q * c) / std::pow(segment.duration_s, 7);
    }
  }
  return total;
}

}  // namespace skyroute
