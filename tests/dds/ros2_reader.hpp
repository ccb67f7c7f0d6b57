// A ROS 2 subscriber without ROS 2: a Cyclone reader set up the way ROS 2's Cyclone RMW sets one
// up for a latched topic (rt/ topic name, the ROS type name, no type information, XCDR1 only,
// reliable, transient-local, keep-last 1), copying what arrives into plain values.
#pragma once

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>

#include "geographic_msgs.h"
#include "nav_msgs.h"
#include "service/dds/loaned_take.hpp"

namespace skyroute::testing {

struct RosPose {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string frame_id;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector4d orientation = Eigen::Vector4d::Zero();  // x, y, z, w
};

struct RosPathCopy {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string frame_id;
  std::vector<RosPose> poses;
};

inline RosPathCopy copyOf(const nav_msgs_msg_dds__Path_& p) {
  RosPathCopy out{p.header.stamp.sec, p.header.stamp.nanosec, p.header.frame_id ? p.header.frame_id : "", {}};
  for (std::uint32_t i = 0; i < p.poses._length; ++i) {
    const auto& s = p.poses._buffer[i];
    const auto& q = s.pose.orientation;
    out.poses.push_back({s.header.stamp.sec, s.header.stamp.nanosec, s.header.frame_id ? s.header.frame_id : "",
                         {s.pose.position.x, s.pose.position.y, s.pose.position.z}, {q.x, q.y, q.z, q.w}});
  }
  return out;
}
inline geographic_msgs_msg_dds__GeoPoint_ copyOf(const geographic_msgs_msg_dds__GeoPoint_& p) { return p; }

template <class Wire>
class RmwLikeReader {
 public:
  RmwLikeReader(dds_entity_t participant, const dds_topic_descriptor_t* descriptor, const std::string& topic_name) {
    dds::Qos qos(dds_create_qos());
    dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(qos.get(), 1, &xcdr1);
    topic_ = dds::Entity(dds_create_topic(participant, descriptor, topic_name.c_str(), qos.get(), nullptr));
    reader_ = dds::Entity(dds_create_reader(participant, topic_.get(), qos.get(), nullptr));
  }
  bool ok() const { return topic_.valid() && reader_.valid(); }
  dds_entity_t topic() const { return topic_.get(); }
  dds_entity_t reader() const { return reader_.get(); }

  // The latest sample that arrives within timeout_s (polled every 10 ms), or nullopt.
  auto waitLatest(double timeout_s) {
    using Copy = decltype(copyOf(std::declval<const Wire&>()));
    std::optional<Copy> latest;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      (void)dds::takeLoaned<Wire>(reader_.get(), DDS_ANY_STATE, "rmw-like reader",
                                  [&](const Wire& w, const dds_sample_info_t& info) {
                                    if (info.valid_data) latest = copyOf(w);
                                  });
      if (latest) return latest;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return latest;
  }

 private:
  dds::Entity topic_;  // declared first: destroyed after the reader
  dds::Entity reader_;
};

// ENU yaw (counter-clockwise from east) of a unit quaternion that only turns about z.
inline double yawOf(const Eigen::Vector4d& q) { return 2.0 * std::atan2(q(2), q(3)); }

}  // namespace skyroute::testing
