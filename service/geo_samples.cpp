#include "service/geo_samples.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace skyroute {

std::vector<GeoSample> toGeoSamples(const std::vector<TrajectoryState>& samples, const LocalFrame& frame) {
  std::vector<double> x(samples.size()), y(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    x[i] = samples[i].position_m.x();
    y[i] = samples[i].position_m.y();
  }
  if (!samples.empty()) frame.eastNorthToLonLat(x.data(), y.data(), samples.size());
  std::vector<GeoSample> out(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    out[i].state = samples[i];
    out[i].lon_deg = x[i];
    out[i].lat_deg = y[i];
    out[i].alt_amsl_m = samples[i].position_m.z() + frame.anchor().alt_amsl_m;
  }
  return out;
}

namespace {

// A column of guessed heights would be worse than no file: the ellipsoid is up to 100 m off AMSL.
Status checkEllipsoidHeights(const std::vector<GeoSample>& samples) {
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (!std::isfinite(samples[i].alt_ellipsoid_m))
      return make_error(ErrorCode::kInvalidArgument, "samples[" + std::to_string(i) + "].alt_ellipsoid_m",
                        "the ellipsoidal height is unknown: convert the heights with the geoid first");
  return Status::success();
}

}  // namespace

Status writeTrajectoryCsv(std::ostream& out, const std::vector<GeoSample>& samples) {
  if (Status known = checkEllipsoidHeights(samples); !known.ok()) return known;
  out << kTrajectoryCsvHeader << '\n';
  char line[768];
  for (const GeoSample& g : samples) {
    const TrajectoryState& s = g.state;
    // 9 decimals of a degree is ~0.1 mm; metres to the millimetre, rates to 1e-4.
    std::snprintf(line, sizeof(line),
                  "%.4f,%.9f,%.9f,%.3f,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f\n",
                  s.time_s, g.lat_deg, g.lon_deg, g.alt_amsl_m, s.position_m.x(), s.position_m.y(), s.position_m.z(),
                  s.velocity_mps.x(), s.velocity_mps.y(), s.velocity_mps.z(), s.heading_deg,
                  s.acceleration_mps2.x(), s.acceleration_mps2.y(), s.acceleration_mps2.z(), s.jerk_mps3.x(),
                  s.jerk_mps3.y(), s.jerk_mps3.z(), s.velocity_mps.norm(), g.alt_ellipsoid_m);
    out << line;
  }
  return Status::success();
}

Status writeTrajectoryCsv(const std::string& path, const std::vector<GeoSample>& samples) {
  if (Status known = checkEllipsoidHeights(samples); !known.ok()) return known;
  std::ofstream file(path);
  if (!file) return make_error(ErrorCode::kFileNotFound, path, "cannot open the trajectory CSV for writing");
  if (Status written = writeTrajectoryCsv(file, samples); !written.ok()) return written;
  file.flush();
  if (!file) return make_error(ErrorCode::kFileNotFound, path, "writing the trajectory CSV failed");
  return Status::success();
}

}  // namespace skyroute
