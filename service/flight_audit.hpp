// The audit as a flight uses it (ReplanOptions::audit): every trajectory a FlightReplanner is
// about to put in force, from the first plan to each replan, hold, loiter and new order, passes
// trajectory_audit.hpp against the data of the flight's world as it is at that moment (the zones
// and obstacles in force then), with the moving obstacles checked up to the end of the replanning
// horizon. Every audit is counted, and a refusal is counted and logged as
// `event=audit_failed vehicle=V revision=N reason="..." t_s=T check=C` (t_s: the failing sample's
// time in the revision), then returned as an error with field "audit".
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "service/fleet_replanner.hpp"
#include "service/flight_replanner.hpp"
#include "service/trajectory_audit.hpp"

namespace skyroute {

// Who the logged revisions belong to: the vehicle, and the number the engine adds to the
// flight's own revision count (a flight resumed after a restart or a handover counts on from the
// revision published before).
struct FlightAuditLabel {
  std::string vehicle_id;
  std::atomic<std::uint32_t> revision_base{0};
};

// The hook for ReplanOptions::audit. counters and label may be null (nothing counted; no vehicle named).
decltype(ReplanOptions::audit) flightAudit(std::shared_ptr<const CollisionWorld> world, const VehicleLimits& limits,
                                           const AuditOptions& options, double horizon_s,
                                           std::shared_ptr<AuditCounters> counters,
                                           std::shared_ptr<const FlightAuditLabel> label);

// The audit of a fleet's vehicles (FleetReplanOptions::audit, and each vehicle's first trajectory
// before the fleet is published): vehicle i's audits are counted and logged as flightAudit's,
// naming vehicle_ids[i]. A vehicle index outside vehicle_ids is refused.
FleetAuditHook fleetAudit(std::shared_ptr<const CollisionWorld> world, const VehicleLimits& limits,
                          const AuditOptions& options, double horizon_s, std::shared_ptr<AuditCounters> counters,
                          const std::vector<std::string>& vehicle_ids);

}  // namespace skyroute
