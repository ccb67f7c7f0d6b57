#include "service/offboard_follower.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "service/trajectory_frame.hpp"
#include "trajectory/spline7.hpp"

namespace skyroute {

namespace {

constexpr double kNsPerS = 1e9;

double wrapPi(double a) { return std::atan2(std::sin(a), std::cos(a)); }

std::string describeNed(const Eigen::Vector3d& ned) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "north=%.2f east=%.2f down=%.2f", ned.x(), ned.y(), ned.z());
  return buf;
}

std::string describePlan(const std::string& plan_id, std::uint32_t revision) {
  return "plan " + plan_id + " revision " + std::to_string(revision);
}

}  // namespace

std::string_view to_string(FollowMode mode) {
  switch (mode) {
    case FollowMode::kWaiting: return "waiting";
    case FollowMode::kBeforeStart: return "before_start";
    case FollowMode::kFollowing: return "following";
    case FollowMode::kHoldingAtEnd: return "holding_at_end";
    case FollowMode::kHoldingSilent: return "holding_silent";
    case FollowMode::kHoldingRetracted: return "holding_retracted";
  }
  return "unknown";
}

OffboardFollower::OffboardFollower(const GeoPoint& px4_origin, Options options)
    : projection_(px4_origin), options_(options) {}

Result<OffboardFollower::Prepared> OffboardFollower::prepare(const TrajectoryData& trajectory) {
  auto frame = recoverTrajectoryFrame(trajectory);
  if (!frame.ok()) return frame.error();
  const auto& samples = trajectory.samples;
  Prepared p{trajectory.plan_id, trajectory.revision, {}, {}, {samples.front(), samples.back()}, *frame, {}, 0, 0};
  p.start_utc_ns = samples.front().utc_ns;

  // Knots: samples at strictly increasing times (the sampler repeats the end time at most once).
  std::vector<std::size_t> knots{0};
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const double dt = samples[i].t_rel_s - samples[knots.back()].t_rel_s;
    if (!(dt >= 0.0)) {
      return make_error(ErrorCode::kInvalidArgument, "samples[" + std::to_string(i) + "].t_rel_s",
                        "goes back in time");
    }
    if (dt > 1e-9) knots.push_back(i);
  }
  std::vector<Eigen::Vector3d> waypoints;
  std::vector<double> durations_s;
  std::vector<KnotDerivatives> derivatives;
  const double t0 = samples.front().t_rel_s;
  for (std::size_t k = 0; k < knots.size(); ++k) {
    const TrajectorySampleData& s = samples[knots[k]];
    p.sample_times_s.push_back(s.t_rel_s - t0);
    p.heading_deg.push_back(s.heading_deg);
    waypoints.push_back(s.position_enu_m);
    if (k > 0) durations_s.push_back(s.t_rel_s - samples[knots[k - 1]].t_rel_s);
    // The samples carry no jerk; the central difference of the accelerations is second-order
    // accurate, and the position between samples depends on it only at order dt^3.
    const TrajectorySampleData& before = samples[knots[k > 0 ? k - 1 : k]];
    const TrajectorySampleData& after = samples[knots[k + 1 < knots.size() ? k + 1 : k]];
    const double span_s = after.t_rel_s - before.t_rel_s;
    const Eigen::Vector3d jerk =
        span_s > 0.0 ? Eigen::Vector3d((after.acceleration_enu_mps2 - before.acceleration_enu_mps2) / span_s)
                     : Eigen::Vector3d::Zero();
    derivatives.push_back({s.velocity_enu_mps, s.acceleration_enu_mps2, jerk});
  }
  if (knots.size() >= 2) {
    auto segments = hermiteSpline(waypoints, durations_s, derivatives);
    if (!segments.ok()) return segments.error();
    p.curve = Trajectory(std::move(*segments));
  }
  p.end_utc_ns = p.start_utc_ns + static_cast<std::int64_t>(std::llround(p.sample_times_s.back() * kNsPerS));
  return p;
}

