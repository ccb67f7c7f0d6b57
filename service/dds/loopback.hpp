// Cyclone DDS configuration that keeps traffic on the loopback interface, for tests, CI and
// demos on one machine. `lo` has no multicast, so Cyclone discovers peers by unicast using
// participant indices: each process on a domain takes the lowest free index, and discovery
// probes the ports of every index up to MaxAutoParticipantIndex. So it bounds the processes per
// domain per host (one more than the limit); Cyclone's default (9) allows about ten, 120 allows
// 121. Index i on domain d listens on UDP ports 7410 + 250 d + 2 i and the next, which must stay
// under 65536: on domains above 201 fewer indices exist (63 on domain 232).
#pragma once

#include <string>

namespace skyroute::dds {

inline constexpr int kLoopbackMaxParticipantIndex = 120;

std::string loopbackConfigXml(int max_auto_participant_index = kLoopbackMaxParticipantIndex);

// Sets CYCLONEDDS_URI to loopbackConfigXml() (overwriting it). Call before creating the first
// participant of the process; child processes inherit it.
void useLoopbackOnly(int max_auto_participant_index = kLoopbackMaxParticipantIndex);

}  // namespace skyroute::dds
