// Helpers the HAB-PP files share that are not part of the planner's interface (hab_pp.hpp).
#pragma once

#include <cmath>

#include "planning/colony/hab_pp.hpp"

namespace skyroute::habpp {

// x^e for the exponents of eq. (1): the paper's 2, 1 and 1 need no std::pow, which otherwise
// dominates the ants' innermost loop.
inline double powExponent(double x, double e) {
  if (e == 1.0) return x;
  if (e == 2.0) return x * x;
  if (e == 0.0) return 1.0;
  return std::pow(x, e);
}

// tightenPath after its greedy pruning, for paths that are already pruned (prunePath is
// idempotent: after a pass no kept point sees a later one beyond its successor), such as the
// crossover's children.
Path relaxPruned(const GridLayer& grid, Path p, int max_passes);

}  // namespace skyroute::habpp
