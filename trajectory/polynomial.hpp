// One axis of one segment: x(tau) = sum_k a_k tau^k, k = 0..7, in the seed's dimensionless time
// tau = (t - t_start) / T in [0, 1] (seed 003, eqs. 5 and 6). Keeping the coefficients in tau keeps
// them of the size of the positions whatever the duration; derivatives in time divide by T^n.
#pragma once

#include <array>

#include "trajectory/derivative.hpp"

namespace skyroute {

class Polynomial7 {
 public:
  static constexpr int kDegree = 7;
  static constexpr int kCoefficients = kDegree + 1;
  using Coefficients = std::array<double, kCoefficients>;

  Polynomial7() { coefficients_.fill(0.0); }
  explicit Polynomial7(const Coefficients& coefficients_in_tau) : coefficients_(coefficients_in_tau) {}

  // n-th derivative with respect to tau at tau (any n >= 0; zero beyond the degree).
  double evaluateTau(double tau, int n) const;
  // n-th derivative with respect to time, for a segment of duration_s, at tau.
  double evaluateTime(double tau, int n, double duration_s) const;
  double evaluateTime(double tau, Derivative d, double duration_s) const {
    return evaluateTime(tau, order(d), duration_s);
  }

  // Time derivatives 0..max_order (<= 7) at tau in one pass, into out[0..max_order].
  void evaluateTimeUpTo(double tau, int max_order, double duration_s, double* out) const;

  const Coefficients& coefficients() const { return coefficients_; }

  // Falling factorial k (k-1) ... (k-n+1): the factor of tau^(k-n) in the n-th derivative of tau^k.
  static double fallingFactorial(int k, int n);

 private:
  Coefficients coefficients_;
};

}  // namespace skyroute
