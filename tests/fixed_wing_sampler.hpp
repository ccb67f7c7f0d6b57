// An independent check of a published trajectory against a fixed wing's limits, from the sample
// positions alone (central differences over equally spaced samples; nothing from the planner's
// polynomials or its feasibility check): airspeed within [minimum, maximum], the bank angle of
// the coordinated turn that flies the horizontal curvature, atan(a_across / g), within the
// largest bank, the flight path angle within the climb and descent angles, and the height above
// the ground within the clearance. Used by the engine test and the daemon's end-to-end test.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "service/mission_types.hpp"

namespace skyroute::testing {

struct FixedWingEnvelope {
  double min_airspeed_mps = 0.0;
  double max_speed_mps = 0.0;
  double max_bank_deg = 0.0;
  double max_climb_angle_deg = 0.0;
  double max_descent_angle_deg = 0.0;
  double min_clearance_m = 0.0;
};

struct FixedWingFlight {
  double min_speed_mps = std::numeric_limits<double>::infinity();
  double max_speed_mps = 0.0;
  double max_bank_deg = 0.0;
  double max_climb_angle_deg = 0.0;
  double max_descent_angle_deg = 0.0;
  double min_clearance_m = std::numeric_limits<double>::infinity();
  std::size_t checked = 0;               // samples whose neighbours are equally spaced
  std::vector<std::string> violations;   // "bank_angle 41.2 deg at t=12.3 s", first few of each kind
};

// ground_m(east, north): the terrain height there (AMSL, the samples' frame). tolerance: a
// relative slack on every limit for the differences' own error.
inline FixedWingFlight sampleFixedWing(const TrajectoryData& t, const FixedWingEnvelope& e,
                                       const std::function<double(double, double)>& ground_m,
                                       double tolerance = 0.01) {
  constexpr double kG = 9.80665;
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  FixedWingFlight f;
  std::vector<std::string> kinds;
  auto flag = [&](const std::string& kind, double value, const char* unit, double time_s) {
    if (std::count(kinds.begin(), kinds.end(), kind) >= 3) return;
    kinds.push_back(kind);
    f.violations.push_back(kind + " " + std::to_string(value) + " " + unit + " at t=" + std::to_string(time_s) + " s");
  };
  const auto& s = t.samples;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d& p = s[i].position_enu_m;
    const double clearance = p.z() - ground_m(p.x(), p.y());
    f.min_clearance_m = std::min(f.min_clearance_m, clearance);
    if (clearance < e.min_clearance_m * (1.0 - tolerance)) flag("clearance", clearance, "m", s[i].t_rel_s);
    if (i == 0 || i + 1 >= s.size()) continue;
    const double h0 = s[i].t_rel_s - s[i - 1].t_rel_s;
    const double h1 = s[i + 1].t_rel_s - s[i].t_rel_s;
    if (h0 <= 0.0 || std::abs(h1 - h0) > 1e-9 * std::max(1.0, h0)) continue;
    ++f.checked;
    const Eigen::Vector3d v = (s[i + 1].position_enu_m - s[i - 1].position_enu_m) / (2.0 * h0);
    const Eigen::Vector3d a = (s[i + 1].position_enu_m - 2.0 * p + s[i - 1].position_enu_m) / (h0 * h0);
    const double speed = v.norm();
    const double horizontal = std::hypot(v.x(), v.y());
    const double across = horizontal > 0.0 ? std::abs(v.x() * a.y() - v.y() * a.x()) / horizontal : 0.0;
    const double bank = std::atan2(across, kG) * kDeg;
    const double path = std::atan2(v.z(), horizontal) * kDeg;
    const double time = s[i].t_rel_s;
    f.min_speed_mps = std::min(f.min_speed_mps, speed);
    f.max_speed_mps = std::max(f.max_speed_mps, speed);
    f.max_bank_deg = std::max(f.max_bank_deg, bank);
    f.max_climb_angle_deg = std::max(f.max_climb_angle_deg, path);
    f.max_descent_angle_deg = std::max(f.max_descent_angle_deg, -path);
    if (speed < e.min_airspeed_mps * (1.0 - tolerance)) flag("below_min_airspeed", speed, "m/s", time);
    if (speed > e.max_speed_mps * (1.0 + tolerance)) flag("over_max_speed", speed, "m/s", time);
    if (bank > e.max_bank_deg * (1.0 + tolerance)) flag("bank_angle", bank, "deg", time);
    if (path > e.max_climb_angle_deg * (1.0 + tolerance)) flag("climb_angle", path, "deg", time);
    if (-path > e.max_descent_angle_deg * (1.0 + tolerance)) flag("descent_angle", -path, "deg", time);
  }
  return f;
}

// The envelope of a request's limits (every fixed-wing value given in the request).
// The fixed wing of the service and end-to-end tests: 25 m/s cruise, stall 15 m/s x 1.3, bank
// 35 degrees, path angles 15 degrees.
inline VehicleLimitsData fixedWingTestLimits() {
  VehicleLimitsData l;
  l.model = VehicleModel::kFixedWing;
  l.v_ref_mps = 25.0;
  l.max_speed_mps = 35.0;
  l.max_accel_mps2 = 10.0;
  l.max_climb_rate_mps = 8.0;
  l.max_descent_rate_mps = 8.0;
  l.stall_speed_mps = 15.0;
  l.stall_margin = 1.3;
  l.max_bank_deg = 35.0;
  l.max_climb_angle_deg = 15.0;
  l.max_descent_angle_deg = 15.0;
  return l;
}

inline FixedWingEnvelope envelopeOf(const VehicleLimitsData& l) {
  return FixedWingEnvelope{l.stall_speed_mps * l.stall_margin, l.max_speed_mps,       l.max_bank_deg,
                           l.max_climb_angle_deg,              l.max_descent_angle_deg, l.min_clearance_agl_m};
}

inline std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

}  // namespace skyroute::testing
