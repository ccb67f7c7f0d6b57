// What the DDS tools share: opening a participant (with the identity folder of --security, see
// dds_commands.hpp) and its readers, writers and wait loops, or failing with a message and exit
// code; stopping a waitset on SIGINT/SIGTERM; and one-line descriptions of what arrives.
#pragma once

#include <string>
#include <utility>

#include "planning/core/result.hpp"
#include "service/cli/cli_common.hpp"
#include "service/cli/exit_codes.hpp"
#include "service/dds/dds_entities.hpp"
#include "service/dds/typed_io.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/mission_types.hpp"

namespace skyroute::cli {

// An identity folder that fails its checks, or that DDS Security refuses, exits 3 naming the file
// or the reason; a domain out of range exits 2.
dds::Entity openParticipant(const std::string& tool, int domain);

// What a DDS call created, or exit kExitServiceUnavailable with its reason.
template <class T>
T createdOrFail(const std::string& tool, Result<T> created) {
  if (!created) fail(tool, kExitServiceUnavailable, created.error().describe());
  return std::move(*created);
}

template <class Plain>
dds::Reader<Plain> openReader(const std::string& tool, const dds::Entity& participant) {
  return createdOrFail(tool, dds::Reader<Plain>::create(participant.get()));
}

template <class Plain>
dds::Writer<Plain> openWriter(const std::string& tool, const dds::Entity& participant) {
  return createdOrFail(tool, dds::Writer<Plain>::create(participant.get()));
}

inline dds::WaitLoop openWaitLoop(const std::string& tool, const dds::Entity& participant) {
  return createdOrFail(tool, dds::WaitLoop::create(participant.get()));
}

// SIGINT and SIGTERM trigger this waitset (only that, as the Cyclone examples do).
void stopOnSignals(dds_entity_t waitset);

std::string describe(const TrajectoryData& trajectory);
std::string describe(const PlanStatusData& status);

}  // namespace skyroute::cli
