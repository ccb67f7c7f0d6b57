#include "service/trajectory_frame.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace skyroute {

Result<LocalFrame> recoverTrajectoryFrame(const TrajectoryData& trajectory, double tolerance_m) {
  const auto& samples = trajectory.samples;
  if (samples.empty()) return make_error(ErrorCode::kInvalidArgument, "samples", "a trajectory without samples has no frame");
  // The sample nearest the anchor: there the projection is closest to a plain shift.
  std::size_t base = 0;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    if (samples[i].position_enu_m.head<2>().norm() < samples[base].position_enu_m.head<2>().norm()) base = i;
  }
  const TrajectorySampleData& s = samples[base];
  const double anchor_alt_m = s.geo.alt_amsl_m - s.position_enu_m.z();
  const Eigen::Vector3d target(s.position_enu_m.x(), s.position_enu_m.y(), 0.0);

  // First guess: the point at -p from the sample. Then move the anchor by the residual until the
  // sample lands on its ENU position. The move is converted to degrees on a sphere, not through
  // the frame: PROJ maps points within a millimetre of a projection's centre onto the centre.
  // The sphere's error (under 1 %) only slows the convergence down a little.
  constexpr double kMetresPerDegree = 6371000.0 * M_PI / 180.0;
  auto frame = LocalFrame::create(s.geo.lat_deg, s.geo.lon_deg, anchor_alt_m);
  if (!frame.ok()) return frame.error();
  GeoPoint anchor = frame->toGeo(-target);
  for (int iteration = 0; iteration < 20; ++iteration) {
    frame = LocalFrame::create(anchor.lat_deg, anchor.lon_deg, anchor_alt_m);
    if (!frame.ok()) return frame.error();
    const Eigen::Vector3d residual = frame->toEnu(s.geo) - s.position_enu_m;
    if (residual.head<2>().norm() < 1e-7) break;
    anchor.lat_deg += residual.y() / kMetresPerDegree;
    anchor.lon_deg += residual.x() / (kMetresPerDegree * std::cos(anchor.lat_deg * M_PI / 180.0));
  }

  // Every sample against the frame, in one bulk transform (one per sample costs milliseconds).
  std::vector<double> east(samples.size()), north(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    east[i] = samples[i].geo.lon_deg;
    north[i] = samples[i].geo.lat_deg;
  }
  frame->lonLatToEastNorth(east.data(), north.data(), samples.size());
  double worst_m = 0.0;
  std::size_t worst = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3d enu(east[i], north[i], samples[i].geo.alt_amsl_m - anchor_alt_m);
    const double r = (enu - samples[i].position_enu_m).norm();
    if (!(r <= worst_m)) {
      worst_m = r;
      worst = i;
    }
  }
  if (!(worst_m <= tolerance_m)) {
    return make_error(ErrorCode::kInvalidArgument, "samples[" + std::to_string(worst) + "]",
                      "the samples' ENU and WGS84 positions do not fit one local frame: " + std::to_string(worst_m) +
                          " m off at samples[" + std::to_string(worst) + "]");
  }
  return frame;
}

}  // namespace skyroute
