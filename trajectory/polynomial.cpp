#include "trajectory/polynomial.hpp"

#include <cmath>

namespace skyroute {

double Polynomial7::fallingFactorial(int k, int n) {
  if (n > k) return 0.0;
  double f = 1.0;
  for (int i = 0; i < n; ++i) f *= static_cast<double>(k - i);
  return f;
}

namespace {

// kFalling[k][n] = k (k-1) ... (k-n+1), computed once: evaluation is on the hot path of the checks.
struct FallingTable {
  double value[Polynomial7::kCoefficients][Polynomial7::kCoefficients];
  constexpr FallingTable() : value{} {
    for (int k = 0; k < Polynomial7::kCoefficients; ++k)
      for (int n = 0; n < Polynomial7::kCoefficients; ++n) {
        double f = n > k ? 0.0 : 1.0;
        for (int i = 0; i < n && n <= k; ++i) f *= static_cast<double>(k - i);
        value[k][n] = f;
      }
  }
};
constexpr FallingTable kFalling;

}  // namespace

double Polynomial7::evaluateTau(double tau, int n) const {
  if (n < 0 || n > kDegree) return 0.0;
  // Horner on the differentiated coefficients.
  double value = 0.0;
  for (int k = kDegree; k >= n; --k) value = value * tau + coefficients_[k] * kFalling.value[k][n];
  return value;
}

double Polynomial7::evaluateTime(double tau, int n, double duration_s) const {
  double scale = 1.0;
  for (int i = 0; i < n; ++i) scale *= duration_s;
  return evaluateTau(tau, n) / scale;
}

void Polynomial7::evaluateTimeUpTo(double tau, int max_order, double duration_s, double* out) const {
  max_order = max_order < 0 ? 0 : (max_order > kDegree ? kDegree : max_order);
  double value[kCoefficients] = {};
  for (int k = kDegree; k >= 0; --k)
    for (int n = 0; n <= max_order && n <= k; ++n) value[n] = value[n] * tau + coefficients_[k] * kFalling.value[k][n];
  double scale = 1.0;
  for (int n = 0; n <= max_order; ++n) {
    out[n] = value[n] / scale;
    scale *= duration_s;
  }
}

}  // namespace skyroute
