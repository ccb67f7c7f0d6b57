// Cyclone DDS configuration that keeps traffic on the loopback interface, for tests, CI and
// demos on one machine. `lo` has no multicast, so Cyclone discovers peers by unicast using
// participant indices; the default MaxAutoParticipantIndex (9) caps a host at about ten
// processes per domain, hence the higher limit.
#pragma once

#include <string>

namespace skyroute::dds {

std::string loopbackConfigXml(int max_auto_participant_index = 32);

// Sets CYCLONEDDS_URI to loopbackConfigXml() (overwriting it). Call before creating the first
// participant of the process; child processes inherit it.
void useLoopbackOnly(int max_auto_participant_index = 32);

}  // namespace skyroute::dds
