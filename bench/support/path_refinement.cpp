#include "bench/support/path_refinement.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"

namespace skyroute {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A change must shorten the path by more than this to count (rounding noise is not progress).
constexpr double kMinChangeGain_m = 1e-9;

// Per-vertex state: whether a relaxation is worth trying (not yet, or something nearby changed
// since every move failed) and the next corner-cut depth to try (infinite until the first try,
// then the last successful depth or the failed one halved).
struct VertexState {
  bool relax_due = true;
  double cut_step_m = kInf;
  bool collapse_due = true;  // the neighbours changed since the last collapse test
};

// splitmix64: a fixed, platform-independent sequence for the partial shortcuts.
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  double uniform() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

class Refiner {
 public:
  Refiner(const MotionValidator& validator, const PathRefinementOptions& options, const TerminationCondition& stop,
          PathRefinementResult& result, std::vector<Eigen::Vector3d> path)
      : validator_(validator), options_(options), stop_(stop), result_(result), path_(std::move(path)),
        states_(path_.size()), rng_(options.seed) {}

  void run() {
    double length = polylineLength(path_);
    for (int round = 0; round < options_.max_rounds && !stopped_; ++round) {
      for (std::size_t i = 1; i + 1 < path_.size() && !stopped_; ++i) {
        if (options_.collapse && tryCollapse(i)) {
          --i;  // the vertex now at i has new neighbours; the loop revisits it
          continue;
        }
        if (options_.relax) tryRelax(i);
        if (options_.cut_corners && tryCut(i)) ++i;  // skip the second cut point, new this round
      }
      for (int k = 0; k < options_.shortcut_attempts && !stopped_; ++k) tryShortcut();
      ++result_.rounds;
      const double next = polylineLength(path_);
      const double gain = length - next;
      length = next;
      if (gain < options_.min_round_gain_m) break;
    }
    result_.stopped_early = stopped_;
  }

  std::vector<Eigen::Vector3d>& path() { return path_; }

 private:
  bool check(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    if (stopped_) return false;
    if (stop_.shouldStop()) {
      stopped_ = true;
      return false;
    }
    ++result_.motion_checks;
    return validator_.isMotionValid(a, b);
  }

  // Vertex i or its segments changed by about moved_m: its neighbours may move or collapse again,
  // the corner cut starting its line search no smaller than the change.
  void touch(std::size_t i, double moved_m) {
    for (std::size_t j = i == 0 ? 0 : i - 1; j <= i + 1 && j < states_.size(); ++j) {
      states_[j].collapse_due = true;
      states_[j].relax_due = true;
      states_[j].cut_step_m = std::max(states_[j].cut_step_m, moved_m);
    }
  }

