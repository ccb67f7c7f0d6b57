// A fixed wing's hold: it cannot stop, so where a multirotor would come to rest it loiters
// (trajectory/loiter.hpp). The circle is chosen as the hold's stop is: the latest entry on the
// current trajectory (the most of it kept) from which a circle is clear, with room to spare from
// the obstacles where it can. Every candidate is checked against the vehicle's limits (entry and
// one whole turn, which then repeats exactly), against the terrain, the fixed obstacles and the
// no-fly zones over one whole turn, and against the moving obstacles over the horizon.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>

#include "service/flight_replanner.hpp"
#include "trajectory/trajectory_splice.hpp"

namespace skyroute {

namespace {

// Room a loiter keeps from every obstacle round its circle, when it can (m).
constexpr double kLoiterRoomM = 30.0;
// The loiter speed's floor over the minimum airspeed: the arcs' speed is the circle's within a
// fraction of a percent, and the entry eases between the entry speed and this.
constexpr double kLoiterSpeedOverMin = 1.1;

}  // namespace

bool FlightReplanner::adoptLoiter(double now_s, double takeover_s, double conflict_s, std::optional<Error>& why_not) {
  const auto started = std::chrono::steady_clock::now();
  const Trajectory& current = route_.built.trajectory;
  const double from_s = std::max(now_s, start_world_s_);
  const double speed_mps =
      std::min(limits_.max_speed_mps, std::max(limits_.v_ref_mps, kLoiterSpeedOverMin * limits_.minAirspeedMps()));
  const double tightest_m = std::max(limits_.turnRadiusAtM(speed_mps), limits_.min_turn_radius_m);
  // Entry times as the hold's stop times: latest first (at most 6), down to the takeover.
  std::vector<double> entry_times;
  const double step_s = std::max(1.0, (conflict_s - 2.0 - takeover_s) / 5.0);
  for (double t = conflict_s - 2.0; t > takeover_s && entry_times.size() < 5; t -= step_s) entry_times.push_back(t);
  entry_times.push_back(takeover_s);
  struct Shape {
    double radius_scale;
    double join_turn_rad;
  };
  const double margin = options_.loiter_radius_margin;
  const Shape shapes[] = {{margin, 0.5 * std::numbers::pi},
                          {margin, std::numbers::pi},
                          {1.6 * margin, 0.5 * std::numbers::pi},
                          {1.6 * margin, std::numbers::pi}};
  const double circle_s = 2.0 * options_.horizon_s;
  std::optional<LoiterPath> best;
  std::optional<Trajectory> best_hold;
  double best_conflict = conflict_s;
  double best_entry_s = 0.0;
  double best_room_m = -1.0;
  int tried = 0, over_limits = 0, blocked = 0;
  for (double entry_s : entry_times) {
    const TrajectoryState entry = stateAt(entry_s);
    bool room_enough = false;
    for (const Shape& shape : shapes) {
      for (bool left : {true, false}) {
        ++tried;
        LoiterShape s;
        s.turning_left = left;
        s.radius_m = shape.radius_scale * tightest_m;
        s.speed_mps = speed_mps;
        s.join_turn_rad = shape.join_turn_rad;
        s.lead_m = 0.5 * s.radius_m * shape.join_turn_rad;
        Result<LoiterPath> path = loiterFrom(entry, s, circle_s);
        if (!path) {
          ++over_limits;
          continue;
        }
        // The entry and one whole turn: the rest repeats it exactly.
        const std::size_t first_turn = std::min(path->segments.size(), 1 + static_cast<std::size_t>(path->circle.arcs_per_turn));
        const Trajectory turn(std::vector<Segment>(path->segments.begin(), path->segments.begin() + static_cast<std::ptrdiff_t>(first_turn)));
        if (!checkFeasibility(turn, limits_).ok()) {
          ++over_limits;
          continue;
        }
        bool clear = true;
        Eigen::Vector3d previous = turn.evaluate(0.0, Derivative::kPosition);
        for (double t = options_.check_step_s; clear; t += options_.check_step_s) {
          const Eigen::Vector3d p = turn.evaluate(std::min(t, turn.duration_s()), Derivative::kPosition);
          clear = world_->isStaticSegmentValid(previous, p);
          previous = p;
          if (t >= turn.duration_s()) break;
        }
        if (!clear) {
          ++blocked;
          continue;
        }
        std::vector<Segment> segments = segmentsBetween(current, from_s - start_world_s_, entry_s - start_world_s_);
        segments.insert(segments.end(), path->segments.begin(), path->segments.end());
        Trajectory hold(std::move(segments));
        // Up to the entry it is the current trajectory, clear until conflict_s: checked from there.
        const double conflict = firstConflictS(hold, from_s, entry_s, now_s + options_.horizon_s - entry_s);
        if (!std::isinf(conflict)) ++blocked;
        double room_m = -1.0;
        if (std::isinf(conflict)) {
          const double join_s = entry_s + path->segments.front().duration_s;
          room_m = std::numeric_limits<double>::infinity();
          for (int k = 0; k < path->circle.arcs_per_turn; ++k) {
            const double angle = path->join_angle_rad + path->circle.arcAngleRad() * k;
            room_m = std::min(room_m, world_->obstacleDistance(path->circle.positionAt(angle), join_s));
          }
        }
        if (conflict > best_conflict || (std::isinf(conflict) && room_m > best_room_m)) {
          best_conflict = conflict;
          best = std::move(path.value());
          best_hold = std::move(hold);
          best_entry_s = entry_s;
          best_room_m = room_m;
          if (room_m >= kLoiterRoomM) {
            room_enough = true;
            break;
          }
        }
      }
      if (room_enough) break;
    }
    if (room_enough) break;
  }
  // Only a clear loiter is put in force, and only when the audit passes it too.
  if (best && std::isinf(best_conflict)) {
    if (auto refused = auditRefusal(*best_hold, from_s, now_s, revision_ + 1)) {
      why_not = refused;
      return false;
    }
  }
  if (!best || !std::isinf(best_conflict)) {
    why_not = make_error(ErrorCode::kUnreachable, "loiter",
                         fmt::format("no loiter circle is clear: {} circles of radius {:.0f}-{:.0f} m at {:.1f} m/s from {} "
                                     "entry points ({} meet the terrain, an obstacle or a no-fly zone, {} break the "
                                     "vehicle's limits); the current trajectory stays in force",
                                     tried, margin * tightest_m, 1.6 * margin * tightest_m, speed_mps,
                                     entry_times.size(), blocked, over_limits));
    spdlog::debug("event=replan_no_loiter tried={} blocked={} over_limits={} conflict_in_s={:.1f}", tried, blocked,
                  over_limits, conflict_s - now_s);
    return false;
  }
  installHold(std::move(*best_hold), from_s, best_entry_s);
  loiter_circle_ = best->circle;
  loiter_end_rad_ = best->end_angle_rad;
  spdlog::debug("event=replan_loiter entry_in_s={:.1f} radius_m={:.0f} speed_mps={:.1f} left={} conflict_in_s={:.1f} "
                "room_m={:.0f} tried={} ms={:.1f}",
                best_entry_s - now_s, best->circle.radius_m, best->circle.speed_mps, best->circle.turning_left,
                best_conflict - now_s, best_room_m, tried,
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
  return true;
}

bool FlightReplanner::extendLoiter(double now_s) {
  if (!holding_ || !loiter_circle_) return false;
  const double end_s = arrivalWorldS();
  if (end_s - now_s >= options_.horizon_s + 1.0) return false;
  const double from_s = std::max(now_s, start_world_s_);
  const LoiterCircle& circle = *loiter_circle_;
  const double arc_s = circle.turnS() / static_cast<double>(circle.arcs_per_turn);
  // Back to twice the horizon ahead.
  const auto arcs = static_cast<std::size_t>(std::ceil(std::max(0.0, from_s + 2.0 * options_.horizon_s - end_s) / arc_s));
  std::vector<Segment> more = loiterArcs(circle, loiter_end_rad_, std::max<std::size_t>(1, arcs));
  if (more.empty()) return false;
  std::vector<Segment> segments =
      segmentsBetween(route_.built.trajectory, from_s - start_world_s_, route_.built.trajectory.duration_s());
  const std::size_t added = more.size();
  segments.insert(segments.end(), more.begin(), more.end());
  Trajectory extended(std::move(segments));
  if (auditRefusal(extended, from_s, now_s, revision_ + 1)) return false;  // the loiter in force stays as it is
  installHold(std::move(extended), from_s, from_s);
  loiter_end_rad_ += circle.arcAngleRad() * static_cast<double>(added);
  spdlog::debug("event=replan_loiter_extended arcs={} until_s={:.1f}", added, arrivalWorldS());
  return true;
}

double FlightReplanner::loiterExitTime(double now_s) const {
  const double earliest = now_s + options_.reaction_delay_s;
  const std::vector<Eigen::Vector3d> ahead = remainingPoints(earliest);
  if (ahead.empty() || !loiter_circle_) return earliest;
  const double latest = std::min(earliest + loiter_circle_->turnS(), arrivalWorldS());
  constexpr double kStepS = 0.1;
  double best_s = earliest;
  double best_cos = -2.0;
  for (double t = earliest; t <= latest + 1e-9; t += kStepS) {
    const TrajectoryState s = stateAt(t);
    const Eigen::Vector2d heading = s.velocity_mps.head<2>();
    const Eigen::Vector2d to_point = (ahead.front() - s.position_m).head<2>();
    if (heading.norm() < 1e-6 || to_point.norm() < 1.0) continue;
    const double cos = heading.normalized().dot(to_point.normalized());
    if (cos > best_cos) {
      best_cos = cos;
      best_s = t;
    }
  }
  return best_s;
}

}  // namespace skyroute
