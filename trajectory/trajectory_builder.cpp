#include "trajectory/trajectory_builder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "planning/core/enum_names.hpp"

namespace skyroute {

std::string_view to_string(TrajectoryStatus status) {
  constexpr EnumName<TrajectoryStatus> kNames[] = {{TrajectoryStatus::kFeasible, "feasible"},
                                                   {TrajectoryStatus::kRepaired, "repaired"},
                                                   {TrajectoryStatus::kInfeasible, "infeasible"}};
  return enumName(kNames, status);
}

namespace {

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), fmt, a, b, c, d);
  return buffer;
}

std::string describe(const Violation& v) {
  const std::string kind(to_string(v.kind));
  if (v.kind == ViolationKind::kCollision)
    return "collision in segment " + std::to_string(v.segment) + format(" at t=%.2f s", v.time_s);
  return kind + " in segment " + std::to_string(v.segment) +
         format(" at t=%.2f s: %.3f (limit %.3f)", v.time_s, v.value, v.limit);
}

// How much longer a segment must take to bring the violation within its limit (> 1), or 0 when
// stretching time cannot fix it.
double stretchFactor(const Violation& v) {
  switch (v.kind) {
    case ViolationKind::kSpeed:
    case ViolationKind::kClimbRate:
    case ViolationKind::kDescentRate: return v.value / v.limit;
    case ViolationKind::kAcceleration: return std::sqrt(v.value / v.limit);
    // The lift beyond the weight scales with the acceleration, as 1/k^2.
    case ViolationKind::kLoadFactor: return v.limit > 1.0 ? std::sqrt((v.value - 1.0) / (v.limit - 1.0)) : 0.0;
    case ViolationKind::kTurnRadius:
    case ViolationKind::kCollision:
    case ViolationKind::kBelowMinAirspeed:
    case ViolationKind::kBankAngle:
    case ViolationKind::kClimbAngle:
    case ViolationKind::kDescentAngle: return 0.0;
  }
  return 0.0;
}

Status validateOptions(const TrajectoryOptions& o, std::size_t waypoint_count) {
  auto bad = [](const char* field, const std::string& why) { return make_error(ErrorCode::kInvalidArgument, field, why); };
  if (!std::isfinite(o.waypoint_spacing_m) || o.waypoint_spacing_m < 0.0)
    return bad("options.waypoint_spacing_m", "must be >= 0 and finite (0 = no extra waypoints)");
  if (!std::isfinite(o.feasibility.dt_s) || o.feasibility.dt_s <= 0.0)
    return bad("options.feasibility.dt_s", "must be positive and finite");
  if (!std::isfinite(o.feasibility.relative_tolerance) || o.feasibility.relative_tolerance < 0.0)
    return bad("options.feasibility.relative_tolerance", "must be >= 0 and finite");
  if (o.max_repair_rounds < 0) return bad("options.max_repair_rounds", "must be >= 0");
  if (!std::isfinite(o.min_waypoint_separation_m) || o.min_waypoint_separation_m < 0.0)
    return bad("options.min_waypoint_separation_m", "must be >= 0 and finite");
  if (!std::isfinite(o.min_split_length_m) || o.min_split_length_m <= 0.0)
    return bad("options.min_split_length_m", "must be positive and finite");
  for (std::size_t index : o.fixed_waypoints)
    if (index >= waypoint_count)
      return bad("options.fixed_waypoints", "index " + std::to_string(index) + " is past the last waypoint (" +
                                                std::to_string(waypoint_count - 1) + ")");
  const CornerRoundingOptions& c = o.corner_rounding;
  if (!std::isfinite(c.radius_factor) || c.radius_factor < 1.0)
    return bad("options.corner_rounding.radius_factor", "must be >= 1 and finite");
  if (c.radius_attempts < 1) return bad("options.corner_rounding.radius_attempts", "must be >= 1");
  if (!std::isfinite(c.arc_step_deg) || c.arc_step_deg <= 0.0 || c.arc_step_deg > 90.0)
    return bad("options.corner_rounding.arc_step_deg", "must be in (0, 90]");
  if (!std::isfinite(c.pass_through_straight_share) || c.pass_through_straight_share < 0.0)
    return bad("options.corner_rounding.pass_through_straight_share", "must be >= 0 and finite");
  const std::pair<const char*, const Eigen::Vector3d*> ends[] = {
      {"boundary.start.velocity_mps", &o.boundary.start.velocity_mps},
      {"boundary.start.acceleration_mps2", &o.boundary.start.acceleration_mps2},
      {"boundary.start.jerk_mps3", &o.boundary.start.jerk_mps3},
      {"boundary.end.velocity_mps", &o.boundary.end.velocity_mps},
      {"boundary.end.acceleration_mps2", &o.boundary.end.acceleration_mps2},
      {"boundary.end.jerk_mps3", &o.boundary.end.jerk_mps3}};
  for (const auto& [name, value] : ends)
    if (!value->allFinite()) return bad(name, "is NaN or infinite");
  return Status::success();
}

// The geometric path the knots are densified from: the input polyline, with rounded corners
// replaced by their fillet (or pass-through) points.
struct PathVertex {
  Eigen::Vector3d point;
  bool fixed = false;           // must stay a knot (input fixed waypoint, or the point of a pass-through)
  std::size_t input_index = 0;  // the input waypoint it is, or whose corner it rounds
  int corner = -1;              // the rounded corner it belongs to (index into CornerRecord), or -1
  bool stop = false;            // the vehicle comes to rest here (a fixed waypoint)
};

