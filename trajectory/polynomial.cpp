#include "trajectory/polynomial.hpp"

#include <cmath>

namespace skyroute {

double Polynomial7::fallingFactorial(int k, int n) {
  if (n > k) return 0.0;
  double f = 1.0;
  for (int i = 0; i < n; ++i) f *= static_cast<double>(k - i);
  return f;
}

double Polynomial7::evaluateTau(double tau, int n) const {
  if (n < 0 || n > kDegree) return 0.0;
  // Horner on the differentiated coefficients.
  double value = 0.0;
  for (int k = kDegree; k >= n; --k) value = value * tau + coefficients_[k] * fallingFactorial(k, n);
  return value;
}

double Polynomial7::evaluateTime(double tau, int n, double duration_s) const {
  return evaluateTau(tau, n) / std::pow(duration_s, n);
}

}  // namespace skyroute
