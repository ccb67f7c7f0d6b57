#include "service/dds/loopback.hpp"

#include <cstdlib>

namespace skyroute::dds {

std::string loopbackConfigXml(int max_auto_participant_index) {
  return "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers><MaxAutoParticipantIndex>" +
         std::to_string(max_auto_participant_index) +
         "</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>";
}

void useLoopbackOnly(int max_auto_participant_index) {
  ::setenv("CYCLONEDDS_URI", loopbackConfigXml(max_auto_participant_index).c_str(), 1);
}

}  // namespace skyroute::dds
