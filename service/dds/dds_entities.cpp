#include "service/dds/dds_entities.hpp"

#include "service/dds/dds_security.hpp"

namespace skyroute::dds {

Error ddsError(dds_return_t rc, const std::string& operation) {
  return make_error(ErrorCode::kInternal, operation, operation + " failed: " + dds_strretcode(rc));
}

void EndpointDeleter::operator()(dds_builtintopic_endpoint_t* endpoint) const {
  if (endpoint == nullptr) return;
  dds_delete_qos(endpoint->qos);
  dds_free(endpoint->topic_name);
  dds_free(endpoint->type_name);
  dds_free(endpoint);
}

Endpoint matchedPublication(dds_entity_t reader, dds_instance_handle_t publication) {
  return Endpoint(dds_get_matched_publication_data(reader, publication));
}

void Entity::reset() {
  if (handle_ > 0) {
    // An entity already deleted with its parent reports "already deleted": nothing left to do.
    (void)dds_delete(handle_);
  }
  handle_ = 0;
}

namespace {

Result<Entity> owned(dds_entity_t handle, const char* operation) {
  if (handle < 0) return ddsError(handle, operation);
  return Entity(handle);
}

}  // namespace

Result<Entity> createParticipant(dds_domainid_t domain, const std::string& user_data, const std::string& security_dir) {
  if (user_data.empty() && security_dir.empty()) {
    return owned(dds_create_participant(domain, nullptr, nullptr), "dds_create_participant");
  }
  Qos qos(dds_create_qos());
  if (!user_data.empty()) dds_qset_userdata(qos.get(), user_data.data(), user_data.size());
  if (!security_dir.empty()) {
    if (Status checked = checkSecurityFolder(security_dir); !checked.ok()) return checked.error();
    addSecurityProperties(qos.get(), security_dir);
    const dds_entity_t participant = dds_create_participant(domain, qos.get(), nullptr);
    if (participant < 0) {
      // The files passed their checks: what is left is the plugins' judgement (permissions or
      // governance not signed by permissions_ca.pem, or no grant for this domain or subject).
      return make_error(ErrorCode::kInvalidArgument, security_dir,
                        std::string("DDS Security refused the identity in ") + security_dir + ": " +
                            dds_strretcode(participant) +
                            " (are governance.p7s and permissions.p7s signed by permissions_ca.pem, and do the "
                            "permissions grant this identity's subject and domain " + std::to_string(domain) + "?)");
    }
    return Entity(participant);
  }
  return owned(dds_create_participant(domain, qos.get(), nullptr), "dds_create_participant");
}

Result<Entity> createParticipantReader(dds_entity_t participant) {
  return owned(dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr),
               "dds_create_reader(DCPSParticipant)");
}

Result<Entity> createTopic(dds_entity_t participant, const dds_topic_descriptor_t* descriptor,
                           const std::string& name, const dds_qos_t* qos) {
  return owned(dds_create_topic(participant, descriptor, name.c_str(), qos, nullptr), "dds_create_topic");
}

Result<Entity> createReader(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos) {
  return owned(dds_create_reader(participant, topic, qos, nullptr), "dds_create_reader");
}

Result<Entity> createWriter(dds_entity_t participant, dds_entity_t topic, const dds_qos_t* qos) {
  const dds_entity_t writer = dds_create_writer(participant, topic, qos, nullptr);
  if (writer == DDS_RETCODE_NOT_ALLOWED_BY_SECURITY) {
    char name[256] = "";
    (void)dds_get_name(topic, name, sizeof name);
    return make_error(ErrorCode::kInvalidArgument, std::string("topic ") + name,
                      std::string("DDS Security: this identity's permissions grant no publish on topic '") + name +
                          "' (scripts/make-pki.sh gives that grant to the station identity)");
  }
  return owned(writer, "dds_create_writer");
}

Result<Entity> createWaitset(dds_entity_t participant) {
  return owned(dds_create_waitset(participant), "dds_create_waitset");
}

Result<Entity> createGuardCondition(dds_entity_t participant) {
  return owned(dds_create_guardcondition(participant), "dds_create_guardcondition");
}

Result<Entity> createReadCondition(dds_entity_t reader, uint32_t mask) {
  return owned(dds_create_readcondition(reader, mask), "dds_create_readcondition");
}

}  // namespace skyroute::dds
