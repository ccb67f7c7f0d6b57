// What `skyroute px4` streams to PX4, decided without DDS: given the vehicle's trajectories as
// they arrive, PX4's EKF origin and the time, the offboard setpoint for that instant.
//
// - Following: the trajectory's state at that instant, interpolated between samples by the
//   degree-7 Hermite segments that match each sample's position, velocity and acceleration (jerk
//   from neighbouring accelerations), then converted exactly from the daemon's ENU frame (recovered
//   from the samples, service/trajectory_frame.hpp) to PX4's NED frame (service/px4_projection.hpp);
//   velocity and acceleration go through the same conversion's Jacobian, so they are the time
//   derivatives of the positions given. yaw_ned = pi/2 - yaw_enu, i.e. the compass heading, in
//   -pi..pi (interpolated between samples along the shorter arc).
// - A new revision (or plan) takes over at its first sample's time: a replan starts at the state
//   the vehicle is predicted to have then, so the setpoints stay continuous. Until then the
//   current one goes on (a revision that arrives later but starts earlier replaces those still
//   waiting). A trajectory that starts later than now with nothing flown before: the setpoint
//   waits at its first sample.
// - Holding: after the last sample, when the daemon has been silent for longer than the timeout,
//   or when the daemon retracts the trajectory, the setpoint stays at one position with zero
//   velocity and acceleration, until a different trajectory arrives (the same one arriving again,
//   e.g. from a restarted daemon, does not end a hold). Each change of mode is reported once.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "service/mission_types.hpp"
#include "service/px4_projection.hpp"
#include "terrain/local_frame.hpp"
#include "planning/core/result.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

struct OffboardSetpoint {
  std::int64_t time_utc_ns = 0;  // the instant this setpoint is for
  Eigen::Vector3d position_ned_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ned_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_ned_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d jerk_ned_mps3 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;  // NED: clockwise from north, -pi..pi
};

enum class FollowMode { kWaiting, kBeforeStart, kFollowing, kHoldingAtEnd, kHoldingSilent, kHoldingRetracted };
std::string_view to_string(FollowMode mode);

class OffboardFollower {
 public:
  struct Options {
    double silence_timeout_s = 3.0;  // no heartbeat nor trajectory from the daemon for this long: hold
  };

  OffboardFollower(const GeoPoint& px4_origin, Options options);

  // A trajectory of the followed vehicle arrived at now_utc_ns. Errors (no samples, samples that
  // fit no local frame, a broken time line) name the field; the trajectory is then ignored.
  Status offer(const TrajectoryData& trajectory, std::int64_t now_utc_ns);
  // The daemon retracted the vehicle's trajectory (a cancelled mission).
  void retract();
  void heardFromDaemon(std::int64_t now_utc_ns);
  // PX4 moved its EKF origin: setpoints, a held one included, follow it.
  void setOrigin(const GeoPoint& px4_origin);

  // The setpoint for now_utc_ns, or nullopt while there is nothing to fly.
  std::optional<OffboardSetpoint> step(std::int64_t now_utc_ns);
  FollowMode mode() const { return mode_; }
  // One line per change since the last call (for the operator).
  std::vector<std::string> takeEvents();

 private:
  struct Prepared {
    std::string plan_id;
    std::uint32_t revision = 0;
    std::vector<double> sample_times_s;   // relative to the first sample
    std::vector<double> heading_deg;      // per sample
    std::vector<TrajectorySampleData> ends;  // first and last sample
    LocalFrame frame;
    Trajectory curve;                     // in the daemon's ENU frame; empty for a single sample
    std::int64_t start_utc_ns = 0;
    std::int64_t end_utc_ns = 0;
  };
  static Result<Prepared> prepare(const TrajectoryData& trajectory);
  OffboardSetpoint evaluate(const Prepared& p, std::int64_t at_utc_ns, std::int64_t stamp_utc_ns) const;
  void hold(FollowMode why, OffboardSetpoint at, const std::string& message);
  bool known(const TrajectoryData& t) const;

  Px4Projection projection_;
  Options options_;
  FollowMode mode_ = FollowMode::kWaiting;
  std::optional<Prepared> current_;
  std::deque<Prepared> pending_;  // arrived, not yet started; by start time
  std::optional<OffboardSetpoint> last_;  // the last setpoint given
  std::optional<OffboardSetpoint> held_;  // while holding
  std::int64_t last_heard_utc_ns_ = 0;
  std::vector<std::string> events_;
};

}  // namespace skyroute
