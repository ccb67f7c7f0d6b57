#include "planning/sampling/lospo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "planning/core/polyline.hpp"

namespace skyroute {

namespace {

using Clock = std::chrono::steady_clock;

// Vertices strictly between a and b, at most spacing apart (equal pieces), in order from a.
void appendInterior(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double spacing, std::vector<Eigen::Vector3d>& out) {
  const double length = (b - a).norm();
  const auto pieces = static_cast<long>(std::ceil(length / spacing - 1e-9));
  for (long k = 1; k < pieces; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / static_cast<double>(pieces)));
}

struct PassResult {
  std::vector<Eigen::Vector3d> path;
  bool stopped = false;
};

// Whether a -> b is a valid motion, rejecting cheaply first: a valid motion has every point on
// it valid (the MotionValidator contract), so an invalid point at the middle or a quarter of the
// way proves the motion invalid with a point check (a fraction of a swept-segment check on a
// long segment). The answer is exactly isMotionValid's; only its cost changes. Most of LOSPO's
// tests are far vertices hidden behind terrain, which these points usually catch.
bool visible(const MotionValidator& validator, const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool prefilter,
             std::uint64_t& checks, std::uint64_t& point_checks) {
  if (prefilter) {
    for (double f : {0.5, 0.25, 0.75}) {
      ++point_checks;
      if (!validator.isStateValid(a + f * (b - a))) return false;
    }
  }
  ++checks;
  return validator.isMotionValid(a, b);
}

// One LOSPO pass as seed 003 section 2-3 describes it.
PassResult lospoPass(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path, double spacing,
                     bool prefilter, const TerminationCondition& stop, std::uint64_t& checks,
                     std::uint64_t& point_checks) {
  const std::vector<Eigen::Vector3d> dense = densifyPath(path, spacing);
  // `done` holds the fixed vertices (the last one is the current vertex); `ahead` the rest of the
  // path in reverse order, so ahead.front() is the goal and ahead.back() the next vertex.
  std::vector<Eigen::Vector3d> done{dense.front()};
  std::vector<Eigen::Vector3d> ahead(dense.rbegin(), dense.rend() - 1);
  std::vector<Eigen::Vector3d> inserted;
  while (!ahead.empty()) {
    if (stop.shouldStop()) {
      done.insert(done.end(), ahead.rbegin(), ahead.rend());
      return {std::move(done), true};
    }
    const Eigen::Vector3d current = done.back();
    // Farthest visible vertex, testing from the goal backwards. The next vertex lies on the
    // current (valid) path, so it is visible without a test.
    std::size_t farthest = ahead.size() - 1;
    for (std::size_t k = 0; k + 1 < ahead.size(); ++k) {
      if (visible(validator, current, ahead[k], prefilter, checks, point_checks)) {
        farthest = k;
        break;
      }
    }
    if (farthest == 0) {  // the goal is visible: connect and stop
      done.push_back(ahead.front());
      break;
    }
    // Connect current -> ahead[farthest], dropping the vertices in between, and re-insert vertices
    // along the new segment; then move on to the next vertex.
    const Eigen::Vector3d target = ahead[farthest];
    ahead.resize(farthest + 1);
    inserted.clear();
    appendInterior(current, target, spacing, inserted);
    ahead.insert(ahead.end(), inserted.rbegin(), inserted.rend());
    done.push_back(ahead.back());
    ahead.pop_back();
  }
  return {std::move(done), false};
}

// Drops vertices where the path goes straight on (within 1e-6 m of the line through its
// neighbours), keeping a merge only when the merged segment is a valid motion.
std::vector<Eigen::Vector3d> mergeCollinear(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path,
                                            std::uint64_t& checks) {
  if (path.size() < 3) return path;
  std::vector<Eigen::Vector3d> out{path.front()};
  std::size_t i = 0;  // index in path of out.back()
  while (i + 1 < path.size()) {
    std::size_t j = i + 1;
    // Extend j while every vertex between i and j + 1 lies on the segment path[i] -> path[j + 1].
    while (j + 1 < path.size()) {
      const Eigen::Vector3d a = path[i];
      const Eigen::Vector3d c = path[j + 1];
      const Eigen::Vector3d ac = c - a;
      const double len2 = ac.squaredNorm();
      bool straight = len2 > 0.0;
      for (std::size_t m = i + 1; m <= j && straight; ++m) {
        const double t = (path[m] - a).dot(ac) / len2;
        straight = t > 0.0 && t < 1.0 && (a + t * ac - path[m]).norm() < 1e-6;
      }
      if (!straight) break;
      ++j;
    }
    if (j > i + 1) {
      ++checks;
      if (!validator.isMotionValid(path[i], path[j])) j = i + 1;
    }
    out.push_back(path[j]);
    i = j;
  }
  return out;
}

bool allMotionsValid(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path, std::uint64_t& checks) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    ++checks;
    if (!validator.isMotionValid(path[i - 1], path[i])) return false;
  }
  return true;
}

}  // namespace

