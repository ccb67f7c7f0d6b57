// Piecewise degree-7 polynomials through waypoints (seed 003, section 3-1, eqs. 5-7): each segment
// passes through its two waypoints; velocity, acceleration and jerk are continuous at every interior
// waypoint; the values of those three at the interior waypoints (the remaining freedom) minimise
// the integral of squared snap over the whole curve. Ends: given velocity, acceleration and jerk
// (rest to rest by default).
//
// Why this formulation: the snap integral of a degree-7 segment is a quadratic form in its end
// derivatives (Hermite form), so the optimum is one sparse symmetric positive definite system in
// 3 (M - 1) unknowns per axis, block tridiagonal, shared by the three axes (one factorisation).
// The optimum is in fact continuous up to the 6th derivative (the Euler-Lagrange conditions), which
// the tests use as an independent check of the solve.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "trajectory/segment.hpp"

namespace skyroute {

struct EndpointDerivatives {
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d jerk_mps3 = Eigen::Vector3d::Zero();
};

struct SplineBoundary {
  EndpointDerivatives start;  // rest by default
  EndpointDerivatives end;    // rest by default
};

// Derivatives (velocity, acceleration, jerk) at one waypoint; the position is the waypoint.
struct KnotDerivatives {
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d jerk_mps3 = Eigen::Vector3d::Zero();
};

// waypoints: M + 1 points (ENU m); durations_s: M positive finite durations.
// Errors (kInvalidArgument) name the field: "waypoints", "waypoints[i]", "durations_s[i]",
// "boundary.start.velocity_mps", ...
Result<std::vector<Segment>> solveMinimumSnapSpline(const std::vector<Eigen::Vector3d>& waypoints,
                                                    const std::vector<double>& durations_s,
                                                    const SplineBoundary& boundary = {});

// The same curve family with every waypoint's derivatives given (M + 1 of them): the Hermite
// segments. Used to build alternatives to compare the optimum with, and by the solver itself.
Result<std::vector<Segment>> hermiteSpline(const std::vector<Eigen::Vector3d>& waypoints,
                                           const std::vector<double>& durations_s,
                                           const std::vector<KnotDerivatives>& knots);

// Integral over time of |snap|^2 (m^2/s^7), exact from the coefficients.
double snapCost(const std::vector<Segment>& segments);

}  // namespace skyroute
