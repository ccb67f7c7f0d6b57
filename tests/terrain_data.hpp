// Terrain fixtures for the tests whose module links terrain/ (the trajectory tests link the core
// alone, so they cannot use these): coordinate systems for synthetic DEMs and the embedded default
// terrain.
#pragma once

#include <memory>
#include <string>

namespace skyroute {
class Heightfield;
}

namespace skyroute::testing {

// WKT of an EPSG coordinate reference system (for synthetic DEMs in tests).
std::string epsgWkt(int epsg);
// The embedded default terrain (data/default_terrain.tif) as a heightfield; null if it fails to load.
std::shared_ptr<const Heightfield> defaultTerrainHeightfield();

}  // namespace skyroute::testing