OffboardSetpoint OffboardFollower::evaluate(const Prepared& p, std::int64_t at_utc_ns, std::int64_t stamp_utc_ns) const {
  const double t_s = static_cast<double>(at_utc_ns - p.start_utc_ns) / kNsPerS;
  TrajectoryState state;
  if (p.curve.empty()) {
    state.position_m = p.ends.front().position_enu_m;
  } else {
    state = p.curve.stateAt(t_s);
  }
  // ENU (daemon) -> WGS84 -> NED (PX4); its Jacobian by central differences over +-1 m, where the
  // map's curvature (1 / earth radius) leaves errors of 1e-7.
  auto toNed = [&](const Eigen::Vector3d& enu) { return projection_.toNed(p.frame.toGeo(enu)); };
  const Eigen::Vector3d ned = toNed(state.position_m);
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    step(axis) = 1.0;
    jacobian.col(axis) = (toNed(state.position_m + step) - toNed(state.position_m - step)) / 2.0;
    jacobian(2, axis) = 0.0;  // horizontal moves leave the altitude as it is
  }
  jacobian(2, 2) = -1.0;  // down = -up exactly (both are altitudes AMSL minus a constant)

  OffboardSetpoint out;
  out.time_utc_ns = stamp_utc_ns;
  out.position_ned_m = ned;
  out.velocity_ned_mps = jacobian * state.velocity_mps;
  out.acceleration_ned_mps2 = jacobian * state.acceleration_mps2;
  out.jerk_ned_mps3 = jacobian * state.jerk_mps3;

  // Heading: the samples' compass heading, interpolated along the shorter arc.
  const auto& times = p.sample_times_s;
  const std::size_t hi = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t_s) - times.begin());
  double heading_rad = p.heading_deg.back() * M_PI / 180.0;
  if (hi == 0) {
    heading_rad = p.heading_deg.front() * M_PI / 180.0;
  } else if (hi < times.size()) {
    const double a = p.heading_deg[hi - 1] * M_PI / 180.0, b = p.heading_deg[hi] * M_PI / 180.0;
    const double f = (t_s - times[hi - 1]) / (times[hi] - times[hi - 1]);
    heading_rad = a + f * wrapPi(b - a);
  }
  // yaw_ned = pi/2 - yaw_enu with yaw_enu = pi/2 - heading: the compass heading itself. Measured
  // from the daemon's grid north, which within 10 km of its anchor is true north to 0.1 degree.
  const double yaw_enu = M_PI / 2.0 - heading_rad;
  out.yaw_rad = wrapPi(M_PI / 2.0 - yaw_enu);
  return out;
}

bool OffboardFollower::known(const TrajectoryData& t) const {
  auto same = [&](const Prepared& p) { return p.plan_id == t.plan_id && p.revision == t.revision; };
  return (current_ && same(*current_)) || std::any_of(pending_.begin(), pending_.end(), same);
}

Status OffboardFollower::offer(const TrajectoryData& trajectory, std::int64_t now_utc_ns) {
  heardFromDaemon(now_utc_ns);
  // Transient-local history hands the same revision out again (a reconnect, a restarted daemon):
  // it is not news, and it must not end a hold.
  if (known(trajectory)) return Status::success();
  auto prepared = prepare(trajectory);
  if (!prepared.ok()) {
    events_.push_back("ignored " + describePlan(trajectory.plan_id, trajectory.revision) + ": " +
                      prepared.error().describe());
    return prepared.error();
  }
  // The newest word holds from its start on: waiting ones that would start later are void.
  while (!pending_.empty() && pending_.back().start_utc_ns >= prepared->start_utc_ns) pending_.pop_back();
  pending_.push_back(std::move(*prepared));
  return Status::success();
}

void OffboardFollower::retract() {
  pending_.clear();
  if (!current_ || mode_ == FollowMode::kHoldingRetracted) return;
  if (!last_) {  // nothing flown yet: nothing to hold, nothing to follow
    current_.reset();
    mode_ = FollowMode::kWaiting;
    events_.push_back("skyrouted retracted the trajectory before it was flown; waiting");
    return;
  }
  hold(FollowMode::kHoldingRetracted, *last_, "skyrouted retracted the trajectory (mission cancelled)");
}

