#include "terrain/no_fly_zone.hpp"

#include "terrain/ring_simplicity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace skyroute {
namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Which side of the line p -> q the point r lies on: +1 left, -1 right, 0 on it.
int orientation(const Vec2& p, const Vec2& q, const Vec2& r) {
  const double c = cross(q - p, r - p);
  return c > 0.0 ? 1 : (c < 0.0 ? -1 : 0);
}

// r is on the closed segment p-q, given that the three are collinear.
bool withinBox(const Vec2& p, const Vec2& q, const Vec2& r) {
  return r.x() >= std::min(p.x(), q.x()) && r.x() <= std::max(p.x(), q.x()) && r.y() >= std::min(p.y(), q.y()) &&
         r.y() <= std::max(p.y(), q.y());
}

// The closed segments p1-p2 and q1-q2 share a point.
bool segmentsMeet(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  const int o1 = orientation(p1, p2, q1), o2 = orientation(p1, p2, q2);
  const int o3 = orientation(q1, q2, p1), o4 = orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4) return true;
  return (o1 == 0 && withinBox(p1, p2, q1)) || (o2 == 0 && withinBox(p1, p2, q2)) ||
         (o3 == 0 && withinBox(q1, q2, p1)) || (o4 == 0 && withinBox(q1, q2, p2));
}

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double segmentDistance(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  if (segmentsMeet(p1, p2, q1, q2)) return 0.0;
  return std::min({pointSegmentDistance(p1, q1, q2), pointSegmentDistance(p2, q1, q2), pointSegmentDistance(q1, p1, p2),
                   pointSegmentDistance(q2, p1, p2)});
}

// Even-odd rule: a ray to the east crosses the ring an odd number of times.
bool insideRing(const std::vector<Vec2>& ring, const Vec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

// The 2D segment p-q lies within margin_m of the polygon (or inside it).
bool segmentNearRing(const std::vector<Vec2>& ring, const Vec2& p, const Vec2& q, double margin_m) {
  if (insideRing(ring, p)) return true;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    if (segmentDistance(p, q, ring[i], ring[(i + 1) % ring.size()]) <= margin_m) return true;
  }
  return false;
}

std::string numberText(double v, int digits = 10) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace

bool NoFlyZone::activeAt(double t_s) const {
  return (!valid_from_s || t_s >= *valid_from_s) && (!valid_until_s || t_s < *valid_until_s);
}

bool NoFlyZone::activeDuring(double t0_s, double t1_s) const {
  return (!valid_from_s || t1_s >= *valid_from_s) && (!valid_until_s || t0_s < *valid_until_s);
}

Eigen::AlignedBox2d NoFlyZone::boundsEn() const {
  Eigen::AlignedBox2d box;
  for (const Vec2& v : ring_m) box.extend(v);
  return box;
}

bool NoFlyZone::touchesPoint(const Eigen::Vector3d& p_m, double margin_m) const {
  return touchesSegment(p_m, p_m, margin_m);
}

bool NoFlyZone::touchesSegment(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m, double margin_m) const {
  if (ring_m.size() < 3) return false;
  // Clip the segment to the slab between the grown floor and ceiling.
  const double lo = floor_m - margin_m, hi = ceiling_m + margin_m;
  const double dz = b_m.z() - a_m.z();
  double t0 = 0.0, t1 = 1.0;
  if (dz == 0.0) {
    if (!(a_m.z() >= lo && a_m.z() <= hi)) return false;
  } else {
    double enter = (lo - a_m.z()) / dz, leave = (hi - a_m.z()) / dz;
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (!(t0 <= t1)) return false;
  }
  const Vec2 p = a_m.head<2>() + t0 * (b_m - a_m).head<2>();
  const Vec2 q = a_m.head<2>() + t1 * (b_m - a_m).head<2>();
  Eigen::AlignedBox2d reach = boundsEn();
  reach.min().array() -= margin_m;
  reach.max().array() += margin_m;
  Eigen::AlignedBox2d span(p.cwiseMin(q), p.cwiseMax(q));
  if (!reach.intersects(span)) return false;
  return segmentNearRing(ring_m, p, q, margin_m);
}

bool NoFlyZone::touchesSquare(const Eigen::Vector2d& center_m, double edge_m, double margin_m) const {
  const Vec2 half = Vec2::Constant(0.5 * edge_m);
  return touchesRectangle(Eigen::AlignedBox2d(center_m - half, center_m + half), margin_m);
}

bool NoFlyZone::touchesRectangle(const Eigen::AlignedBox2d& box_m, double margin_m) const {
  if (ring_m.size() < 3 || box_m.isEmpty()) return false;
  Eigen::AlignedBox2d reach = boundsEn();
  reach.min().array() -= margin_m;
  reach.max().array() += margin_m;
  if (!reach.intersects(box_m)) return false;
  if (insideRing(ring_m, box_m.center())) return true;
  for (const Vec2& v : ring_m)
    if (box_m.contains(v)) return true;
  const Vec2 corners[4] = {box_m.corner(Eigen::AlignedBox2d::BottomLeft), box_m.corner(Eigen::AlignedBox2d::BottomRight),
                           box_m.corner(Eigen::AlignedBox2d::TopRight), box_m.corner(Eigen::AlignedBox2d::TopLeft)};
  for (int s = 0; s < 4; ++s) {
    for (std::size_t i = 0; i < ring_m.size(); ++i) {
      if (segmentDistance(corners[s], corners[(s + 1) % 4], ring_m[i], ring_m[(i + 1) % ring_m.size()]) <= margin_m) {
        return true;
      }
    }
  }
  return false;
}

