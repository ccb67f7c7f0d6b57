#include "service/trajectory_figure.hpp"

namespace skyroute {

FigureLine trajectoryLine(const TrajectoryData& trajectory, const std::string& label, Rgb colour, double width_px) {
  FigureLine line{label, {}, colour, width_px};
  line.points.reserve(trajectory.samples.size());
  for (const TrajectorySampleData& s : trajectory.samples) line.points.push_back(s.position_enu_m.head<2>());
  return line;
}

FigureProfile trajectoryProfile(const Heightfield& terrain, const TrajectoryData& trajectory) {
  FigureProfile profile;
  double distance_m = 0.0;
  const double up_to_amsl_m = terrain.frame().anchor().alt_amsl_m;  // up is altitude minus the anchor's
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    const Eigen::Vector3d& p = trajectory.samples[i].position_enu_m;
    if (i > 0) distance_m += (p.head<2>() - trajectory.samples[i - 1].position_enu_m.head<2>()).norm();
    profile.distance_m.push_back(distance_m);
    profile.altitude_m.push_back(p.z() + up_to_amsl_m);
    profile.ground_m.push_back(terrain.heightAt(p.x(), p.y()) + up_to_amsl_m);
  }
  return profile;
}

std::vector<Eigen::Vector2d> groundTrack(const std::vector<Eigen::Vector3d>& path_m) {
  std::vector<Eigen::Vector2d> track;
  track.reserve(path_m.size());
  for (const Eigen::Vector3d& p : path_m) track.push_back(p.head<2>());
  return track;
}

}  // namespace skyroute
