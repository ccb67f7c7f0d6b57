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

namespace skyroute {

std::string_view to_string(TrajectoryStatus status) {
  switch (status) {
    case TrajectoryStatus::kFeasible: return "feasible";
    case TrajectoryStatus::kRepaired: return "repaired";
    case TrajectoryStatus::kInfeasible: return "infeasible";
  }
  return "unknown";
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
    case ViolationKind::kTurnRadius:
    case ViolationKind::kCollision: return 0.0;
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
};

// A rounded corner, so it can be put back and rounded wider when the curve through it still
// turns too tightly (the spline dips under the arc's radius where a straight joins the arc).
struct CornerRecord {
  PathVertex original;
  double radius_m = 0.0;
  int widenings = 0;
};

constexpr double kTurningRad = 1e-6;  // a vertex turning less is straight
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
    return path[j].corner >= 0 || turnAt(path, j) < kTurningRad ? kFullShare : 0.5;
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

}  // namespace

Result<BuiltTrajectory> buildTrajectory(const std::vector<Eigen::Vector3d>& waypoints, const VehicleLimits& limits,
                                        const TrajectoryOptions& options, const MotionCheck* collision) {
  const auto started = std::chrono::steady_clock::now();
  if (Status s = validateWaypoints(waypoints, options.min_waypoint_separation_m); !s) return s.error();
  if (Status s = limits.validate(); !s) return s.error();
  if (Status s = validateOptions(options, waypoints.size()); !s) return s.error();

  std::vector<PathVertex> path;
  path.reserve(waypoints.size());
  for (std::size_t i = 0; i < waypoints.size(); ++i)
    path.push_back(PathVertex{waypoints[i], i == 0 || i + 1 == waypoints.size(), i, -1});
  for (std::size_t index : options.fixed_waypoints) path[index].fixed = true;

  TimeAllocationOptions allocation = options.time_allocation;
  allocation.start_speed_mps = options.boundary.start.velocity_mps.norm();
  allocation.end_speed_mps = options.boundary.end.velocity_mps.norm();
  std::vector<Eigen::Vector3d> knots;
  std::vector<double> durations;
  std::vector<std::size_t> vertex_knot;  // knot index of each path vertex
  std::vector<CornerRecord> corners;
  // Knots and times from the path: extra waypoints at the LOSPO spacing, then time allocation.
  auto layOut = [&]() -> Status {
    std::vector<Eigen::Vector3d> points;
    points.reserve(path.size());
    for (const PathVertex& v : path) points.push_back(v.point);
    DensifiedPath densified = densifyWaypoints(points, options.waypoint_spacing_m);
    knots = std::move(densified.points);
    vertex_knot = std::move(densified.original_indices);
    Result<std::vector<double>> allocated = allocateTimes(knots, limits, allocation);
    if (!allocated) return allocated.error();
    durations = std::move(allocated.value());
    return Status::success();
  };
  if (Status s = layOut(); !s) return s.error();

  BuiltTrajectory built;
  TrajectoryBuildReport& report = built.report;
  report.input_waypoints = waypoints.size();
  const int local_rounds = options.max_repair_rounds / 2;  // then stretch everything uniformly
  int timing_from_round = 0;  // the round the current knots and times were laid out in
  // Worst violation / limit ratio before the last uniform stretch (it must keep falling).
  double previous_uniform_worst = std::numeric_limits<double>::infinity();
  double previous_local_worst = std::numeric_limits<double>::infinity();
  int growing_rounds = 0;  // stretch rounds in a row whose worst violation grew

  for (int round = 0;; ++round) {
    Result<std::vector<Segment>> segments = solveMinimumSnapSpline(knots, durations, options.boundary);
    if (!segments) return segments.error();
    built.trajectory = Trajectory(std::move(segments.value()));
    report.final_check = checkFeasibility(built.trajectory, limits, options.feasibility, collision);
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
    if (!options.repair) {
      report.failure_reason = "repair disabled; first violation: " + describe(violations.front());
      break;
    }
    if (round >= options.max_repair_rounds) {
      report.failure_reason = "still infeasible after " + std::to_string(round) +
                              " repair rounds; first violation: " + describe(violations.front());
      break;
    }
    const std::vector<double>& t = built.trajectory.knotTimes();

    // Turns tighter than the vehicle can fly: a different path, so this comes first and the
    // knots and times are laid out again from the new path (time repairs of the old one are moot).
    if (report.final_check.has(ViolationKind::kTurnRadius)) {
      std::string unrepairable;
      // Corner to round, keyed by its path position (its first vertex): the radius it needs at least
      // (0: first rounding, from the options) and the violation that asks for it.
      struct Job {
        double radius_m = 0.0;
        std::string cause;
      };
      std::map<std::size_t, Job> jobs;
      for (const Violation& v : violations) {
        if (v.kind != ViolationKind::kTurnRadius) continue;
        if (!options.round_corners) {
          unrepairable = describe(v) +
                         ": the path's corner is too sharp for this vehicle (stretching time does not widen a turn) "
                         "and corner rounding is off; the path needs smoothing or replanning";
          break;
        }
        // The turning vertex whose knot time is nearest the violation is the corner it flies.
        std::size_t nearest = path.size();
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t i = 1; i + 1 < path.size(); ++i) {
          if (turnAt(path, i) < kTurningRad) continue;
          const double gap = std::abs(t[vertex_knot[i]] - v.time_s);
          if (gap < best) {
            best = gap;
            nearest = i;
          }
        }
        if (nearest == path.size()) {
          unrepairable = describe(v) + ": no corner of the path explains it (the curve wiggles on a straight path)";
          break;
        }
        const int id = path[nearest].corner;
        if (id < 0) {
          jobs.emplace(nearest, Job{0.0, describe(v)});
          continue;
        }
        // Already rounded, yet the curve through it turns too tightly: widen it by the shortfall.
        CornerRecord& record = corners[static_cast<std::size_t>(id)];
        if (record.widenings >= kMaxWidenings) {
          unrepairable = describe(v) + ": the curve through the rounded corner at waypoint " +
                         std::to_string(record.original.input_index) + " still turns too tightly after " +
                         std::to_string(record.widenings) + " widenings; the path needs replanning";
          break;
        }
        std::size_t first = nearest;
        while (first > 0 && path[first - 1].corner == id) --first;
        const double wider = record.radius_m * std::max(1.05, 1.05 * v.limit / std::max(v.value, 1e-9));
        Job& job = jobs[first];
        if (wider > job.radius_m) job = Job{wider, describe(v)};
      }
      if (unrepairable.empty()) {
        std::vector<double> vertex_time(path.size());
        for (std::size_t i = 0; i < path.size(); ++i) vertex_time[i] = t[vertex_knot[i]];
        // From the back, so the positions in front stay valid as vertices are replaced.
        for (auto it = jobs.rbegin(); it != jobs.rend(); ++it) {
          const std::size_t at = it->first;
          const int existing = path[at].corner;
          double preferred = options.corner_rounding.radius_factor * limits.min_turn_radius_m;
          double lowest = limits.min_turn_radius_m;
          int id = static_cast<int>(corners.size());
          if (existing >= 0) {
            // Put the original corner back, then round it wider than before.
            std::size_t last = at;
            while (last + 1 < path.size() && path[last + 1].corner == existing) ++last;
            path.erase(path.begin() + static_cast<std::ptrdiff_t>(at + 1),
                       path.begin() + static_cast<std::ptrdiff_t>(last + 1));
            path[at] = corners[static_cast<std::size_t>(existing)].original;
            vertex_time.erase(vertex_time.begin() + static_cast<std::ptrdiff_t>(at + 1),
                              vertex_time.begin() + static_cast<std::ptrdiff_t>(last + 1));
            preferred = it->second.radius_m;
            lowest = corners[static_cast<std::size_t>(existing)].radius_m * 1.01;
            id = existing;
          }
          const PathVertex original = path[at];
          CornerRepair repair = roundPathCorner(path, at, id, preferred, lowest, vertex_time, options.corner_rounding,
                                                collision);
          if (!repair.ok) {
            unrepairable = it->second.cause + ": " +
                           (existing >= 0 ? format("the curve through the %.1f m rounded corner still turns too "
                                                   "tightly and a wider one fails: ",
                                                   corners[static_cast<std::size_t>(existing)].radius_m)
                                          : std::string()) +
                           repair.line;
            break;
          }
          vertex_time.insert(vertex_time.begin() + static_cast<std::ptrdiff_t>(at), repair.added, vertex_time[at]);
          if (existing >= 0) {
            CornerRecord& record = corners[static_cast<std::size_t>(existing)];
            ++record.widenings;
            report.repairs.push_back(format("widened (the curve dipped under the limit through the %.1f m one): ",
                                            record.radius_m) +
                                     repair.line);
            record.radius_m = repair.radius_m;
          } else {
            corners.push_back(CornerRecord{original, repair.radius_m, 0});
            ++report.corners_rounded;
            report.repairs.push_back(repair.line);
          }
        }
      }
      if (!unrepairable.empty()) {
        report.failure_reason = unrepairable;
        break;
      }
      if (Status s = layOut(); !s) return s.error();
      timing_from_round = round + 1;
      previous_uniform_worst = std::numeric_limits<double>::infinity();
      previous_local_worst = std::numeric_limits<double>::infinity();
      growing_rounds = 0;
      continue;
    }

    // Collisions: split the segment at the middle of its chord. Knots lie on the path (the input
    // polyline, or a rounded corner's points, each checked clear when adopted) and no path vertex
    // lies between two consecutive knots, so the chord is part of the checked path; if the chord
    // itself is blocked no amount of splitting helps.
    std::set<std::size_t> to_split;
    std::map<std::size_t, double> stretch;  // segment -> factor
    std::string unrepairable;
    for (const Violation& v : violations) {
      if (v.kind == ViolationKind::kCollision) {
        const std::size_t s = v.segment;
        if (collision && !(*collision)(knots[s], t[s], knots[s + 1], t[s + 1])) {
          unrepairable = "the straight path between knots " + std::to_string(s) + " and " + std::to_string(s + 1) +
                         format(" (t=%.2f..%.2f s) is itself blocked (terrain or obstacle): the path needs replanning",
                                t[s], t[s + 1]);
          break;
        }
        if ((knots[s + 1] - knots[s]).norm() < 2.0 * options.min_split_length_m) {
          unrepairable = "the curve in segment " + std::to_string(s) +
                         " still leaves the clear corridor after splitting it down to " +
                         format("%.2f m", (knots[s + 1] - knots[s]).norm());
          break;
        }
        to_split.insert(s);
      } else {
        stretch[v.segment] = std::max(stretch[v.segment], stretchFactor(v));
      }
    }
    if (!unrepairable.empty()) {
      report.failure_reason = unrepairable;
      break;
    }

    // Stretch first (indices refer to the current segments), then split from the back.
    if (!stretch.empty()) {
      double worst = 1.0;
      for (const auto& [s, f] : stretch) worst = std::max(worst, f);
      const double margin = 1.03;
      // Stretching a segment whose start velocity is given makes the curve overshoot instead of
      // easing it; when the worst violation grew two rounds running, more rounds only diverge
      // (a replan once spent 0.5 s stretching its first segment to 500 s).
      growing_rounds = worst > previous_local_worst ? growing_rounds + 1 : 0;
      previous_local_worst = worst;
      if (growing_rounds >= 2) {
        report.failure_reason = "stretching in time makes the violation worse (" + format("%.2f", worst) +
                                " x the limit; " + describe(violations.front()) + "); the end conditions or the path must change";
        break;
      }
      if (round - timing_from_round < local_rounds) {
        std::vector<double> factor(durations.size(), 1.0);
        for (const auto& [s, f] : stretch) {
          const double k = std::min(4.0, f * margin);
          factor[s] = std::max(factor[s], k);
          // Neighbours share the joint's derivatives; stretch them part way so the joint eases too.
          if (s > 0) factor[s - 1] = std::max(factor[s - 1], std::sqrt(k));
          if (s + 1 < factor.size()) factor[s + 1] = std::max(factor[s + 1], std::sqrt(k));
        }
        for (std::size_t s = 0; s < durations.size(); ++s) durations[s] *= factor[s];
        report.repairs.push_back("stretched " + std::to_string(stretch.size()) + " segment(s) in time by up to " +
                                 format("%.1f%%", (std::min(4.0, worst * margin) - 1.0) * 100.0) + " (" +
                                 describe(*std::find_if(violations.begin(), violations.end(), [](const Violation& v) {
                                   return v.kind != ViolationKind::kCollision;
                                 })) +
                                 ")");
      } else {
        // A uniform stretch slows a rest-to-rest curve exactly, but with a given end velocity it
        // can make things worse (the curve keeps the end's speed over a longer time, so it strays
        // further and must come back faster): stop as soon as a stretch did not help, instead of
        // stretching without end (a replan's curve once ran to 1e17 s and took minutes).
        if (worst >= previous_uniform_worst) {
          report.failure_reason = "stretching the whole trajectory in time does not reduce the violation (" +
                                  format("%.2f", worst) + " x the limit, " + format("%.2f", previous_uniform_worst) +
                                  " before; " + describe(violations.front()) +
                                  "); the end conditions or the path must change";
          break;
        }
        previous_uniform_worst = worst;
        const double k = std::min(4.0, worst * margin);
        for (double& d : durations) d *= k;
        report.repairs.push_back("stretched the whole trajectory in time by " + format("%.1f%%", (k - 1.0) * 100.0));
      }
    }
    if (!to_split.empty()) {
      for (auto it = to_split.rbegin(); it != to_split.rend(); ++it) {
        const std::size_t s = *it;
        const Eigen::Vector3d middle = 0.5 * (knots[s] + knots[s + 1]);
        const double half = 0.5 * durations[s];
        knots.insert(knots.begin() + static_cast<std::ptrdiff_t>(s + 1), middle);
        durations[s] = half;
        durations.insert(durations.begin() + static_cast<std::ptrdiff_t>(s + 1), half);
        for (std::size_t& k : vertex_knot)
          if (k > s) ++k;
      }
      report.repairs.push_back("added " + std::to_string(to_split.size()) +
                               " waypoint(s) on the checked path where the curve collided (first in segment " +
                               std::to_string(*to_split.begin()) + ")");
    }
  }
  built.knots = std::move(knots);
  report.knots = built.knots.size();
  report.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return built;
}

}  // namespace skyroute