// A rounded corner, so it can be put back and rounded wider when the curve through it still
// turns too tightly (the spline dips under the arc's radius where a straight joins the arc).
struct CornerRecord {
  PathVertex original;
  double radius_m = 0.0;
  int widenings = 0;
};

constexpr double kTurningRad = 1e-6;  // a vertex turning less is straight
constexpr double kStretchMargin = 1.03;  // a stretch goes this much beyond the violation's ratio

// Turns the vehicle cannot fly: too tight for its radius, or (a fixed wing) for its bank.
bool isTurnViolation(ViolationKind kind) {
  return kind == ViolationKind::kTurnRadius || kind == ViolationKind::kBankAngle;
}

// How much wider a corner must be for the violation to go (> 1 when it is too tight).
double turnShortfall(const Violation& v) {
  if (v.kind == ViolationKind::kLoadFactor) {
    // In a level turn n = 1 / cos(bank): tan(bank) = sqrt(n^2 - 1) scales with the curvature.
    const double need = std::sqrt(std::max(0.0, v.value * v.value - 1.0));
    const double allowed = std::sqrt(std::max(1e-9, v.limit * v.limit - 1.0));
    return need / allowed;
  }
  if (v.kind == ViolationKind::kBankAngle) {
    // At the same speed the bank's tangent scales with the curvature, 1 / radius.
    const double deg = std::numbers::pi / 180.0;
    return std::tan(std::min(v.value, 89.0) * deg) / std::tan(v.limit * deg);
  }
  return v.limit / std::max(v.value, 1e-9);
}

// A fixed wing's violations no repair here fixes: the path or the limits must change.
bool isFixedWingPathViolation(ViolationKind kind) {
  return kind == ViolationKind::kBelowMinAirspeed || kind == ViolationKind::kClimbAngle ||
         kind == ViolationKind::kDescentAngle;
}
constexpr double kFullShare = 0.9;    // tangent share of a leg whose other end needs none
constexpr int kMaxWidenings = 3;

double turnAt(const std::vector<PathVertex>& path, std::size_t i) {
  if (i == 0 || i + 1 >= path.size()) return 0.0;
  return deflectionAngle(path[i - 1].point, path[i].point, path[i + 1].point);
}

struct CornerRepair {
  bool ok = false;
  std::string line;  // repair line, or why it failed
  std::size_t added = 0;
  double radius_m = 0.0;
};

// Rounds corner i of `path` (an unrounded interior vertex): radii from `preferred_m` (or the
// largest that fits) down to `lowest_m` until the new geometry is clear. On success replaces path[i]
// by the corner's points, tagged with `corner_id`.
CornerRepair roundPathCorner(std::vector<PathVertex>& path, std::size_t i, int corner_id, double preferred_m,
                             double lowest_m, const std::vector<double>& vertex_time_s,
                             const CornerRoundingOptions& options, const MotionCheck* collision) {
  CornerRepair result;
  const Eigen::Vector3d a = path[i - 1].point;
  const Eigen::Vector3d p = path[i].point;
  const Eigen::Vector3d b = path[i + 1].point;
  const CornerMethod method = path[i].fixed ? CornerMethod::kPassThrough : CornerMethod::kFillet;
  // A neighbour that may itself need rounding keeps half of the shared leg.
  auto share = [&](std::size_t j) {
    return path[j].corner >= 0 || path[j].stop || turnAt(path, j) < kTurningRad ? kFullShare : 0.5;
  };
  const double share_in = share(i - 1);
  const double share_out = share(i + 1);
  const double phi_deg = turnAt(path, i) * 180.0 / std::numbers::pi;
  const std::string where = "waypoint " + std::to_string(path[i].input_index) + (path[i].fixed ? " (fixed)" : "") +
                            format(" turning %.1f deg", phi_deg);
  const double first = largestFittingRadius(method, a, p, b, preferred_m, share_in, share_out, options);
  if (first < lowest_m * (1.0 - 1e-9)) {
    result.line = "the corner at " + where + " cannot be rounded: the largest " + std::string(to_string(method)) +
                  format(" that fits its legs (%.1f m and %.1f m) has radius %.1f m, under the %.1f m needed; the path "
                         "needs replanning",
                         (p - a).norm(), (b - p).norm(), first, lowest_m);
    return result;
  }
  // Smaller radii keep the new curve closer to the checked corner, so they are the fallback.
  std::vector<double> radii{first};
  const int attempts = std::max(1, options.radius_attempts);
  for (int k = 1; k < attempts; ++k) {
    const double r = first * std::pow(lowest_m / first, static_cast<double>(k) / (attempts - 1));
    if (r < radii.back() * (1.0 - 1e-6)) radii.push_back(std::max(r, lowest_m));
  }
  // New pieces: a fillet's chords (its tangent points lie on the checked legs); a pass-through
  // leaves the legs, so its chords from a and to b too. Times by length between the neighbours'.
  for (double radius : radii) {
    std::optional<CornerGeometry> corner = roundCorner(method, a, p, b, radius, share_in, share_out, options);
    if (!corner) continue;
    std::vector<Eigen::Vector3d> chain;
    chain.push_back(a);
    chain.insert(chain.end(), corner->points.begin(), corner->points.end());
    chain.push_back(b);
    bool clear = true;
    if (collision) {
      std::vector<double> along(chain.size(), 0.0);
      for (std::size_t k = 1; k < chain.size(); ++k) along[k] = along[k - 1] + (chain[k] - chain[k - 1]).norm();
      const double t_a = vertex_time_s[i - 1];
      const double t_b = vertex_time_s[i + 1];
      auto time_at = [&](std::size_t k) { return t_a + (t_b - t_a) * along[k] / along.back(); };
      const std::size_t from = method == CornerMethod::kFillet ? 1 : 0;
      const std::size_t to = method == CornerMethod::kFillet ? chain.size() - 2 : chain.size() - 1;
      for (std::size_t k = from; k < to && clear; ++k)
        clear = (*collision)(chain[k], time_at(k), chain[k + 1], time_at(k + 1));
    }
    if (!clear) continue;
    std::vector<PathVertex> replacement;
    for (std::size_t k = 0; k < corner->points.size(); ++k)
      replacement.push_back(PathVertex{corner->points[k], k == corner->kept_point, path[i].input_index, corner_id});
    result.ok = true;
    result.added = replacement.size() - 1;
    result.radius_m = radius;
    result.line = "rounded the corner at " + where + " with a " +
                  (method == CornerMethod::kFillet
                       ? format("%.1f m fillet", radius)
                       : format("straight pass along its bisector between two %.1f m fillets", radius)) +
                  (radius < first ? format(" (wider ones from %.1f m collide)", first) : std::string());
    path.erase(path.begin() + static_cast<std::ptrdiff_t>(i));
    path.insert(path.begin() + static_cast<std::ptrdiff_t>(i), replacement.begin(), replacement.end());
    return result;
  }
  result.line = "the corner at " + where + " cannot be rounded: every " + std::string(to_string(method)) +
                format(" from %.1f m down to %.1f m collides (terrain or obstacle); the path needs replanning", first,
                       lowest_m);
  return result;
}

