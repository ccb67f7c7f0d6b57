#include "terrain/ring_simplicity.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <utility>

namespace skyroute {
namespace {

__extension__ typedef __int128 Wide;  // products of two coordinate differences (at most 8e28)

Wide cross(const RingGridPoint& p, const RingGridPoint& q, const RingGridPoint& r) {
  return static_cast<Wide>(q.x - p.x) * static_cast<Wide>(r.y - p.y) -
         static_cast<Wide>(q.y - p.y) * static_cast<Wide>(r.x - p.x);
}

// (a - b) . (c - b)
Wide dotAt(const RingGridPoint& b, const RingGridPoint& a, const RingGridPoint& c) {
  return static_cast<Wide>(a.x - b.x) * static_cast<Wide>(c.x - b.x) +
         static_cast<Wide>(a.y - b.y) * static_cast<Wide>(c.y - b.y);
}

// r lies in the bounding box of p-q (for r on the line through them: on the closed segment).
bool withinBox(const RingGridPoint& p, const RingGridPoint& q, const RingGridPoint& r) {
  return r.x >= std::min(p.x, q.x) && r.x <= std::max(p.x, q.x) && r.y >= std::min(p.y, q.y) &&
         r.y <= std::max(p.y, q.y);
}

// Two vertices at one place: found by sorting, so the sweep only ever meets distinct vertices.
std::optional<RingDefect> repeatedVertex(std::span<const RingGridPoint> ring) {
  std::vector<std::size_t> order(ring.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return ring[a] != ring[b] ? ring[a] < ring[b] : a < b;
  });
  for (std::size_t k = 1; k < order.size(); ++k) {
    if (ring[order[k - 1]] == ring[order[k]]) {
      return RingDefect{RingDefect::Kind::kRepeatedVertex, order[k - 1], order[k]};
    }
  }
  return std::nullopt;
}

// Consecutive edges a-b and b-c share b, and may meet only there: with distinct vertices they
// overlap exactly when c lies on the line through a and b, on a's side of b.
std::optional<RingDefect> foldingEdges(std::span<const RingGridPoint> ring) {
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const RingGridPoint& a = ring[i];
    const RingGridPoint& b = ring[(i + 1) % n];
    const RingGridPoint& c = ring[(i + 2) % n];
    if (cross(a, b, c) == 0 && dotAt(b, a, c) > 0) {
      return RingDefect{RingDefect::Kind::kFoldingEdges, std::min(i, (i + 1) % n), std::max(i, (i + 1) % n)};
    }
  }
  return std::nullopt;
}

// The sweep over the edges of a ring with distinct vertices and no folding edges. The line moves
// in lexicographic order of the points (x, then y), which orders vertical edges too; an edge is
// in the status from its left (lexicographically smaller) end to its right end.
class EdgeSweep {
 public:
  explicit EdgeSweep(std::span<const RingGridPoint> ring) : ring_(ring), n_(ring.size()) {
    edges_.reserve(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      const RingGridPoint& a = ring[i];
      const RingGridPoint& b = ring[(i + 1) % n_];
      edges_.push_back(a < b ? Edge{a, b} : Edge{b, a});
    }
  }

