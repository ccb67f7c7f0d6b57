// The replanning cycle's look at a flying mission's visiting order (seed 000 in the daemon): when
// the obstacles changed since the last look, the mission's MMD*L searches are repaired and the
// points left ordered again (MissionPipeline::reorder); a better order is flown at once, as a new
// revision whose status (reordered) and log line give the old and the new order. A look costs
// nothing for a mission whose order was fixed or had one point, and little when the change is far
// from the mission's costs (only the cells it flipped are expanded).
#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"
#include "service/mission_reorder.hpp"

namespace skyroute {

bool Engine::reorderMission(Mission& mission, std::unique_lock<std::mutex>& lock, double now_s, std::uint64_t changes,
                            std::uint64_t coalesced) {
  if (!mission.plan.reorder || mission.order_checked == changes) return false;
  mission.order_checked = changes;
  const MissionPipeline pipeline(mission.world_model, options().pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(mission.cancel);
  FlightSnapshot before;  // a new order the journal does not record is undone
  if (sink_.recordsTrajectories()) {
    before.flight = std::make_unique<FlightReplanner>(*mission.plan.flight);
    before.order = mission.plan.mission;
  }
  const ReorderOutcome outcome = pipeline.reorder(mission.plan, now_s, stop);
  const ReorderCheck& check = outcome.check;
  const MissionRequestData& r = mission.request;
  if (check.repaired) {
    spdlog::debug("event=reorder_check request={} vehicle={} changed_cells={} covered_cells={} expansions={} ms={:.1f} "
                  "old_order={} new_order={} failure=\"{}\"",
                  r.request_id, r.vehicle_id, check.changed_cells, check.covered_cells, check.search.expansions,
                  check.time_ms, orderText(check.old_order), orderText(check.new_order),
                  check.failure ? check.failure->describe() : std::string());
  }
  if (!check.reordered()) return false;
  if (!outcome.step.replanned) {
    // The current revision stays; the next change of the obstacles looks again.
    spdlog::info("event=reorder_failed request={} vehicle={} old_order={} new_order={} reason=\"{}\"", r.request_id,
                 r.vehicle_id, orderText(check.old_order), orderText(check.new_order),
                 outcome.step.failure ? outcome.step.failure->describe() : std::string());
    return false;
  }
  const TrajectoryData data = trajectoryOf(mission);
  if (!recordRevision(mission, data, before, check.time_ms + outcome.step.latency_ms)) return false;
  mission.failure_answered = false;
  sink_.publishTrajectory(data);
  lock.unlock();
  ++replans_;
  const double latency_ms = check.time_ms + outcome.step.latency_ms;
  spdlog::info("event=reordered request={} vehicle={} plan={} revision={} old_order={} new_order={} old_cost_m={:.0f} "
               "new_cost_m={:.0f} changed_cells={} expansions={} reorder_ms={:.1f} latency_ms={:.1f} "
               "updates_coalesced={}",
               r.request_id, r.vehicle_id, mission.plan_id, data.revision, orderText(check.old_order),
               orderText(check.new_order), check.old_cost_m, check.new_cost_m, check.changed_cells,
               check.search.expansions, check.time_ms, latency_ms, coalesced);
  PlanStatusData s;
  s.request_id = r.request_id;
  s.vehicle_id = r.vehicle_id;
  s.state = PlanState::kReordered;
  s.planning_time_s = latency_ms * 1e-3;
  s.requester = r.requester;
  s.message = "reordered: revision " + std::to_string(data.revision) + " visits the points left in a new order, " +
              orderText(check.old_order) + " -> " + orderText(check.new_order) + " (from the last point reached; " +
              fmt::format("{:.0f} m -> {:.0f} m on the order grid", check.old_cost_m, check.new_cost_m) + ")";
  sink_.publishStatus(s);
  return true;
}

}  // namespace skyroute