// A corner to round, keyed by its path position (its first vertex): the radius it needs at least
// (0: first rounding, from the options) and the violation that asks for it.
struct CornerJob {
  double radius_m = 0.0;
  std::string cause;
  bool stop = false;  // a fixed corner that cannot be flown through: come to rest there instead
  Violation violation;
};

// The time and chord repairs one round asks for.
struct SegmentRepairs {
  std::set<std::size_t> to_split;
  std::map<std::size_t, double> stretch;  // segment -> factor
};

// buildTrajectory's solve-check-repair loop and the state its rounds share: the geometric path
// (input waypoints, rounded corners replaced by their points), the knots and times laid out from
// it, and what earlier rounds learnt (rounded corners, worst violations of the stretches).
class RepairLoop {
 public:
  RepairLoop(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits, const TrajectoryOptions& options,
             const MotionCheck* collision, const std::vector<WaypointStop>& stops)
      : limits_(limits), options_(options), collision_(collision), allocation_(options.time_allocation),
        local_rounds_(options.max_repair_rounds / 2), stops_(stops), may_stop_(!limits.fixedWing()) {
    path_.reserve(waypoints.size());
    for (std::size_t i = 0; i < waypoints.size(); ++i)
      path_.push_back(PathVertex{waypoints[i], i == 0 || i + 1 == waypoints.size(), i, -1});
    for (std::size_t index : options.fixed_waypoints) path_[index].fixed = true;
    for (const WaypointStop& stop : stops) path_[stop.waypoint].stop = true;
    allocation_.start_speed_mps = options.boundary.start.velocity_mps.norm();
    allocation_.end_speed_mps = options.boundary.end.velocity_mps.norm();
  }

  // Knots and times from the path: extra waypoints at the LOSPO spacing, then time allocation.
  Status layOut() {
    std::vector<Eigen::Vector3d> points;
    points.reserve(path_.size());
    for (const PathVertex& v : path_) points.push_back(v.point);
    DensifiedPath densified = densifyWaypoints(points, options_.waypoint_spacing_m);
    knots_ = std::move(densified.points);
    vertex_knot_ = std::move(densified.original_indices);
    Result<std::vector<double>> allocated = allocateTimesWithStops(knots_, limits_, allocation_, stopKnots());
    if (!allocated) return allocated.error();
    durations_ = std::move(allocated.value());
    return Status::success();
  }

  // Solves, checks and repairs until the trajectory is feasible, the rounds run out or a violation
  // cannot be repaired (the report says which); an error only for a failed solve or layout.
  Status run(BuiltTrajectory& built);

  // The stops it was given and those it made (fixed corners that could not be flown through).
  const std::vector<WaypointStop>& stops() const { return stops_; }
  // The violation that ended the repairs unrepaired: the one the failure reason is about.
  std::optional<Violation> failingViolation(const FeasibilityReport& check) const {
    if (failing_) return failing_;
    if (!check.violations.empty()) return check.violations.front();
    return std::nullopt;
  }

 private:
  std::vector<std::size_t> stopKnots() const {
    std::vector<std::size_t> knots;
    for (std::size_t i = 0; i < path_.size() && i < vertex_knot_.size(); ++i)
      if (path_[i].stop) knots.push_back(vertex_knot_[i]);
    return knots;
  }
  // Makes the unrounded fixed vertex path_[at] a stop.
  void stopAt(std::size_t at, const std::string& why, TrajectoryBuildReport& report) {
    path_[at].stop = true;
    stops_.push_back(WaypointStop{path_[at].input_index, why});
    report.repairs.push_back("stops at waypoint " + std::to_string(path_[at].input_index) + ": " + why);
  }

