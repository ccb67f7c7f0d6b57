#include "terrain/obstacle.hpp"

#include <algorithm>
#include <cmath>

namespace skyroute {

std::string_view to_string(ObstacleShape shape) {
  switch (shape) {
    case ObstacleShape::kSphere: return "sphere";
    case ObstacleShape::kEllipsoid: return "ellipsoid";
    case ObstacleShape::kBox: return "box";
    case ObstacleShape::kCylinder: return "cylinder";
  }
  return "unknown";
}

Eigen::Vector3d Obstacle::centerAt(double t_s) const {
  if (!moving()) return motion ? motion->from_m : center_m;
  const Eigen::Vector3d leg = motion->to_m - motion->from_m;
  const double length = leg.norm();
  if (length <= 0.0) return motion->from_m;
  // Triangle wave: from -> to -> from -> ..., one leg every length / speed seconds.
  const double travelled = std::max(0.0, t_s - motion->start_time_s) * motion->speed_mps;
  const double phase = std::fmod(travelled, 2.0 * length);
  const double along = phase <= length ? phase : 2.0 * length - phase;
  return motion->from_m + leg * (along / length);
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> Obstacle::trackDuring(double t0_s, double t1_s) const {
  if (!moving()) {
    const Eigen::Vector3d c = centerAt(t0_s);
    return {c, c};
  }
  const Eigen::Vector3d leg = motion->to_m - motion->from_m;
  const double length = leg.norm();
  if (length <= 0.0) return {motion->from_m, motion->from_m};
  // Unfolded distance travelled; the centre turns round at every multiple of the track length.
  const double u0 = std::max(0.0, t0_s - motion->start_time_s) * motion->speed_mps;
  const double u1 = std::max(0.0, t1_s - motion->start_time_s) * motion->speed_mps;
  // Two track lengths cover the whole track. Past 2^52 lengths a double no longer holds the phase
  // (and k += 1 below would stop changing k: the count of turns never ended): the whole track too.
  if (!(u1 - u0 < 2.0 * length) || !(u1 / length < 0x1p52)) return {motion->from_m, motion->to_m};
  auto along = [&](double u) {
    const double phase = std::fmod(u, 2.0 * length);
    return phase <= length ? phase : 2.0 * length - phase;
  };
  double lo = std::min(along(u0), along(u1));
  double hi = std::max(along(u0), along(u1));
  for (double k = std::floor(u0 / length) + 1.0; k * length < u1; k += 1.0) {  // turning points
    const double turn = std::fmod(k, 2.0) == 1.0 ? length : 0.0;
    lo = std::min(lo, turn);
    hi = std::max(hi, turn);
    if (hi - lo >= length) break;
  }
  const Eigen::Vector3d dir = leg / length;
  return {motion->from_m + lo * dir, motion->from_m + hi * dir};
}

double Obstacle::boundingRadius() const {
  switch (shape) {
    case ObstacleShape::kSphere: return size_m.x();
    case ObstacleShape::kEllipsoid: return size_m.maxCoeff();
    case ObstacleShape::kBox: return size_m.norm();
    case ObstacleShape::kCylinder: return std::hypot(size_m.x(), size_m.z());
  }
  return size_m.norm();
}

bool Obstacle::contains(const Eigen::Vector3d& p_m, double t_s, double margin_m) const {
  const Eigen::Vector3d d = p_m - centerAt(t_s);
  switch (shape) {
    case ObstacleShape::kSphere: return d.norm() <= size_m.x() + margin_m;
    case ObstacleShape::kEllipsoid: {
      // The ellipsoid with every semi-axis grown by the margin contains the true offset surface.
      const Eigen::Vector3d axes = size_m.array() + margin_m;
      return (d.array() / axes.array()).matrix().squaredNorm() <= 1.0;
    }
    case ObstacleShape::kBox: {
      const Eigen::Vector3d outside = (d.cwiseAbs() - size_m).cwiseMax(0.0);
      return outside.norm() <= margin_m;
    }
    case ObstacleShape::kCylinder: {
      const double radial = std::max(0.0, d.head<2>().norm() - size_m.x());
      const double vertical = std::max(0.0, std::abs(d.z()) - size_m.z());
      return std::hypot(radial, vertical) <= margin_m;
    }
  }
  return false;
}

}  // namespace skyroute