void OffboardFollower::heardFromDaemon(std::int64_t now_utc_ns) {
  last_heard_utc_ns_ = std::max(last_heard_utc_ns_, now_utc_ns);
}

void OffboardFollower::setOrigin(const GeoPoint& px4_origin) {
  const Px4Projection moved(px4_origin);
  for (std::optional<OffboardSetpoint>* s : {&last_, &held_}) {
    if (*s) (*s)->position_ned_m = moved.toNed(projection_.toGeo((*s)->position_ned_m));
  }
  projection_ = moved;
}

void OffboardFollower::hold(FollowMode why, OffboardSetpoint at, const std::string& message) {
  at.velocity_ned_mps.setZero();
  at.acceleration_ned_mps2.setZero();
  at.jerk_ned_mps3.setZero();
  held_ = at;
  mode_ = why;
  events_.push_back("holding (" + std::string(to_string(why)) + "): " + message + "; at " +
                    describeNed(at.position_ned_m));
}

std::optional<OffboardSetpoint> OffboardFollower::step(std::int64_t now_utc_ns) {
  const bool holding = mode_ == FollowMode::kHoldingAtEnd || mode_ == FollowMode::kHoldingSilent ||
                       mode_ == FollowMode::kHoldingRetracted;
  const double silent_s = static_cast<double>(now_utc_ns - last_heard_utc_ns_) / kNsPerS;
  if (current_ && last_ && !holding && silent_s > options_.silence_timeout_s) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "no word from skyrouted for %.1f s (timeout %.1f s)", silent_s,
                  options_.silence_timeout_s);
    pending_.clear();
    hold(FollowMode::kHoldingSilent, *last_, buf);
  }
  // Take over at its start; at once when there is nothing else, or when the current one has not
  // started and the new one starts no later (nothing of the current one would be flown).
  while (!pending_.empty() &&
         (!current_ || now_utc_ns >= pending_.front().start_utc_ns ||
          (now_utc_ns < current_->start_utc_ns && pending_.front().start_utc_ns <= current_->start_utc_ns))) {
    const bool first = !current_;
    events_.push_back((first ? "following " : "switched to ") +
                      describePlan(pending_.front().plan_id, pending_.front().revision) + (first ? "" : " at its start"));
    current_ = std::move(pending_.front());
    pending_.pop_front();
    held_.reset();
    mode_ = FollowMode::kFollowing;
  }
  if (held_) {
    held_->time_utc_ns = now_utc_ns;
    last_ = held_;
    return last_;
  }
  if (!current_) return std::nullopt;

  if (now_utc_ns < current_->start_utc_ns) {
    if (mode_ != FollowMode::kBeforeStart) {
      events_.push_back("waiting at the first sample until " + describePlan(current_->plan_id, current_->revision) +
                        " starts");
    }
    mode_ = FollowMode::kBeforeStart;
    OffboardSetpoint at_start = evaluate(*current_, current_->start_utc_ns, now_utc_ns);
    at_start.velocity_ned_mps.setZero();
    at_start.acceleration_ned_mps2.setZero();
    at_start.jerk_ned_mps3.setZero();
    return last_ = at_start;
  }
  if (now_utc_ns > current_->end_utc_ns) {
    OffboardSetpoint at_end = evaluate(*current_, current_->end_utc_ns, now_utc_ns);
    hold(FollowMode::kHoldingAtEnd, at_end,
         describePlan(current_->plan_id, current_->revision) + " ended; holding its last position");
    return last_ = *held_;
  }
  mode_ = FollowMode::kFollowing;
  return last_ = evaluate(*current_, now_utc_ns, now_utc_ns);
}

std::vector<std::string> OffboardFollower::takeEvents() {
  std::vector<std::string> out;
  out.swap(events_);
  return out;
}

}  // namespace skyroute