  // Turns tighter than the vehicle can fly (turn radius, bank, a fixed wing's load factor): the
  // corners they fly, to round (or widen). Returns why it cannot, or "". A load factor with no
  // corner to explain it is left to the stretch (a pull-up on a straight), which says why not.
  std::string findCornerJobs(const std::vector<Violation>& violations, const std::vector<double>& t,
                             std::map<std::size_t, CornerJob>& jobs);
  std::string roundCorners(const std::map<std::size_t, CornerJob>& jobs, const std::vector<double>& t,
                           TrajectoryBuildReport& report);
  // Collisions to split and limits to stretch; why a collision cannot be repaired, or "".
  std::string sortSegmentRepairs(const std::vector<Violation>& violations, const std::vector<double>& t,
                                 SegmentRepairs& repairs);
  // Stretches the segments over a limit, locally for the first rounds after a layout, then the
  // whole trajectory; why stretching does not help, or "".
  std::string stretchInTime(const std::map<std::size_t, double>& stretch, const std::vector<Violation>& violations,
                            int round, const Trajectory& trajectory, TrajectoryBuildReport& report);
  // A fixed wing: the largest stretch of segment s (or, for npos, of the whole trajectory) that
  // keeps it at or above its minimum airspeed; infinity for a multirotor.
  double largestStretch(const Trajectory& trajectory, std::size_t s) const;
  // Splits each segment at the middle of its chord, from the back.
  void splitSegments(const std::set<std::size_t>& to_split, TrajectoryBuildReport& report);

  const VehicleLimits& limits_;
  const TrajectoryOptions& options_;
  const MotionCheck* collision_;
  TimeAllocationOptions allocation_;  // its start/end speeds taken from the boundary
  std::vector<PathVertex> path_;
  std::vector<Eigen::Vector3d> knots_;
  std::vector<double> durations_;
  std::vector<std::size_t> vertex_knot_;  // knot index of each path vertex
  std::vector<CornerRecord> corners_;
  const int local_rounds_;       // then stretch everything uniformly
  int timing_from_round_ = 0;    // the round the current knots and times were laid out in
  // Worst violation / limit ratio before the last uniform stretch (it must keep falling).
  double previous_uniform_worst_ = std::numeric_limits<double>::infinity();
  double previous_local_worst_ = std::numeric_limits<double>::infinity();
  int growing_rounds_ = 0;  // stretch rounds in a row whose worst violation grew
  std::vector<WaypointStop> stops_;
  std::optional<Violation> failing_;  // the violation an unrepairable verdict is about
  const bool may_stop_;               // a fixed wing never comes to rest
};

Status RepairLoop::run(BuiltTrajectory& built) {
  TrajectoryBuildReport& report = built.report;
  for (int round = 0;; ++round) {
    failing_.reset();
    Result<std::vector<Segment>> segments =
        solveMinimumSnapSplineWithStops(knots_, durations_, options_.boundary, stopKnots());
    if (!segments) return segments.error();
    built.trajectory = Trajectory(std::move(segments.value()));
    report.final_check = checkFeasibility(built.trajectory, limits_, options_.feasibility, collision_);
    report.repair_rounds = round;
    if (report.final_check.stopped) {
      return make_error(ErrorCode::kCancelled, "trajectory", "stopped while checking the trajectory (repair round " +
                                                                 std::to_string(round) + ")");
    }
    if (report.final_check.ok()) {
      report.status = round == 0 ? TrajectoryStatus::kFeasible : TrajectoryStatus::kRepaired;
      break;
    }
    report.status = TrajectoryStatus::kInfeasible;
    const std::vector<Violation>& violations = report.final_check.violations;
    if (!options_.repair) {
      report.failure_reason = "repair disabled; first violation: " + describe(violations.front());
      break;
    }
    if (round >= options_.max_repair_rounds) {
      report.failure_reason = "still infeasible after " + std::to_string(round) +
                              " repair rounds; first violation: " + describe(violations.front());
      break;
    }
    const std::vector<double>& t = built.trajectory.knotTimes();

    // Turns tighter than the vehicle can fly: a different path, so this comes first and the
    // knots and times are laid out again from the new path (time repairs of the old one are moot).
    // A fixed wing's load factor is eased by slowing down (the stretch below) as far as its
    // minimum airspeed allows; beyond that the turn it flies is widened like a bank.
    std::vector<Violation> turns;
    for (const Violation& v : violations) {
      const bool too_slow = limits_.fixedWing() && v.kind == ViolationKind::kLoadFactor &&
                            stretchFactor(v) * kStretchMargin > largestStretch(built.trajectory, v.segment);
      if (isTurnViolation(v.kind) || too_slow) turns.push_back(v);
    }
    std::map<std::size_t, CornerJob> corner_jobs;
    if (!turns.empty()) {
      if (std::string unrepairable = findCornerJobs(turns, t, corner_jobs); !unrepairable.empty()) {
        report.failure_reason = unrepairable;
        break;
      }
    }
    if (!corner_jobs.empty()) {
      if (std::string unrepairable = roundCorners(corner_jobs, t, report); !unrepairable.empty()) {
        report.failure_reason = unrepairable;
        break;
      }
      if (Status s = layOut(); !s) return s;
      timing_from_round_ = round + 1;
      previous_uniform_worst_ = std::numeric_limits<double>::infinity();
      previous_local_worst_ = std::numeric_limits<double>::infinity();
      growing_rounds_ = 0;
      continue;
    }

    // A fixed wing slower than its minimum airspeed or steeper than its path angles: neither
    // stretching nor splitting helps (a slower curve is worse; the angles are the path's).
    if (auto path = std::find_if(violations.begin(), violations.end(),
                                 [](const Violation& v) { return isFixedWingPathViolation(v.kind); });
        path != violations.end()) {
      failing_ = *path;
      report.failure_reason = describe(*path) +
                              (path->kind == ViolationKind::kBelowMinAirspeed
                                   ? ": the fixed wing would fly under its minimum airspeed (stall speed x margin)"
                                   : ": the path is steeper than the fixed wing's path angle limit; it needs replanning");
      break;
    }
    SegmentRepairs repairs;
    if (std::string unrepairable = sortSegmentRepairs(violations, t, repairs); !unrepairable.empty()) {
      report.failure_reason = unrepairable;
      break;
    }
    // Stretch first (indices refer to the current segments), then split from the back.
    if (!repairs.stretch.empty()) {
      if (std::string failed = stretchInTime(repairs.stretch, violations, round, built.trajectory, report);
          !failed.empty()) {
        report.failure_reason = failed;
        break;
      }
    }
    if (!repairs.to_split.empty()) splitSegments(repairs.to_split, report);
  }
  built.knots = std::move(knots_);
  return Status::success();
}

