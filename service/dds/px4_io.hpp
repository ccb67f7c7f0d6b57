// `skyroute px4`'s side of PX4's uXRCE-DDS bridge: the two offboard topics it writes and the
// local-position topic it reads PX4's EKF origin from, with PX4 v1.16's layouts (idl/ros2/
// px4_msgs.idl), best effort, XCDR1. Topic names are ROS 2's: rt/[<namespace>/]fmu/in/... for
// a PX4 started with `uxrce_dds_client start -n <namespace>`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "service/dds/dds_entities.hpp"
#include "service/offboard_follower.hpp"
#include "terrain/local_frame.hpp"

namespace skyroute::dds {

// "rt/" + namespace + "/" + path, or "rt/" + path without a namespace.
std::string px4Topic(const std::string& ros_namespace, const std::string& path);

inline constexpr const char* kPx4SetpointPath = "fmu/in/trajectory_setpoint";
inline constexpr const char* kPx4OffboardModePath = "fmu/in/offboard_control_mode";
inline constexpr const char* kPx4LocalPositionPath = "fmu/out/vehicle_local_position";

class Px4SetpointWriter {
 public:
  static Result<Px4SetpointWriter> create(dds_entity_t participant, const std::string& ros_namespace);

  // OffboardControlMode (position, velocity and acceleration controlled), then the
  // TrajectorySetpoint, both stamped timestamp_us.
  Status write(const OffboardSetpoint& setpoint, std::uint64_t timestamp_us) const;

 private:
  Px4SetpointWriter(Entity mode_topic, Entity mode_writer, Entity setpoint_topic, Entity setpoint_writer)
      : mode_topic_(std::move(mode_topic)),
        mode_writer_(std::move(mode_writer)),
        setpoint_topic_(std::move(setpoint_topic)),
        setpoint_writer_(std::move(setpoint_writer)) {}
  Entity mode_topic_, mode_writer_, setpoint_topic_, setpoint_writer_;  // each topic before its writer
};

class Px4OriginReader {
 public:
  static Result<Px4OriginReader> create(dds_entity_t participant, const std::string& ros_namespace);

  // The EKF origin in the newest sample that has one (xy_global and z_global set, finite
  // ref_lat, ref_lon, ref_alt), or nullopt when none arrived since the last call.
  Result<std::optional<GeoPoint>> takeOrigin() const;

 private:
  Px4OriginReader(Entity topic, Entity reader) : topic_(std::move(topic)), reader_(std::move(reader)) {}
  Entity topic_, reader_;
};

}  // namespace skyroute::dds
