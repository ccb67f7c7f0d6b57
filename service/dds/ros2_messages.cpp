#include "service/dds/ros2_messages.hpp"

#include <cmath>

namespace skyroute::dds {

namespace {
// The serializer only reads the frame_id; the IDL's C mapping has no const char*.
char* mapFrame() { return const_cast<char*>(kRosMapFrame); }
}  // namespace

builtin_interfaces_msg_dds__Time_ toRosTime(std::int64_t utc_ns) {
  constexpr std::int64_t kNsPerS = 1000000000;
  std::int64_t sec = utc_ns / kNsPerS;
  std::int64_t nanosec = utc_ns % kNsPerS;
  if (nanosec < 0) {  // ROS keeps nanosec in [0, 1e9) also before the epoch
    nanosec += kNsPerS;
    sec -= 1;
  }
  return {static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nanosec)};
}

geometry_msgs_msg_dds__Quaternion_ headingQuaternion(double heading_deg) {
  const double yaw_enu_rad = M_PI / 2.0 - heading_deg * M_PI / 180.0;
  return {0.0, 0.0, std::sin(yaw_enu_rad / 2.0), std::cos(yaw_enu_rad / 2.0)};
}

RosPath::RosPath(const TrajectoryData& trajectory) {
  poses_.reserve(trajectory.samples.size());
  for (const TrajectorySampleData& s : trajectory.samples) {
    geometry_msgs_msg_dds__PoseStamped_ pose{};
    pose.header.stamp = toRosTime(s.utc_ns);
    pose.header.frame_id = mapFrame();
    pose.pose.position = {s.position_enu_m.x(), s.position_enu_m.y(), s.position_enu_m.z()};
    pose.pose.orientation = headingQuaternion(s.heading_deg);
    poses_.push_back(pose);
  }
  msg_.header.stamp = toRosTime(trajectory.created_utc_ns != 0 ? trajectory.created_utc_ns : utcNowNs());
  msg_.header.frame_id = mapFrame();
  msg_.poses._maximum = static_cast<std::uint32_t>(poses_.size());
  msg_.poses._length = static_cast<std::uint32_t>(poses_.size());
  msg_.poses._buffer = poses_.data();
  msg_.poses._release = false;
}

}  // namespace skyroute::dds