std::string RepairLoop::findCornerJobs(const std::vector<Violation>& violations, const std::vector<double>& t,
                                       std::map<std::size_t, CornerJob>& jobs) {
  for (const Violation& v : violations) {
    failing_ = v;  // until it is explained
    if (!options_.round_corners) {
      return describe(v) +
             ": the path's corner is too sharp for this vehicle (stretching time does not widen a turn) "
             "and corner rounding is off; the path needs smoothing or replanning";
    }
    // The turning vertex whose knot time is nearest the violation is the corner it flies.
    std::size_t nearest = path_.size();
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i + 1 < path_.size(); ++i) {
      if (path_[i].stop || turnAt(path_, i) < kTurningRad) continue;
      const double gap = std::abs(t[vertex_knot_[i]] - v.time_s);
      if (gap < best) {
        best = gap;
        nearest = i;
      }
    }
    if (nearest == path_.size()) {
      if (v.kind == ViolationKind::kLoadFactor) {
        failing_.reset();
        continue;
      }
      return describe(v) + ": no corner of the path explains it (the curve wiggles on a straight path)";
    }
    const int id = path_[nearest].corner;
    if (id < 0) {
      jobs.emplace(nearest, CornerJob{0.0, describe(v), false, v});
      continue;
    }
    // Already rounded, yet the curve through it turns too tightly: widen it by the shortfall.
    CornerRecord& record = corners_[static_cast<std::size_t>(id)];
    std::size_t first = nearest;
    while (first > 0 && path_[first - 1].corner == id) --first;
    if (record.widenings >= kMaxWidenings && record.original.fixed && may_stop_) {
      jobs[first] = CornerJob{0.0,
                              describe(v) + ": the curve through its rounded corner still turns too tightly after " +
                                  std::to_string(record.widenings) + " widenings",
                              true, v};
      continue;
    }
    if (record.widenings >= kMaxWidenings) {
      return describe(v) + ": the curve through the rounded corner at waypoint " +
             std::to_string(record.original.input_index) + " still turns too tightly after " +
             std::to_string(record.widenings) + " widenings; the path needs replanning";
    }
    const double wider = record.radius_m * std::max(1.05, 1.05 * turnShortfall(v));
    CornerJob& job = jobs[first];
    if (!job.stop && wider > job.radius_m) job = CornerJob{wider, describe(v), false, v};
  }
  return std::string();
}

std::string RepairLoop::roundCorners(const std::map<std::size_t, CornerJob>& jobs, const std::vector<double>& t,
                                     TrajectoryBuildReport& report) {
  std::vector<double> vertex_time(path_.size());
  for (std::size_t i = 0; i < path_.size(); ++i) vertex_time[i] = t[vertex_knot_[i]];
  // From the back, so the positions in front stay valid as vertices are replaced.
  for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) {
    const std::size_t at = it->first;
    const int existing = path_[at].corner;
    double preferred = options_.corner_rounding.radius_factor * limits_.min_turn_radius_m;
    double lowest = limits_.min_turn_radius_m;
    int id = static_cast<int>(corners_.size());
    if (existing >= 0) {
      // Put the original corner back, then round it wider than before.
      std::size_t last = at;
      while (last + 1 < path_.size() && path_[last + 1].corner == existing) ++last;
      path_.erase(path_.begin() + static_cast<std::ptrdiff_t>(at + 1), path_.begin() + static_cast<std::ptrdiff_t>(last + 1));
      path_[at] = corners_[static_cast<std::size_t>(existing)].original;
      vertex_time.erase(vertex_time.begin() + static_cast<std::ptrdiff_t>(at + 1),
                        vertex_time.begin() + static_cast<std::ptrdiff_t>(last + 1));
      preferred = it->second.radius_m;
      lowest = corners_[static_cast<std::size_t>(existing)].radius_m * 1.01;
      id = existing;
    }
    const PathVertex original = path_[at];
    if (it->second.stop) {
      stopAt(at, it->second.cause, report);
      continue;
    }
    CornerRepair repair =
        roundPathCorner(path_, at, id, preferred, lowest, vertex_time, options_.corner_rounding, collision_);
    if (!repair.ok && original.fixed && may_stop_) {
      // No pass-through fits or is clear: come to rest at the point, which turns any corner.
      stopAt(at, it->second.cause + ": " + repair.line, report);
      continue;
    }
    if (!repair.ok) {
      failing_ = it->second.violation;
      return it->second.cause + ": " +
             (existing >= 0 ? format("the curve through the %.1f m rounded corner still turns too "
                                     "tightly and a wider one fails: ",
                                     corners_[static_cast<std::size_t>(existing)].radius_m)
                            : std::string()) +
             repair.line;
    }
    vertex_time.insert(vertex_time.begin() + static_cast<std::ptrdiff_t>(at), repair.added, vertex_time[at]);
    if (existing >= 0) {
      CornerRecord& record = corners_[static_cast<std::size_t>(existing)];
      ++record.widenings;
      report.repairs.push_back(
          format("widened (the curve dipped under the limit through the %.1f m one): ", record.radius_m) + repair.line);
      record.radius_m = repair.radius_m;
    } else {
      corners_.push_back(CornerRecord{original, repair.radius_m, 0});
      ++report.corners_rounded;
      report.repairs.push_back(repair.line);
    }
  }
  return std::string();
}

