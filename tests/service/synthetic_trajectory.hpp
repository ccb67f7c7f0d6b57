// Trajectories with a known closed form, sampled as skyrouted samples them (relative and UTC time,
// ENU state, compass heading, WGS84 through the daemon's kind of local frame), so a follower's
// output can be checked against the exact motion between the samples.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>

#include <Eigen/Core>

#include "service/mission_types.hpp"
#include "terrain/local_frame.hpp"

namespace skyroute::testing {

// Position, velocity and acceleration (ENU) at t seconds after the motion's start.
struct Motion {
  std::function<Eigen::Vector3d(double)> p, v, a;
};

// A climbing turn round centre_m: radius_m, rate_rad_s (counter-clockwise), climb_mps.
inline Motion climbingTurn(Eigen::Vector3d centre_m, double radius_m, double rate_rad_s, double climb_mps) {
  return {[=](double t) {
            return Eigen::Vector3d(centre_m.x() + radius_m * std::cos(rate_rad_s * t),
                                   centre_m.y() + radius_m * std::sin(rate_rad_s * t), centre_m.z() + climb_mps * t);
          },
          [=](double t) {
            return Eigen::Vector3d(-radius_m * rate_rad_s * std::sin(rate_rad_s * t),
                                   radius_m * rate_rad_s * std::cos(rate_rad_s * t), climb_mps);
          },
          [=](double t) {
            const double w2 = rate_rad_s * rate_rad_s;
            return Eigen::Vector3d(-radius_m * w2 * std::cos(rate_rad_s * t), -radius_m * w2 * std::sin(rate_rad_s * t),
                                   0.0);
          }};
}

// The same motion from `at_s` on, plus (t - at_s)^3 * deviation: position, velocity and
// acceleration agree at at_s, so a revision that starts there starts at the predicted state.
inline Motion divergingAt(const Motion& m, double at_s, Eigen::Vector3d deviation) {
  return {[=](double t) { return Eigen::Vector3d(m.p(t) + std::pow(t - at_s, 3) * deviation); },
          [=](double t) { return Eigen::Vector3d(m.v(t) + 3.0 * std::pow(t - at_s, 2) * deviation); },
          [=](double t) { return Eigen::Vector3d(m.a(t) + 6.0 * (t - at_s) * deviation); }};
}

inline double compassHeadingOf(const Eigen::Vector3d& v) {
  double deg = std::atan2(v.x(), v.y()) * 180.0 / M_PI;
  return deg < 0.0 ? deg + 360.0 : deg;
}

struct SampledMotion {
  std::string vehicle = "uav-test";
  std::string plan = "plan-1";
  std::uint32_t revision = 0;
  std::int64_t motion_start_utc_ns = 0;  // t = 0 of the motion
  double from_s = 0.0;                   // first sample (motion time)
  double to_s = 10.0;                    // last sample
  double dt_s = 0.2;
};

inline TrajectoryData sample(const Motion& m, const LocalFrame& frame, const SampledMotion& s) {
  TrajectoryData t;
  t.vehicle_id = s.vehicle;
  t.plan_id = s.plan;
  t.revision = s.revision;
  t.request_id = s.plan + "-request";
  t.created_utc_ns = s.motion_start_utc_ns;
  const int n = static_cast<int>(std::floor((s.to_s - s.from_s) / s.dt_s + 1e-9));
  for (int i = 0; i <= n + 1; ++i) {
    const double time_s = i <= n ? s.from_s + i * s.dt_s : s.to_s;  // the end time always, as the sampler
    if (i == n + 1 && time_s - t.samples.back().t_rel_s - s.from_s < 1e-9) break;
    TrajectorySampleData x;
    x.t_rel_s = time_s - s.from_s;
    x.utc_ns = s.motion_start_utc_ns + static_cast<std::int64_t>(std::llround(time_s * 1e9));
    x.position_enu_m = m.p(time_s);
    x.velocity_enu_mps = m.v(time_s);
    x.acceleration_enu_mps2 = m.a(time_s);
    x.heading_deg = compassHeadingOf(x.velocity_enu_mps);
    x.geo = frame.toGeo(x.position_enu_m);
    t.samples.push_back(x);
  }
  return t;
}

}  // namespace skyroute::testing
