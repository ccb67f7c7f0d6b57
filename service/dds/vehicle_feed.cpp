#include "service/dds/vehicle_feed.hpp"

#include "service/dds/loaned_take.hpp"

namespace skyroute::dds {

Result<VehicleFeed> VehicleFeed::create(dds_entity_t participant, std::string vehicle_id) {
  auto trajectories = Reader<TrajectoryData>::create(participant);
  if (!trajectories) return trajectories.error();
  auto heartbeat = Reader<ServiceStatusData>::create(participant);
  if (!heartbeat) return heartbeat.error();
  return VehicleFeed(std::move(vehicle_id), std::move(*trajectories), std::move(*heartbeat));
}

// Disposed instances are taken first, on their own: the typed reader skips samples without data,
// and a dispose arrives as exactly such a sample (its key, the vehicle id, still filled in).
Status VehicleFeed::takeRetractions(Update& update) const {
  constexpr uint32_t kDisposed = DDS_ANY_SAMPLE_STATE | DDS_ANY_VIEW_STATE | DDS_NOT_ALIVE_DISPOSED_INSTANCE_STATE;
  return takeLoaned<skyroute_msgs_Trajectory>(trajectories_.handle(), kDisposed, "skyroute_trajectory",
                                              [&](const skyroute_msgs_Trajectory& key, const dds_sample_info_t&) {
                                                if (key.vehicle_id != nullptr && vehicle_id_ == key.vehicle_id) {
                                                  update.retracted = true;
                                                }
                                              });
}

Result<VehicleFeed::Update> VehicleFeed::take() const {
  Update update;
  if (Status s = takeRetractions(update); !s) return s.error();
  auto taken = trajectories_.takeAvailable(
      [&](TrajectoryData&& t) {
        update.heard_daemon = true;
        if (t.vehicle_id != vehicle_id_) return;
        update.trajectories.push_back(std::move(t));
      },
      [&](const Error& e) { update.rejected.push_back(e); });
  if (!taken) return taken.error();
  auto heard = heartbeat_.takeAvailable([&](ServiceStatusData&&) { update.heard_daemon = true; },
                                        [&](const Error& e) { update.rejected.push_back(e); });
  if (!heard) return heard.error();
  return update;
}

}  // namespace skyroute::dds
