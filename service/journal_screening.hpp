// A restart never replays what would be refused today: every record the state journal recovered
// (JournalState, state_journal.hpp) is checked with the validation the same input gets when it
// arrives now, with the configured bounds and the terrain in force: a mission request (and a
// shard's copy of one) with checkMissionAdmission, a shard's copy of a fleet request with
// checkFleetAdmission, an obstacle update with validateObstacleUpdate and the obstacle bounds, a
// no-fly zone with toNoFlyZone. A refused record is taken out of the state, with what depends on
// it (quarantineDependents: a refused mission's trajectory), and returned, for
// StateJournal::quarantine to move and log; the rest resumes.
#pragma once

#include <vector>

#include "service/engine.hpp"
#include "service/state_journal.hpp"
#include "service/world_model.hpp"

namespace skyroute {

std::vector<QuarantinedRecord> screenJournalState(JournalState& state, const EngineOptions& options,
                                                  const WorldModel& world);

}  // namespace skyroute
