#include "service/dds/qos.hpp"

namespace skyroute::dds {

namespace {

Qos lastValuePerKey() {
  Qos qos(dds_create_qos());
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
  // service_cleanup_delay 0, keep-last 1, no sample or instance limits.
  dds_qset_durability_service(qos.get(), 0, DDS_HISTORY_KEEP_LAST, 1, DDS_LENGTH_UNLIMITED,
                              DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  dds_qset_writer_data_lifecycle(qos.get(), false);
  return qos;
}

Qos latestBestEffort() {
  Qos qos(dds_create_qos());
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
  return qos;
}

Qos exclusive(Qos qos) {
  dds_qset_ownership(qos.get(), DDS_OWNERSHIP_EXCLUSIVE);
  return qos;
}

void onlyXcdr1(dds_qos_t* qos) {
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
}

}  // namespace

Qos trajectoryQos() { return exclusive(lastValuePerKey()); }

Qos obstacleQos() { return lastValuePerKey(); }

Qos commandQos(double max_blocking_s) {
  Qos qos(dds_create_qos());
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, static_cast<dds_duration_t>(max_blocking_s * 1e9));
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_ALL, 0);
  return qos;
}

Qos statusQos() {
  Qos qos = exclusive(commandQos());
  dds_qset_writer_data_lifecycle(qos.get(), false);
  return qos;
}

Qos heartbeatQos() {
  Qos qos = exclusive(latestBestEffort());
  dds_qset_writer_data_lifecycle(qos.get(), false);
  return qos;
}

void applyOwnedWriterQos(dds_qos_t* qos, const OwnedWriterOptions& options) {
  dds_qset_ownership_strength(qos, options.ownership_strength);
  dds_qset_liveliness(qos, DDS_LIVELINESS_AUTOMATIC, static_cast<dds_duration_t>(options.liveliness_lease_s * 1e9));
}

Qos rosLatchedQos() {
  Qos qos = lastValuePerKey();
  onlyXcdr1(qos.get());
  return qos;
}

Qos px4StreamQos() {
  Qos qos = latestBestEffort();
  onlyXcdr1(qos.get());
  return qos;
}

}  // namespace skyroute::dds