  bool tryCollapse(std::size_t i) {
    if (!states_[i].collapse_due) return false;
    states_[i].collapse_due = false;
    const Eigen::Vector3d a = path_[i - 1], v = path_[i], b = path_[i + 1];
    if (!check(a, b)) return false;
    const Eigen::Vector3d ab = b - a;
    const double t = ab.squaredNorm() > 0.0 ? std::clamp((v - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    const double moved = (a + t * ab - v).norm();
    path_.erase(path_.begin() + static_cast<std::ptrdiff_t>(i));
    states_.erase(states_.begin() + static_cast<std::ptrdiff_t>(i));
    touch(i - 1, moved);
    ++result_.collapsed;
    return true;
  }

  // Line search towards the closest point of the neighbours' segment: the first valid step,
  // halving from the vertex's current step down to min_step_m. When that is blocked (the vertex
  // presses on an obstacle on the way to the segment), slide the vertex along one of its own
  // segments instead (the part of that segment stays valid, only the other one needs a check,
  // and the triangle inequality makes it shorter), or move it along the horizontal or the
  // vertical part of the steepest descent. Those are how a corner moves along an edge or a ridge
  // to where the taut path touches it. Every move is kept only when it is strictly shorter.
  void tryRelax(std::size_t i) {
    if (!states_[i].relax_due) return;
    states_[i].relax_due = false;
    const Eigen::Vector3d a = path_[i - 1], v = path_[i], b = path_[i + 1];
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((v - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector3d to_line = a + t * ab - v;
    const double before = (a - v).norm() + (b - v).norm();
    // Steepest descent of |a - v| + |v - b|; its horizontal and vertical parts are descent
    // directions too, and one of them often runs along what blocks the others (a vertical edge, a
    // ridge line, the ceiling).
    const Eigen::Vector3d descent = (a - v).normalized() + (b - v).normalized();
    const double near_m = 0.5 * std::min((a - v).norm(), (b - v).norm());
    // Direction, how far it may go, and which new segments need a check.
    const struct {
      Eigen::Vector3d direction;
      double reach_m;
      bool check_a, check_b;
    } moves[] = {{to_line, to_line.norm(), true, true},
                 {a - v, 0.5 * (a - v).norm(), false, true},
                 {b - v, 0.5 * (b - v).norm(), true, false},
                 {Eigen::Vector3d(descent.x(), descent.y(), 0.0), near_m, true, true},
                 {Eigen::Vector3d(0.0, 0.0, descent.z()), near_m, true, true}};
    for (const auto& m : moves) {
      if (!(m.reach_m > 0.0)) continue;
      const Eigen::Vector3d unit = m.direction.normalized();
      double step = m.reach_m;
      while (step >= options_.min_step_m && !stopped_) {
        const Eigen::Vector3d moved = v + unit * step;
        if ((a - moved).norm() + (b - moved).norm() < before - kMinChangeGain_m && (!m.check_a || check(a, moved)) &&
            (!m.check_b || check(moved, b))) {
          path_[i] = moved;
          touch(i, step);  // also makes this vertex due again
          ++result_.relaxed;
          return;
        }
        step *= 0.5;
      }
    }
  }

  // Line search on the cut depth: replace v by p on v -> a and q on v -> b, at the same distance c
  // from v (at most half of either segment so cuts of neighbouring corners never cross).
  bool tryCut(std::size_t i) {
    if (static_cast<int>(path_.size()) >= options_.max_vertices) return false;
    const Eigen::Vector3d a = path_[i - 1], v = path_[i], b = path_[i + 1];
    const double la = (a - v).norm(), lb = (b - v).norm();
    if (la <= 0.0 || lb <= 0.0) return false;
    double c = std::min({states_[i].cut_step_m, 0.5 * la, 0.5 * lb});
    const double smallest = std::max(options_.min_step_m, options_.min_segment_m);
    while (c >= smallest && !stopped_) {
      const Eigen::Vector3d p = v + (a - v) * (c / la);
      const Eigen::Vector3d q = v + (b - v) * (c / lb);
      if ((p - q).norm() >= 2.0 * c - kMinChangeGain_m) return false;  // straight on: nothing to cut
      if ((p - q).norm() < options_.min_segment_m) break;  // sharper corners only get shorter chords
      if (check(p, q)) {
        path_[i] = p;
        path_.insert(path_.begin() + static_cast<std::ptrdiff_t>(i) + 1, q);
        const VertexState fresh{true, c, true};
        states_[i] = fresh;
        states_.insert(states_.begin() + static_cast<std::ptrdiff_t>(i) + 1, fresh);
        touch(i, c);
        touch(i + 1, c);
        ++result_.cut;
        return true;
      }
      c *= 0.5;
    }
    states_[i].cut_step_m = c;
    return false;
  }

  // OMPL-style partial shortcut between two seeded points along the path, in different segments.
  // A midpoint check rejects most blocked long candidates before the motion check.
  void tryShortcut() {
    std::vector<double> along(path_.size(), 0.0);
    for (std::size_t i = 1; i < path_.size(); ++i) along[i] = along[i - 1] + (path_[i] - path_[i - 1]).norm();
    double u1 = along.back() * rng_.uniform(), u2 = along.back() * rng_.uniform();
    if (u1 > u2) std::swap(u1, u2);
    auto segment = [&](double u) {
      const auto it = std::upper_bound(along.begin(), along.end(), u);
      return std::min<std::size_t>(static_cast<std::size_t>(it - along.begin()) - 1, path_.size() - 2);
    };
    const std::size_t s1 = segment(u1), s2 = segment(u2);
    if (s1 >= s2) return;
    if (static_cast<int>(path_.size()) + 2 - static_cast<int>(s2 - s1) > options_.max_vertices) return;
    auto at = [&](std::size_t s, double u) {
      const double len = along[s + 1] - along[s];
      return Eigen::Vector3d(len > 0.0 ? path_[s] + (path_[s + 1] - path_[s]) * ((u - along[s]) / len) : path_[s]);
    };
    const Eigen::Vector3d p1 = at(s1, u1), p2 = at(s2, u2);
    if ((p2 - p1).norm() >= u2 - u1 - kMinChangeGain_m) return;
    if (options_.min_segment_m > 0.0) {
      const double shortest = std::min({(p2 - p1).norm(), u1 - along[s1], along[s2 + 1] - u2});
      if (shortest < options_.min_segment_m) return;
    }
    if (!validator_.isStateValid(0.5 * (p1 + p2))) return;
    if (!check(p1, p2)) return;
    std::vector<Eigen::Vector3d> next(path_.begin(), path_.begin() + static_cast<std::ptrdiff_t>(s1) + 1);
    std::vector<VertexState> next_states(states_.begin(), states_.begin() + static_cast<std::ptrdiff_t>(s1) + 1);
    if ((p1 - next.back()).norm() > 0.0) {
      next.push_back(p1);
      next_states.emplace_back();
    }
    if ((p2 - path_[s2 + 1]).norm() > 0.0) {
      next.push_back(p2);
      next_states.emplace_back();
    }
    const std::size_t joined = next.size() - 1;
    next.insert(next.end(), path_.begin() + static_cast<std::ptrdiff_t>(s2) + 1, path_.end());
    next_states.insert(next_states.end(), states_.begin() + static_cast<std::ptrdiff_t>(s2) + 1, states_.end());
    path_ = std::move(next);
    states_ = std::move(next_states);
    touch(joined, (u2 - u1) - (p2 - p1).norm());
    if (joined + 1 < states_.size()) touch(joined + 1, (u2 - u1) - (p2 - p1).norm());
    ++result_.shortcuts;
  }

  const MotionValidator& validator_;
  const PathRefinementOptions& options_;
  const TerminationCondition& stop_;
  PathRefinementResult& result_;
  std::vector<Eigen::Vector3d> path_;
  std::vector<VertexState> states_;
  SplitMix rng_;
  bool stopped_ = false;
};

}  // namespace

Result<PathRefinementResult> refinePath(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path_m,
                                        const PathRefinementOptions& options, const TerminationCondition& stop) {
  const auto t0 = Clock::now();
  if (Status points = checkPathPoints(path_m); !points.ok()) return points.error();
  if (options.max_rounds < 0) return make_error(ErrorCode::kInvalidArgument, "max_rounds", "max_rounds must be >= 0");
  if (!std::isfinite(options.min_step_m) || !(options.min_step_m > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "min_step_m", "min_step_m must be finite and > 0");
  }
  if (!(options.min_round_gain_m >= 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "min_round_gain_m", "min_round_gain_m must be >= 0");
  }
  if (!(options.min_segment_m >= 0.0) || !std::isfinite(options.min_segment_m)) {
    return make_error(ErrorCode::kInvalidArgument, "min_segment_m", "min_segment_m must be finite and >= 0");
  }
  if (options.shortcut_attempts < 0) {
    return make_error(ErrorCode::kInvalidArgument, "shortcut_attempts", "shortcut_attempts must be >= 0");
  }
  PathRefinementResult result;
  result.input_length_m = polylineLength(path_m);
  if (options.check_input) {
    for (std::size_t i = 1; i < path_m.size(); ++i) {
      ++result.motion_checks;
      if (!validator.isMotionValid(path_m[i - 1], path_m[i])) {
        return make_error(ErrorCode::kInvalidArgument, "path",
                          "segment " + std::to_string(i - 1) + " -> " + std::to_string(i) + " is not a valid motion");
      }
    }
  }
  Refiner refiner(validator, options, stop, result, path_m);
  refiner.run();
  std::vector<Eigen::Vector3d>& refined = refiner.path();
  // Cut points lie on checked segments up to rounding: verify every segment of the result that is
  // not an input segment once (whatever the deadline says) and keep the result only when it is
  // valid and not longer.
  std::map<std::array<double, 3>, std::size_t> input_index;
  for (std::size_t i = 0; i < path_m.size(); ++i) input_index.emplace(std::array{path_m[i].x(), path_m[i].y(), path_m[i].z()}, i);
  auto isInputSegment = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
    const auto it = input_index.find({u.x(), u.y(), u.z()});
    return it != input_index.end() && it->second + 1 < path_m.size() && path_m[it->second + 1] == w;
  };
  bool keep = refined != path_m;
  const double length = polylineLength(refined);
  keep = keep && length <= result.input_length_m;
  for (std::size_t i = 1; keep && i < refined.size(); ++i) {
    if (isInputSegment(refined[i - 1], refined[i])) continue;
    ++result.motion_checks;
    keep = validator.isMotionValid(refined[i - 1], refined[i]);
  }
  result.path_m = keep ? std::move(refined) : path_m;
  result.length_m = keep ? length : result.input_length_m;
  result.time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

}  // namespace skyroute
