// Where tests find data: the project's data/ (always there) and ../shared/data (CI has it, a fresh
// clone may not: tests that need it call SKYROUTE_REQUIRE_SHARED and skip with a message).
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>

namespace skyroute {
class Heightfield;
}

namespace skyroute::testing {

// Absolute path of ../shared/data/<relative>, or "" when it is not there.
std::string sharedDataPath(const std::string& relative);
std::string projectDataPath(const std::string& relative);
// WKT of an EPSG coordinate reference system (for synthetic DEMs in tests).
std::string epsgWkt(int epsg);
// The embedded default terrain (data/default_terrain.tif) as a heightfield; null if it fails to load.
std::shared_ptr<const Heightfield> defaultTerrainHeightfield();

}  // namespace skyroute::testing

#define SKYROUTE_REQUIRE_SHARED(var, relative)                                                   \
  const std::string var = ::skyroute::testing::sharedDataPath(relative);                         \
  if (var.empty()) GTEST_SKIP() << "shared data " << (relative) << " not found under "          \
                                << SKYROUTE_SHARED_DATA_DIR << " (../shared/data is absent in a fresh clone)"
