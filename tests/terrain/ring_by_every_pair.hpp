// The quadratic check of a ring's simplicity the no-fly zones made before the sweep line
// (terrain/ring_simplicity.hpp), kept as the reference the sweep is compared with
// (ring_simplicity_test, the no_fly_zone fuzz harness): every pair of edges, with the same exact
// predicates.
#pragma once

#include <cstddef>
#include <vector>

#include "terrain/ring_simplicity.hpp"

namespace skyroute::testing {

// The check the zones made before the sweep (terrain/no_fly_zone.cpp until then): a repeated
// consecutive vertex, consecutive edges folding back, then every pair of edges that are not
// consecutive. O(n^2).
inline bool simpleByEveryPair(const std::vector<RingGridPoint>& ring) {
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (ring[i] == ring[(i + 1) % n]) return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RingGridPoint& a = ring[i];
    const RingGridPoint& b = ring[(i + 1) % n];
    const RingGridPoint& c = ring[(i + 2) % n];
    const double dot = static_cast<double>(a.x - b.x) * static_cast<double>(c.x - b.x) +
                       static_cast<double>(a.y - b.y) * static_cast<double>(c.y - b.y);
    if (ringOrientation(a, b, c) == 0 && dot > 0.0) return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // the closing edge shares vertex 0 with edge 0
      if (ringSegmentsMeet(a, b, ring[j], ring[(j + 1) % n])) return false;
    }
  }
  return true;
}

}  // namespace skyroute::testing
