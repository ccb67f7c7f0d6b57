// The daemon's ROS 2 mirror: each vehicle's current trajectory as ROS 2 topics a plain ROS 2 node
// subscribes to (no bridge, no ROS 2 on our side), in the daemon's local ENU frame:
//   rt/skyroute/<name>/path    nav_msgs/msg/Path (frame "map", every pose stamped)
//   rt/skyroute/<name>/origin  geographic_msgs/msg/GeoPoint: where x = y = z = 0 is (altitude
//                              above the WGS 84 ellipsoid, as GeoPoint defines it)
// both latched (reliable, transient-local, keep-last 1, durability-service keep-last 1, no
// auto-dispose) and written in XCDR1, with types that carry no type information: what ROS 2's
// Cyclone RMW expects. <name> is the vehicle id as a ROS name (service/ros_names.hpp). A retracted
// trajectory becomes an empty path. Thread-safe: the engine publishes from several threads.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "service/dds/dds_entities.hpp"
#include "service/mission_types.hpp"
#include "service/ros_names.hpp"
#include "terrain/local_frame.hpp"

namespace skyroute::dds {

class Ros2Mirror {
 public:
  // frame_origin: the daemon's local frame anchor (altitude AMSL). Its ellipsoidal altitude comes
  // from the EGM96 grid; without the grid it is NaN (GeoPoint's "unknown") and a warning says so.
  // The participant must outlive the mirror.
  static std::unique_ptr<Ros2Mirror> create(dds_entity_t participant, const GeoPoint& frame_origin);

  void publish(const TrajectoryData& trajectory);
  void retract(const std::string& vehicle_id);
  // Waits until readers acknowledged what was written (on stop), at most timeout_s per writer.
  void flush(double timeout_s);

  static std::string pathTopic(const std::string& ros_name) { return "rt/skyroute/" + ros_name + "/path"; }
  static std::string originTopic(const std::string& ros_name) { return "rt/skyroute/" + ros_name + "/origin"; }

 private:
  struct Writers {
    Entity path_topic, path_writer, origin_topic, origin_writer;  // topics first: destroyed last
  };
  struct Vehicle {
    std::optional<Writers> writers;
    TrajectoryData last;  // what its path shows (no samples once retracted)
  };

  Ros2Mirror(dds_entity_t participant, const GeoPoint& frame_origin, double origin_alt_ellipsoid_m);
  Writers* writersOf(const std::string& vehicle_id, const std::string& name);
  void write(const std::string& vehicle_id, Vehicle& vehicle);

  dds_entity_t participant_;
  GeoPoint frame_origin_;
  double origin_alt_ellipsoid_m_;
  std::mutex mutex_;
  RosNameRegistry names_;
  std::map<std::string, Vehicle> vehicles_;
};

}  // namespace skyroute::dds