std::vector<Eigen::Vector3d> densifyPath(const std::vector<Eigen::Vector3d>& path_m, double spacing_m) {
  std::vector<Eigen::Vector3d> out;
  if (path_m.empty()) return out;
  out.push_back(path_m.front());
  for (std::size_t i = 1; i < path_m.size(); ++i) {
    appendInterior(path_m[i - 1], path_m[i], spacing_m, out);
    out.push_back(path_m[i]);
  }
  return out;
}

Status checkPathPoints(const std::vector<Eigen::Vector3d>& path_m) {
  if (path_m.size() < 2) return make_error(ErrorCode::kInvalidArgument, "path", "a path needs at least two points");
  for (std::size_t i = 0; i < path_m.size(); ++i) {
    if (!path_m[i].allFinite()) {
      return make_error(ErrorCode::kInvalidArgument, "path", "point " + std::to_string(i) + " is not finite");
    }
  }
  return Status::success();
}

Result<LospoResult> lospo(const MotionValidator& validator, const std::vector<Eigen::Vector3d>& path_m,
                          const LospoOptions& options, const TerminationCondition& stop) {
  const auto t0 = Clock::now();
  if (Status points = checkPathPoints(path_m); !points.ok()) return points.error();
  if (!std::isfinite(options.spacing_m) || !(options.spacing_m > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "spacing_m", "spacing_m must be finite and > 0");
  }
  if (options.max_vertices < 0) {
    return make_error(ErrorCode::kInvalidArgument, "max_vertices", "max_vertices must be >= 0 (0 = no limit)");
  }
  if (options.max_passes < 1) return make_error(ErrorCode::kInvalidArgument, "max_passes", "max_passes must be >= 1");
  LospoResult result;
  result.input_length_m = polylineLength(path_m);
  if (options.max_vertices == 0 && result.input_length_m / options.spacing_m > 1e6) {
    return make_error(ErrorCode::kInvalidArgument, "spacing_m",
                      "spacing_m is too small for a path of " + std::to_string(result.input_length_m) +
                          " m (more than 10^6 vertices)");
  }
  for (std::size_t i = 1; i < path_m.size(); ++i) {
    ++result.motion_checks;
    if (!validator.isMotionValid(path_m[i - 1], path_m[i])) {
      return make_error(ErrorCode::kInvalidArgument, "path",
                        "segment " + std::to_string(i - 1) + " -> " + std::to_string(i) + " is not a valid motion");
    }
  }

  std::vector<Eigen::Vector3d> best = path_m;
  double best_length = result.input_length_m;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    double spacing = options.spacing_m;
    if (options.max_vertices > 0) spacing = std::max(spacing, best_length / options.max_vertices);
    PassResult next = lospoPass(validator, best, spacing, options.point_prefilter, stop, result.motion_checks,
                                result.point_checks);
    ++result.passes;
    if (options.merge_collinear) next.path = mergeCollinear(validator, next.path, result.motion_checks);
    const double length = polylineLength(next.path);
    // Guards against rounding in the inserted vertices: keep only verified, not longer results.
    const bool better = length <= best_length && allMotionsValid(validator, next.path, result.motion_checks);
    const double gain = best_length - length;
    if (better) {
      best = std::move(next.path);
      best_length = length;
    }
    if (next.stopped) {
      result.stopped_early = true;
      break;
    }
    if (!better || gain < options.min_pass_gain_m) break;
  }
  result.path_m = std::move(best);
  result.length_m = best_length;
  result.time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

}  // namespace skyroute