std::string RepairLoop::sortSegmentRepairs(const std::vector<Violation>& violations, const std::vector<double>& t,
                                           SegmentRepairs& repairs) {
  // Collisions: split the segment at the middle of its chord. Knots lie on the path (the input
  // polyline, or a rounded corner's points, each checked clear when adopted) and no path vertex
  // lies between two consecutive knots, so the chord is part of the checked path; if the chord
  // itself is blocked no amount of splitting helps.
  for (const Violation& v : violations) {
    if (v.kind == ViolationKind::kCollision) {
      const std::size_t s = v.segment;
      failing_ = v;
      if (collision_ && !(*collision_)(knots_[s], t[s], knots_[s + 1], t[s + 1])) {
        return "the straight path between knots " + std::to_string(s) + " and " + std::to_string(s + 1) +
               format(" (t=%.2f..%.2f s) is itself blocked (terrain or obstacle): the path needs replanning", t[s],
                      t[s + 1]);
      }
      if ((knots_[s + 1] - knots_[s]).norm() < 2.0 * options_.min_split_length_m) {
        return "the curve in segment " + std::to_string(s) + " still leaves the clear corridor after splitting it down to " +
               format("%.2f m", (knots_[s + 1] - knots_[s]).norm());
      }
      failing_.reset();
      repairs.to_split.insert(s);
    } else {
      repairs.stretch[v.segment] = std::max(repairs.stretch[v.segment], stretchFactor(v));
    }
  }
  return std::string();
}

double RepairLoop::largestStretch(const Trajectory& trajectory, std::size_t s) const {
  if (!limits_.fixedWing()) return std::numeric_limits<double>::infinity();
  const auto& segments = trajectory.segments();
  const std::size_t from = s == std::string::npos ? 0 : s;
  const std::size_t to = s == std::string::npos ? segments.size() : std::min(segments.size(), s + 1);
  double slowest = std::numeric_limits<double>::infinity();
  constexpr int kSamples = 16;
  for (std::size_t i = from; i < to; ++i)
    for (int k = 0; k <= kSamples; ++k)
      slowest = std::min(slowest, segments[i].evaluate(segments[i].duration_s * k / kSamples, Derivative::kVelocity).norm());
  return slowest / limits_.minAirspeedMps();
}

