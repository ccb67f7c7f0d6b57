#include "terrain/no_fly_zone.hpp"

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

std::string numberText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
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
  if (ring_m.size() < 3) return false;
  const double h = 0.5 * edge_m;
  const Eigen::AlignedBox2d square(center_m - Vec2::Constant(h), center_m + Vec2::Constant(h));
  Eigen::AlignedBox2d reach = boundsEn();
  reach.min().array() -= margin_m;
  reach.max().array() += margin_m;
  if (!reach.intersects(square)) return false;
  if (insideRing(ring_m, center_m)) return true;
  for (const Vec2& v : ring_m)
    if (square.contains(v)) return true;
  const Vec2 corners[4] = {square.corner(Eigen::AlignedBox2d::BottomLeft), square.corner(Eigen::AlignedBox2d::BottomRight),
                           square.corner(Eigen::AlignedBox2d::TopRight), square.corner(Eigen::AlignedBox2d::TopLeft)};
  for (int s = 0; s < 4; ++s) {
    for (std::size_t i = 0; i < ring_m.size(); ++i) {
      if (segmentDistance(corners[s], corners[(s + 1) % 4], ring_m[i], ring_m[(i + 1) % ring_m.size()]) <= margin_m) {
        return true;
      }
    }
  }
  return false;
}

std::optional<Error> checkNoFlyZone(const NoFlyZone& zone) {
  auto fail = [&](const std::string& what) { return make_error(ErrorCode::kInvalidArgument, zone.name, what); };
  const std::vector<Vec2>& ring = zone.ring_m;
  const std::size_t n = ring.size();
  if (n < 3) return fail("has " + std::to_string(n) + " distinct vertices; a zone needs at least 3");
  for (std::size_t i = 0; i < n; ++i) {
    if (!ring[i].allFinite()) return fail("vertex " + std::to_string(i) + " is not a finite position (NaN)");
  }
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
  for (std::size_t i = 0; i < n; ++i) {
    if (ring[i] == ring[(i + 1) % n]) {
      return fail("self-intersection: vertices " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                  " are the same point");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[(i + 1) % n];
    // The next edge shares b: it may only meet this one there, so it must not fold back onto it.
    const Vec2& c = ring[(i + 2) % n];
    if (orientation(a, b, c) == 0 && (a - b).dot(c - b) > 0.0) {
      return fail("self-intersection: edges " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
                  " overlap");
    }
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // the closing edge shares vertex 0 with edge 0
      if (segmentsMeet(a, b, ring[j], ring[(j + 1) % n])) {
        return fail("self-intersection: edges " + std::to_string(i) + " and " + std::to_string(j) + " cross");
      }
    }
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
