// PX4 as `skyroute px4` meets it over DDS, for the end-to-end tests: readers of
// rt/[ns/]fmu/in/trajectory_setpoint and offboard_control_mode with PX4 v1.16's layouts (best
// effort, XCDR1, every sample kept with its arrival time), and a writer of
// rt/[ns/]fmu/out/vehicle_local_position that tells the EKF origin, as PX4's bridge does.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "px4_msgs.h"
#include "service/dds/loaned_take.hpp"
#include "service/dds/px4_io.hpp"

namespace skyroute::testing {

struct ReceivedSetpoint {
  std::chrono::steady_clock::time_point received;
  std::uint64_t timestamp_us = 0;
  Eigen::Vector3d position, velocity, acceleration;  // NED, as sent (float32)
  double yaw = 0.0;
};

struct ReceivedMode {
  std::uint64_t timestamp_us = 0;
  bool position = false, velocity = false, acceleration = false, attitude = false, body_rate = false,
       thrust_and_torque = false, direct_actuator = false;
};

class FakePx4 {
 public:
  static std::unique_ptr<FakePx4> open(int domain, const std::string& ros_namespace) {
    auto px4 = std::unique_ptr<FakePx4>(new FakePx4);
    auto p = dds::createParticipant(domain);
    if (!p.ok()) return nullptr;
    px4->participant_ = std::move(*p);
    const dds_entity_t pp = px4->participant_.get();
    dds::Qos qos(dds_create_qos());
    dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
    dds_qset_history(qos.get(), DDS_HISTORY_KEEP_ALL, 0);  // the test sees every setpoint
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(qos.get(), 1, &xcdr1);
    auto make = [&](const dds_topic_descriptor_t* d, const char* path, dds::Entity& topic, dds::Entity& endpoint,
                    bool reader) {
      topic = dds::Entity(dds_create_topic(pp, d, dds::px4Topic(ros_namespace, path).c_str(), qos.get(), nullptr));
      endpoint = dds::Entity(reader ? dds_create_reader(pp, topic.get(), qos.get(), nullptr)
                                    : dds_create_writer(pp, topic.get(), qos.get(), nullptr));
      return topic.valid() && endpoint.valid();
    };
    if (!make(&px4_msgs_msg_dds__TrajectorySetpoint__desc, dds::kPx4SetpointPath, px4->setpoint_topic_,
              px4->setpoint_reader_, true) ||
        !make(&px4_msgs_msg_dds__OffboardControlMode__desc, dds::kPx4OffboardModePath, px4->mode_topic_,
              px4->mode_reader_, true) ||
        !make(&px4_msgs_msg_dds__VehicleLocalPosition__desc, dds::kPx4LocalPositionPath, px4->position_topic_,
              px4->position_writer_, false)) {
      return nullptr;
    }
    return px4;
  }

  // Takes what arrived (call often: arrival times are taken here).
  void poll() {
    const auto now = std::chrono::steady_clock::now();
    takeAll<px4_msgs_msg_dds__TrajectorySetpoint_>(setpoint_reader_.get(), [&](const auto& s) {
      setpoints.push_back({now, s.timestamp, Eigen::Vector3d(s.position[0], s.position[1], s.position[2]),
                           Eigen::Vector3d(s.velocity[0], s.velocity[1], s.velocity[2]),
                           Eigen::Vector3d(s.acceleration[0], s.acceleration[1], s.acceleration[2]), s.yaw});
    });
    takeAll<px4_msgs_msg_dds__OffboardControlMode_>(mode_reader_.get(), [&](const auto& m) {
      modes.push_back({m.timestamp, m.position, m.velocity, m.acceleration, m.attitude, m.body_rate,
                       m.thrust_and_torque, m.direct_actuator});
    });
  }

  // One VehicleLocalPosition whose EKF origin is set (ref_lat, ref_lon, ref_alt AMSL).
  bool tellOrigin(double lat_deg, double lon_deg, float alt_amsl_m) const {
    px4_msgs_msg_dds__VehicleLocalPosition_ p{};
    p.xy_valid = p.z_valid = true;
    p.xy_global = p.z_global = true;
    p.ref_lat = lat_deg;
    p.ref_lon = lon_deg;
    p.ref_alt = alt_amsl_m;
    p.heading = 0.5f;  // non-zero neighbours: a layout slip would show in ref_*
    p.dist_bottom = 12.0f;
    return dds_write(position_writer_.get(), &p) == DDS_RETCODE_OK;
  }

  std::vector<ReceivedSetpoint> setpoints;
  std::vector<ReceivedMode> modes;

 private:
  FakePx4() = default;
  template <class Wire, class F>
  static void takeAll(dds_entity_t reader, F&& on) {
    (void)dds::takeLoaned<Wire>(reader, DDS_ANY_STATE, "fake px4", [&](const Wire& w, const dds_sample_info_t& info) {
      if (info.valid_data) on(w);
    });
  }

  dds::Entity participant_;
  dds::Entity setpoint_topic_, setpoint_reader_, mode_topic_, mode_reader_, position_topic_, position_writer_;
};

}  // namespace skyroute::testing