std::string RepairLoop::stretchInTime(const std::map<std::size_t, double>& stretch,
                                      const std::vector<Violation>& violations, int round,
                                      const Trajectory& trajectory, TrajectoryBuildReport& report) {
  double worst = 1.0;
  for (const auto& [s, f] : stretch) worst = std::max(worst, f);
  const double margin = kStretchMargin;
  // A fixed wing slowed under its minimum airspeed has traded one violation for another: say
  // where and why instead.
  auto too_slow = [&](std::size_t s, double k, double cap) {
    const auto it = std::find_if(violations.begin(), violations.end(), [&](const Violation& v) {
      return v.kind != ViolationKind::kCollision && (s == std::string::npos || v.segment == s);
    });
    const Violation& v = it != violations.end() ? *it : violations.front();
    failing_ = v;
    const std::vector<double>& t = trajectory.knotTimes();
    const std::string where = s == std::string::npos
                                  ? std::string("the whole trajectory")
                                  : "segment " + std::to_string(s) + format(" (t=%.2f..%.2f s)", t[s], t[s + 1]);
    return describe(v) + ": slowing " + where + format(" by %.1f%%", (k - 1.0) * 100.0) +
           " would take the fixed wing under its minimum airspeed (" +
           format("%.1f m/s at the slowest there, at most %.1f%% slower keeps %.1f m/s", cap * limits_.minAirspeedMps(),
                  (cap - 1.0) * 100.0, limits_.minAirspeedMps()) +
           "); the path must change (a wider turn, a gentler climb or pull-up)";
  };
  // Stretching a segment whose start velocity is given makes the curve overshoot instead of
  // easing it; when the worst violation grew two rounds running, more rounds only diverge
  // (a replan once spent 0.5 s stretching its first segment to 500 s).
  growing_rounds_ = worst > previous_local_worst_ ? growing_rounds_ + 1 : 0;
  previous_local_worst_ = worst;
  if (growing_rounds_ >= 2 && round - timing_from_round_ < local_rounds_) {
    // Local stretches (and the splits between them) fight each other: stretch everything
    // uniformly from here, which slows rest-to-rest pieces exactly (and has its own guard).
    timing_from_round_ = round - local_rounds_;
    growing_rounds_ = 0;
  } else if (growing_rounds_ >= 2) {
    return "stretching in time makes the violation worse (" + format("%.2f", worst) + " x the limit; " +
           describe(violations.front()) + "); the end conditions or the path must change";
  }
  if (round - timing_from_round_ < local_rounds_) {
    std::vector<double> factor(durations_.size(), 1.0);
    for (const auto& [s, f] : stretch) {
      const double k = std::min(4.0, f * margin);
      if (const double cap = largestStretch(trajectory, s); k > cap) return too_slow(s, k, cap);
      factor[s] = std::max(factor[s], k);
      // Neighbours share the joint's derivatives; stretch them part way so the joint eases too
      // (a fixed wing's no further than its minimum airspeed allows).
      auto ease = [&](std::size_t n) {
        factor[n] = std::max(factor[n], std::min(std::sqrt(k), std::max(1.0, largestStretch(trajectory, n))));
      };
      if (s > 0) ease(s - 1);
      if (s + 1 < factor.size()) ease(s + 1);
    }
    for (std::size_t s = 0; s < durations_.size(); ++s) durations_[s] *= factor[s];
    report.repairs.push_back("stretched " + std::to_string(stretch.size()) + " segment(s) in time by up to " +
                             format("%.1f%%", (std::min(4.0, worst * margin) - 1.0) * 100.0) + " (" +
                             describe(*std::find_if(violations.begin(), violations.end(), [](const Violation& v) {
                               return v.kind != ViolationKind::kCollision;
                             })) +
                             ")");
    return std::string();
  }
  // A uniform stretch slows a rest-to-rest curve exactly, but with a given end velocity it can
  // make things worse (the curve keeps the end's speed over a longer time, so it strays further
  // and must come back faster): stop as soon as a stretch did not help, instead of stretching
  // without end (a replan's curve once ran to 1e17 s and took minutes).
  if (worst >= previous_uniform_worst_) {
    return "stretching the whole trajectory in time does not reduce the violation (" + format("%.2f", worst) +
           " x the limit, " + format("%.2f", previous_uniform_worst_) + " before; " + describe(violations.front()) +
           "); the end conditions or the path must change";
  }
  previous_uniform_worst_ = worst;
  const double k = std::min(4.0, worst * margin);
  if (const double cap = largestStretch(trajectory, std::string::npos); k > cap) return too_slow(std::string::npos, k, cap);
  for (double& d : durations_) d *= k;
  report.repairs.push_back("stretched the whole trajectory in time by " + format("%.1f%%", (k - 1.0) * 100.0));
  return std::string();
}

void RepairLoop::splitSegments(const std::set<std::size_t>& to_split, TrajectoryBuildReport& report) {
  for (auto it = to_split.rbegin(); it != to_split.rend(); ++it) {
    const std::size_t s = *it;
    const Eigen::Vector3d middle = 0.5 * (knots_[s] + knots_[s + 1]);
    const double half = 0.5 * durations_[s];
    knots_.insert(knots_.begin() + static_cast<std::ptrdiff_t>(s + 1), middle);
    durations_[s] = half;
    durations_.insert(durations_.begin() + static_cast<std::ptrdiff_t>(s + 1), half);
    for (std::size_t& k : vertex_knot_)
      if (k > s) ++k;
  }
  report.repairs.push_back("added " + std::to_string(to_split.size()) +
                           " waypoint(s) on the checked path where the curve collided (first in segment " +
                           std::to_string(*to_split.begin()) + ")");
}

// Rebuilds with more stops after a failure: with the stops the loop made, at the passed point
// nearest the violation, at every point still passed, at every corner of the path (the last);
// each rebuild costs a full repair loop.
constexpr int kMaxStopAttempts = 5;

// The stops the mode asks for from the start: every interior fixed waypoint in the stop mode.
std::vector<WaypointStop> modeStops(const TrajectoryOptions& options, std::size_t waypoint_count) {
  std::vector<WaypointStop> stops;
  if (options.fixed_waypoint_mode != FixedWaypointMode::kStop) return stops;
  std::set<std::size_t> interior;
  for (std::size_t index : options.fixed_waypoints)
    if (index > 0 && index + 1 < waypoint_count) interior.insert(index);
  for (std::size_t index : interior) stops.push_back(WaypointStop{index, "mission_point_mode is stop"});
  return stops;
}

// Interior fixed waypoints the trajectory still passes (does not stop at), in order.
std::vector<std::size_t> passedFixedWaypoints(const TrajectoryOptions& options, std::size_t waypoint_count,
                                              const std::vector<WaypointStop>& stops) {
  std::set<std::size_t> passed;
  for (std::size_t index : options.fixed_waypoints)
    if (index > 0 && index + 1 < waypoint_count) passed.insert(index);
  for (const WaypointStop& stop : stops) passed.erase(stop.waypoint);
  return {passed.begin(), passed.end()};
}

// The candidate (input index) whose knot time is nearest time_s. A fixed waypoint always stays a
// knot, found by position, in order along the knots.
std::optional<std::size_t> nearestWaypointInTime(const BuiltTrajectory& built,
                                                 const std::vector<Eigen::Vector3d>& waypoints,
                                                 std::vector<std::size_t> candidates, double time_s) {
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  const std::vector<double>& times = built.trajectory.knotTimes();
  std::optional<std::size_t> best;
  double best_gap = std::numeric_limits<double>::infinity();
  std::size_t k = 0;
  for (std::size_t index : candidates) {
    std::size_t at = k;
    while (at < built.knots.size() && (built.knots[at] - waypoints[index]).norm() > 1e-6) ++at;
    if (at >= built.knots.size() || at >= times.size()) continue;
    k = at;
    const double gap = std::abs(times[at] - time_s);
    if (gap < best_gap) {
      best_gap = gap;
      best = index;
    }
  }
  return best;
}

