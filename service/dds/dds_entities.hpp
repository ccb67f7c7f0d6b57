// RAII owners of Cyclone DDS entities and QoS objects, and the turning of a DDS return code into
// the project's Error (with dds_strretcode's text). Creation follows the Cyclone examples:
// participant -> topic -> reader/writer in a straight line, every return code checked.
// Deleting a participant deletes everything under it; each owner deletes only its own entity, so
// owners must be destroyed children first (declare them parent first).
#pragma once

#include <memory>
#include <string>

#include <dds/dds.h>

#include "planning/core/result.hpp"

namespace skyroute::dds {

// Error for a failed DDS call: code kInternal, field = the operation, message with strretcode.
Error ddsError(dds_return_t rc, const std::string& operation);

// Owns one entity handle; dds_delete on destruction. Move-only.
class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity() { reset(); }
  Entity(Entity&& other) noexcept : handle_(other.release()) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = other.release();
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  dds_entity_t get() const { return handle_; }
  bool valid() const { return handle_ > 0; }
  dds_entity_t release() {
    dds_entity_t h = handle_;
    handle_ = 0;
    return h;
  }
  void reset();

 private:
  dds_entity_t handle_ = 0;
};

struct QosDeleter {
  void operator()(dds_qos_t* qos) const { dds_delete_qos(qos); }
};
using Qos = std::unique_ptr<dds_qos_t, QosDeleter>;

// A matched endpoint's discovery data (dds_get_matched_publication_data), freed as
// dds_builtintopic_free_endpoint does (that function is not declared in Cyclone 0.10's headers).
struct EndpointDeleter {
  void operator()(dds_builtintopic_endpoint_t* endpoint) const;
};
using Endpoint = std::unique_ptr<dds_builtintopic_endpoint_t, EndpointDeleter>;
// The writer behind `publication` as `reader` sees it; null when it is no longer matched.
Endpoint matchedPublication(dds_entity_t reader, dds_instance_handle_t publication);

// Each returns the owned entity or an Error naming the operation and Cyclone's reason.
// user_data: the participant's USER_DATA QoS, which every other participant on the domain reads at
// discovery (the daemon names its instance there). security_dir: an identity folder
// (service/dds/dds_security.hpp), checked before use; empty for an unsecured participant.
Result<Entity> createParticipant(dds_domainid_t domain, const std::string& user_data = "",
                                 const std::string& security_dir = "");
// A reader of the built-in DCPSParticipant topic: every participant discovered on the domain.
Result<Entity> createParticipantReader(dds_entity_t participant);
Result<Entity> createTopic(dds_entity_t participant, const dds_topic_descriptor_t* descriptor,
                           const std::string& name, const dds_qos_t* qos);
Result<Entity> createReader(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos);
// Refused by DDS Security: the error names the topic the identity's permissions do not grant.
Result<Entity> createWriter(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos);
Result<Entity> createWaitset(dds_entity_t participant);
Result<Entity> createGuardCondition(dds_entity_t participant);
Result<Entity> createReadCondition(dds_entity_t reader, uint32_t mask);

}  // namespace skyroute::dds