  std::optional<RingDefect> run() {
    struct Event {
      RingGridPoint at;
      bool insert;  // false sorts first: an edge that ends at a vertex leaves before the next one enters
      std::size_t edge;
    };
    std::vector<Event> events;
    events.reserve(2 * n_);
    for (std::size_t i = 0; i < n_; ++i) {
      events.push_back(Event{edges_[i].left, true, i});
      events.push_back(Event{edges_[i].right, false, i});
    }
    std::sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
      if (a.at != b.at) return a.at < b.at;
      if (a.insert != b.insert) return !a.insert;
      return a.edge < b.edge;
    });
    Status status{Below{this}};
    std::vector<Status::iterator> where(n_, status.end());
    for (const Event& event : events) {
      if (event.insert) {
        auto [it, inserted] = status.insert(event.edge);
        if (!inserted) {
          // Neither lies below the other: collinear, and the new edge's left end lies on the other.
          if (auto d = meeting(event.edge, *it, /*known=*/true)) return d;
          return RingDefect{RingDefect::Kind::kCrossingEdges, std::min(event.edge, *it), std::max(event.edge, *it)};
        }
        where[event.edge] = it;
        if (it != status.begin()) {
          if (auto d = firstNonAdjacent(event.edge, std::prev(it), status, /*up=*/false)) return d;
        }
        if (auto d = firstNonAdjacent(event.edge, std::next(it), status, /*up=*/true)) return d;
      } else {
        const auto it = where[event.edge];
        const bool has_below = it != status.begin();
        const auto below = has_below ? std::prev(it) : status.end();
        const auto above = std::next(it);
        status.erase(it);
        if (has_below && above != status.end()) {
          // The edges on either side are neighbours now.
          if (auto d = firstNonAdjacent(*below, above, status, /*up=*/true)) return d;
          if (auto d = firstNonAdjacent(*above, below, status, /*up=*/false)) return d;
        }
      }
    }
    return std::nullopt;
  }

 private:
  struct Edge {
    RingGridPoint left, right;
  };

  // Edge a lies below edge b along the sweep line, at a point of the sweep where both are in the
  // status. Exact, so the order holds as long as no two edges in the status have met.
  bool below(std::size_t a, std::size_t b) const {
    if (a == b) return false;
    const Edge& s = edges_[a];
    const Edge& t = edges_[b];
    if (s.left == t.left) return ringOrientation(s.left, s.right, t.right) > 0;
    if (s.left < t.left) {
      // t entered later, at a point above or below s (on s: they meet, and t's direction decides).
      const int o = ringOrientation(s.left, s.right, t.left);
      return o != 0 ? o > 0 : ringOrientation(s.left, s.right, t.right) > 0;
    }
    const int o = ringOrientation(t.left, t.right, s.left);
    return o != 0 ? o < 0 : ringOrientation(t.left, t.right, s.right) < 0;
  }
  struct Below {
    const EdgeSweep* sweep;
    bool operator()(std::size_t a, std::size_t b) const { return sweep->below(a, b); }
  };
  using Status = std::set<std::size_t, Below>;

  bool adjacent(std::size_t a, std::size_t b) const {
    const std::size_t d = a > b ? a - b : b - a;
    return d == 1 || d == n_ - 1;
  }

  std::optional<RingDefect> meeting(std::size_t a, std::size_t b, bool known = false) const {
    if (adjacent(a, b)) return std::nullopt;  // they share a vertex; a fold was ruled out before
    if (!known && !ringSegmentsMeet(edges_[a].left, edges_[a].right, edges_[b].left, edges_[b].right)) {
      return std::nullopt;
    }
    return RingDefect{RingDefect::Kind::kCrossingEdges, std::min(a, b), std::max(a, b)};
  }

  // Tests `edge` against the nearest edge from `from` on (upwards or downwards) that is not its
  // neighbour on the ring: an edge's ring neighbours (at most two) may lie between it and the
  // next edge it could meet.
  std::optional<RingDefect> firstNonAdjacent(std::size_t edge, Status::iterator from, const Status& status,
                                             bool up) const {
    auto it = from;
    for (int step = 0; step < 3 && it != status.end(); ++step) {
      if (!adjacent(edge, *it)) return meeting(edge, *it);
      if (up) {
        ++it;
      } else {
        if (it == status.begin()) break;
        --it;
      }
    }
    return std::nullopt;
  }

  std::span<const RingGridPoint> ring_;
  std::size_t n_;
  std::vector<Edge> edges_;
};

}  // namespace

int ringOrientation(const RingGridPoint& p, const RingGridPoint& q, const RingGridPoint& r) {
  const Wide c = cross(p, q, r);
  return c > 0 ? 1 : (c < 0 ? -1 : 0);
}

bool ringSegmentsMeet(const RingGridPoint& a1, const RingGridPoint& a2, const RingGridPoint& b1,
                      const RingGridPoint& b2) {
  const int o1 = ringOrientation(a1, a2, b1), o2 = ringOrientation(a1, a2, b2);
  const int o3 = ringOrientation(b1, b2, a1), o4 = ringOrientation(b1, b2, a2);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && withinBox(a1, a2, b1)) || (o2 == 0 && withinBox(a1, a2, b2)) ||
         (o3 == 0 && withinBox(b1, b2, a1)) || (o4 == 0 && withinBox(b1, b2, a2));
}

std::optional<std::vector<RingGridPoint>> ringOnGrid(std::span<const Eigen::Vector2d> ring_m) {
  std::vector<RingGridPoint> out;
  out.reserve(ring_m.size());
  for (const Eigen::Vector2d& v : ring_m) {
    if (!v.allFinite() || std::abs(v.x()) > kRingMaxCoordinateM || std::abs(v.y()) > kRingMaxCoordinateM) {
      return std::nullopt;
    }
    out.push_back(RingGridPoint{std::llround(v.x() / kRingGridM), std::llround(v.y() / kRingGridM)});
  }
  return out;
}

std::optional<RingDefect> findRingDefect(std::span<const RingGridPoint> ring) {
  if (ring.size() < 3) return std::nullopt;
  if (auto d = repeatedVertex(ring)) return d;
  if (auto d = foldingEdges(ring)) return d;
  return EdgeSweep(ring).run();
}

}  // namespace skyroute