// A fixed wing never hovers: it starts and ends at cruise speed along the path's first and last
// pieces (unless the caller gives the end's velocity, as a replan does), flies every piece at
// cruise speed (eq. 3: slowing for a turn or a climb could take it under its minimum airspeed;
// its climbs are bounded by the path angle instead), and passes every fixed waypoint.
Result<BuiltTrajectory> buildWithStops(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                       const TrajectoryOptions& options, const MotionCheck* collision,
                                       std::chrono::steady_clock::time_point started);

TrajectoryOptions fixedWingOptions(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                   TrajectoryOptions options) {
  const std::size_t n = waypoints.size();
  if (options.boundary.start.velocity_mps.isZero(0.0))
    options.boundary.start.velocity_mps = limits.v_ref_mps * (waypoints[1] - waypoints[0]).normalized();
  if (options.boundary.end.velocity_mps.isZero(0.0))
    options.boundary.end.velocity_mps = limits.v_ref_mps * (waypoints[n - 1] - waypoints[n - 2]).normalized();
  options.time_allocation.method = TimeAllocationMethod::kConstantSpeed;
  options.fixed_waypoint_mode = FixedWaypointMode::kPass;
  options.stop_at_corners_as_last_resort = false;
  return options;
}

}  // namespace

Result<BuiltTrajectory> buildTrajectory(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TrajectoryOptions& options, const MotionCheck* collision) {
  const auto started = std::chrono::steady_clock::now();
  if (Status s = validateWaypoints(waypoints, options.min_waypoint_separation_m); !s) return s.error();
  if (Status s = limits.validate(); !s) return s.error();
  if (Status s = validateOptions(options, waypoints.size()); !s) return s.error();
  // The geometry holds the radius of the fixed wing's tightest turn at cruise speed.
  VehicleLimits effective = limits;
  effective.min_turn_radius_m = limits.effectiveMinTurnRadiusM();
  const TrajectoryOptions fixed_wing = limits.fixedWing() ? fixedWingOptions(waypoints, limits, options) : options;
  const TrajectoryOptions& used = limits.fixedWing() ? fixed_wing : options;
  return buildWithStops(waypoints, effective, used, collision, started);
}

namespace {

Result<BuiltTrajectory> buildWithStops(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                       const TrajectoryOptions& options, const MotionCheck* collision,
                                       std::chrono::steady_clock::time_point started) {
  std::vector<WaypointStop> stops = modeStops(options, waypoints.size());
  BuiltTrajectory built;
  bool tried_nearest = false;
  for (int attempt = 0;; ++attempt) {
    const std::size_t given = stops.size();
    RepairLoop loop(waypoints, limits, options, collision, stops);
    if (Status s = loop.layOut(); !s) return s.error();
    built = BuiltTrajectory{};
    built.report.input_waypoints = waypoints.size();
    if (Status s = loop.run(built); !s) return s.error();
    stops = loop.stops();
    if (built.report.status != TrajectoryStatus::kInfeasible) break;
    built.report.failure_violation = loop.failingViolation(built.report.final_check);
    if (!built.report.failure_violation || attempt >= kMaxStopAttempts || limits.fixedWing()) break;
    // The loop made stops of fixed corners it could not round: build again with them from the
    // start (their rounds were spent on the pass-throughs).
    if (stops.size() > given) continue;
    const std::string why = "the trajectory could not be made to fly without it (" + built.report.failure_reason + ")";
    const std::vector<std::size_t> passed = passedFixedWaypoints(options, waypoints.size(), stops);
    if (!passed.empty() && !tried_nearest) {
      // The passed point nearest the violation first, then every point still passed.
      tried_nearest = true;
      if (auto nearest = nearestWaypointInTime(built, waypoints, passed, built.report.failure_violation->time_s)) {
        stops.push_back({*nearest, why});
        continue;
      }
    }
    if (!passed.empty()) {
      for (std::size_t index : passed) stops.push_back({index, why});
      continue;
    }
    // Last resort: rest at every corner of the path too (TrajectoryOptions says why it flies).
    if (!options.stop_at_corners_as_last_resort) break;
    const std::size_t before = stops.size();
    std::set<std::size_t> stopped;
    for (const WaypointStop& stop : stops) stopped.insert(stop.waypoint);
    for (std::size_t i = 1; i + 1 < waypoints.size(); ++i)
      if (!stopped.count(i)) stops.push_back({i, "a corner of the path; " + why});
    if (stops.size() == before) break;
  }
  std::sort(stops.begin(), stops.end(), [](const WaypointStop& a, const WaypointStop& b) { return a.waypoint < b.waypoint; });
  built.report.stops = std::move(stops);
  if (built.report.status == TrajectoryStatus::kInfeasible && built.report.failure_violation) {
    std::vector<std::size_t> fixed = options.fixed_waypoints;
    fixed.push_back(0);
    fixed.push_back(waypoints.size() - 1);
    built.report.failure_waypoint =
        nearestWaypointInTime(built, waypoints, fixed, built.report.failure_violation->time_s);
  }
  built.report.knots = built.knots.size();
  built.report.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return built;
}

}  // namespace

}  // namespace skyroute
