#include "service/trajectory_data.hpp"

#include <cmath>

#include "service/geo_samples.hpp"

namespace skyroute {

std::size_t sampleCount(double duration_s, double dt_s) {
  if (!(duration_s >= 0.0) || !(dt_s > 0.0)) return 1;
  const double steps = std::floor(duration_s / dt_s + 1e-9);
  // Saturates instead of overflowing: the caller compares it with a bound far below this.
  if (!(steps < 1e15)) return static_cast<std::size_t>(1e15);
  return static_cast<std::size_t>(steps) + 2;
}

TrajectoryData toTrajectoryData(const Trajectory& trajectory, const LocalFrame& frame, double dt_s,
                                std::int64_t start_utc_ns, const TrajectoryIdentity& identity) {
  TrajectoryData data;
  data.vehicle_id = identity.vehicle_id;
  data.plan_id = identity.plan_id;
  data.revision = identity.revision;
  data.request_id = identity.request_id;
  data.created_utc_ns = utcNowNs();
  const std::vector<GeoSample> samples = toGeoSamples(trajectory.sample(dt_s), frame);
  data.samples.reserve(samples.size());
  for (const GeoSample& s : samples) {
    TrajectorySampleData out;
    out.t_rel_s = s.state.time_s;
    out.utc_ns = start_utc_ns + static_cast<std::int64_t>(std::llround(s.state.time_s * 1e9));
    out.position_enu_m = s.state.position_m;
    out.velocity_enu_mps = s.state.velocity_mps;
    out.acceleration_enu_mps2 = s.state.acceleration_mps2;
    out.heading_deg = s.state.heading_deg;
    out.geo = GeoPoint{s.lat_deg, s.lon_deg, s.alt_amsl_m};
    data.samples.push_back(out);
  }
  return data;
}

}  // namespace skyroute
