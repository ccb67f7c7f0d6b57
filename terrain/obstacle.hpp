// Obstacles in the ENU frame: sphere, ellipsoid, box or vertical cylinder, either fixed or moving
// back and forth between two points at constant speed (Table 1 of seed 003).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <utility>

#include <Eigen/Core>

namespace skyroute {

enum class ObstacleShape { kSphere, kEllipsoid, kBox, kCylinder };
std::string_view to_string(ObstacleShape shape);

struct BackAndForth {
  Eigen::Vector3d from_m = Eigen::Vector3d::Zero();  // centre at t = start_time_s
  Eigen::Vector3d to_m = Eigen::Vector3d::Zero();
  double speed_mps = 0.0;
  double start_time_s = 0.0;
};

struct Obstacle {
  std::uint64_t id = 0;
  ObstacleShape shape = ObstacleShape::kSphere;
  // Sphere: x = radius. Ellipsoid: semi-axes (east, north, up). Box: half extents.
  // Cylinder (vertical): x = radius, z = half height.
  Eigen::Vector3d size_m = Eigen::Vector3d::Ones();
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  // used when not moving
  std::optional<BackAndForth> motion;

  bool moving() const { return motion.has_value() && motion->speed_mps > 0.0; }
  // Centre at time t_s (seconds on the world clock).
  Eigen::Vector3d centerAt(double t_s) const;
  // The stretch of its track the centre covers during [t0_s, t1_s] (a moving obstacle goes back
  // and forth on one line, so this is one segment: from == to for a fixed obstacle).
  std::pair<Eigen::Vector3d, Eigen::Vector3d> trackDuring(double t0_s, double t1_s) const;
  // Radius of a sphere that contains the shape (for broad-phase tests).
  double boundingRadius() const;
  // Inside test (with the shape grown by margin_m in every direction, conservatively for boxes).
  bool contains(const Eigen::Vector3d& p_m, double t_s, double margin_m = 0.0) const;
};

}  // namespace skyroute
