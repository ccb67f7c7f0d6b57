// Fuzzes the no-fly zones of a GeoJSON file (`skyroute plan --nofly`, `skyroute nofly`,
// `terrain.nofly`) and the check of their rings. First byte even: the rest is the file, read into
// the embedded terrain's frame; every zone it accepts must keep the bounds (at most
// kMaxNoFlyZoneVertices vertices, at least 3) and pass the zone check again, and is then tested as
// the planners test zones (a point, a segment, a grid cell). First byte odd: the rest builds a ring
// of up to 64 vertices on a small integer grid, near or far from the origin, and the sweep-line
// check (terrain/ring_simplicity.hpp) must give the verdict of the quadratic check of every pair of
// edges, and name a real defect.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "service/no_fly_geojson.hpp"
#include "terrain/local_frame.hpp"
#include "terrain/no_fly_zone.hpp"
#include "terrain/ring_simplicity.hpp"
#include "tests/fuzz/fuzz_bytes.hpp"
#include "tests/terrain/ring_by_every_pair.hpp"

namespace {

using namespace skyroute;

void zonesOfAFile(const std::uint8_t* data, std::size_t size) {
  // The embedded terrain's centre (data/default_terrain.tif), as the CLI anchors its frame.
  static const LocalFrame frame = LocalFrame::create(46.94, 15.08, 0.0).value();
  auto zones = parseNoFlyGeoJson(std::string(reinterpret_cast<const char*>(data), size), frame);
  if (!zones.ok()) return;
  for (const NoFlyZone& zone : *zones) {
    if (zone.ring_m.size() < 3 || zone.ring_m.size() > kMaxNoFlyZoneVertices) std::abort();
    if (checkNoFlyZone(zone)) std::abort();  // accepted once, accepted again
    const Eigen::Vector2d c = zone.boundsEn().center();
    (void)zone.touchesPoint(Eigen::Vector3d(c.x(), c.y(), zone.floor_m), 5.0);
    (void)zone.touchesSegment(Eigen::Vector3d(c.x() - 100.0, c.y(), 0.0), Eigen::Vector3d(c.x() + 100.0, c.y(), 0.0), 5.0);
    (void)zone.touchesSquare(c, 25.0, 5.0);
  }
}

void ringAgainstEveryPair(const std::uint8_t* data, std::size_t size) {
  fuzz::FuzzBytes bytes(data, size);
  // Far rings stress the orientations of nearly collinear points; the grid stays small so that
  // vertices repeat, touch and line up.
  const bool far = bytes.flag();
  const std::int64_t offset = far ? 10'000'000'000'000 : 0;
  const std::int64_t step = far ? 1'000'003 : 1;
  const std::size_t n = 3 + bytes.byte() % 62;
  std::vector<RingGridPoint> ring;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t b = bytes.byte();
    const std::int64_t jitter = far ? static_cast<std::int64_t>(bytes.byte() % 5) - 2 : 0;
    ring.push_back(RingGridPoint{offset + (b & 0x0f) * step + jitter, offset + (b >> 4) * step - jitter});
  }
  const auto defect = findRingDefect(ring);
  if (defect.has_value() == testing::simpleByEveryPair(ring)) std::abort();
  if (!defect) return;
  if (!(defect->first < defect->second && defect->second < n)) std::abort();
  if (defect->kind == RingDefect::Kind::kRepeatedVertex && !(ring[defect->first] == ring[defect->second])) std::abort();
  if (defect->kind == RingDefect::Kind::kCrossingEdges &&
      !ringSegmentsMeet(ring[defect->first], ring[(defect->first + 1) % n], ring[defect->second],
                        ring[(defect->second + 1) % n])) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  if (data[0] % 2 == 0) {
    zonesOfAFile(data + 1, size - 1);
  } else {
    ringAgainstEveryPair(data + 1, size - 1);
  }
  return 0;
}