std::optional<Error> checkNoFlyRing(const std::vector<Vec2>& ring) {
  auto fail = [](const std::string& what) { return make_error(ErrorCode::kInvalidArgument, "ring", what); };
  const std::size_t n = ring.size();
  // First, before any work that grows with the ring.
  if (n > kMaxNoFlyZoneVertices) {
    return fail("ring has " + std::to_string(n) + " vertices, more than the " + std::to_string(kMaxNoFlyZoneVertices) +
                " a zone may have");
  }
  if (n < 3) return fail("has " + std::to_string(n) + " distinct vertices; a zone needs at least 3");
  for (std::size_t i = 0; i < n; ++i) {
    if (!ring[i].allFinite()) return fail("vertex " + std::to_string(i) + " is not a finite position (NaN)");
  }
  const auto on_grid = ringOnGrid(ring);
  if (!on_grid) {
    return fail("a vertex lies more than " + numberText(kRingMaxCoordinateM) +
                " m from the frame's origin: not a place on Earth");
  }
  if (const auto defect = findRingDefect(*on_grid)) {
    const std::string i = std::to_string(defect->first), j = std::to_string(defect->second);
    switch (defect->kind) {
      case RingDefect::Kind::kRepeatedVertex:
        return fail("self-intersection: vertices " + i + " and " + j + " are the same point");
      case RingDefect::Kind::kFoldingEdges:
        return fail("self-intersection: edges " + i + " and " + j + " overlap");
      case RingDefect::Kind::kCrossingEdges: {
        // Crossing through each other, or touching (an end on the other edge, or overlapping).
        const auto& g = *on_grid;
        const RingGridPoint &a1 = g[defect->first], &a2 = g[(defect->first + 1) % n];
        const RingGridPoint &b1 = g[defect->second], &b2 = g[(defect->second + 1) % n];
        const bool through = ringOrientation(a1, a2, b1) * ringOrientation(a1, a2, b2) < 0 &&
                             ringOrientation(b1, b2, a1) * ringOrientation(b1, b2, a2) < 0;
        return fail("self-intersection: edges " + i + " and " + j + (through ? " cross" : " touch"));
      }
    }
  }
  // A simple ring: the shoelace formula is its area (relative to vertex 0, for precision).
  double twice_area_m2 = 0.0, perimeter_m = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = ring[k] - ring[0];
    const Vec2 b = ring[(k + 1) % n] - ring[0];
    twice_area_m2 += cross(a, b);
    perimeter_m += (b - a).norm();
  }
  const double area_m2 = 0.5 * std::abs(twice_area_m2);
  const double mean_width_m = 2.0 * area_m2 / perimeter_m;
  if (area_m2 < kMinNoFlyZoneAreaM2 || mean_width_m < kMinNoFlyZoneMeanWidthM) {
    return fail("has (nearly) zero area: its vertices lie (nearly) on one line (area " + numberText(area_m2, 3) +
                " m², mean width 2 area / perimeter " + numberText(mean_width_m, 3) + " m; a zone needs at least " +
                numberText(kMinNoFlyZoneAreaM2) + " m² and " + numberText(kMinNoFlyZoneMeanWidthM) + " m)");
  }
  return std::nullopt;
}

std::optional<Error> checkNoFlyZone(const NoFlyZone& zone) {
  if (auto bad = checkNoFlyRing(zone.ring_m)) {
    bad->field = zone.name;
    return bad;
  }
  auto fail = [&](const std::string& what) { return make_error(ErrorCode::kInvalidArgument, zone.name, what); };
  if (!std::isfinite(zone.floor_m)) return fail("floor_m is not a finite number (NaN)");
  if (!std::isfinite(zone.ceiling_m)) return fail("ceiling_m is not a finite number (NaN)");
  if ((zone.valid_from_s && !std::isfinite(*zone.valid_from_s)) ||
      (zone.valid_until_s && !std::isfinite(*zone.valid_until_s))) {
    return fail("its validity window is not finite (NaN)");
  }
  if (zone.floor_m > zone.ceiling_m) {
    return fail("floor_m " + numberText(zone.floor_m) + " is above ceiling_m " + numberText(zone.ceiling_m));
  }
  if (zone.valid_from_s && zone.valid_until_s && !(*zone.valid_from_s < *zone.valid_until_s)) {
    return fail("valid_from is not before valid_until");
  }
  return std::nullopt;
}

namespace {

bool inForce(const NoFlyZone& zone, std::optional<double> t_s, double window_s) {
  if (!t_s) return true;
  return window_s > 0.0 ? zone.activeDuring(*t_s, *t_s + window_s) : zone.activeAt(*t_s);
}

}  // namespace

const NoFlyZone* zoneTouchingPoint(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& p_m, double margin_m,
                                   std::optional<double> t_s, double window_s) {
  for (const NoFlyZone& zone : zones) {
    if (inForce(zone, t_s, window_s) && zone.touchesPoint(p_m, margin_m)) return &zone;
  }
  return nullptr;
}

const NoFlyZone* zoneTouchingSegment(const std::vector<NoFlyZone>& zones, const Eigen::Vector3d& a_m,
                                     const Eigen::Vector3d& b_m, double margin_m, std::optional<double> t_s,
                                     double window_s) {
  for (const NoFlyZone& zone : zones) {
    if (inForce(zone, t_s, window_s) && zone.touchesSegment(a_m, b_m, margin_m)) return &zone;
  }
  return nullptr;
}

}  // namespace skyroute
