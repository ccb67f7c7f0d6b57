// DDS Security for a participant: the folder of one identity, as scripts/make-pki.sh makes it
// (identity_ca.pem, identity.pem, identity.key, permissions_ca.pem, governance.p7s,
// permissions.p7s), turned into the participant properties that load Cyclone's authentication,
// access-control and cryptography plugins. The folder is checked first, so that a bad identity
// gets an error naming the file and the reason rather than a bare "error" from the participant.
#pragma once

#include <string>

#include <dds/dds.h>

#include "planning/core/result.hpp"

namespace skyroute::dds {

// Every file of an identity folder, in the order they are checked.
extern const char* const kSecurityFiles[6];

// A missing or unreadable file; a certificate expired, not yet valid, or not signed by its CA
// (identity_ca.pem, permissions_ca.pem); a key that does not belong to identity.pem. The error's
// field is the file's path. kInvalidArgument.
Status checkSecurityFolder(const std::string& dir);

// The plugins and the folder's files as properties of a participant's QoS.
void addSecurityProperties(dds_qos_t* qos, const std::string& dir);

}  // namespace skyroute::dds
