#include "service/flight_audit.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "terrain/collision_world.hpp"

namespace skyroute {

decltype(ReplanOptions::audit) flightAudit(std::shared_ptr<const CollisionWorld> world, const VehicleLimits& limits,
                                           const AuditOptions& options, double horizon_s,
                                           std::shared_ptr<AuditCounters> counters,
                                           std::shared_ptr<const FlightAuditLabel> label) {
  return [world = std::move(world), limits, options, horizon_s, counters = std::move(counters),
          label = std::move(label)](const Trajectory& trajectory, double start_world_s, double now_s,
                                    std::uint32_t revision) -> std::optional<Error> {
    const auto started = std::chrono::steady_clock::now();
    if (counters) counters->audits.fetch_add(1, std::memory_order_relaxed);
    const AuditWorld data = auditWorldOf(*world, now_s + horizon_s);
    const std::optional<AuditFinding> finding = auditTrajectory(trajectory, start_world_s, data, limits, options);
    spdlog::debug("event=audit vehicle={} revision={} duration_s={:.1f} passed={} ms={:.2f}",
                  label ? label->vehicle_id : std::string(), revision + (label ? label->revision_base.load() : 0U),
                  trajectory.duration_s(), !finding,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
    if (!finding) return std::nullopt;
    if (counters) counters->failures.fetch_add(1, std::memory_order_relaxed);
    const std::uint32_t published = revision + (label ? label->revision_base.load() : 0U);
    spdlog::warn("event=audit_failed vehicle={} revision={} reason=\"{}\" t_s={:.2f} check={}",
                 label ? label->vehicle_id : std::string(), published, finding->reason, finding->t_s,
                 to_string(finding->check));
    return make_error(ErrorCode::kInternal, "audit",
                      "the trajectory failed the audit before publishing (revision " + std::to_string(published) +
                          "): " + finding->reason);
  };
}

FleetAuditHook fleetAudit(std::shared_ptr<const CollisionWorld> world, const VehicleLimits& limits,
                          const AuditOptions& options, double horizon_s, std::shared_ptr<AuditCounters> counters,
                          const std::vector<std::string>& vehicle_ids) {
  std::vector<decltype(ReplanOptions::audit)> hooks;
  hooks.reserve(vehicle_ids.size());
  for (const std::string& id : vehicle_ids) {
    auto label = std::make_shared<FlightAuditLabel>();
    label->vehicle_id = id;
    hooks.push_back(flightAudit(world, limits, options, horizon_s, counters, std::move(label)));
  }
  return [hooks = std::move(hooks)](std::size_t vehicle, const Trajectory& trajectory, double start_world_s,
                                    double now_s, std::uint32_t revision) -> std::optional<Error> {
    if (vehicle >= hooks.size()) {
      return make_error(ErrorCode::kInternal, "audit", "no vehicle " + std::to_string(vehicle) + " in the fleet");
    }
    return hooks[vehicle](trajectory, start_world_s, now_s, revision);
  };
}

}  // namespace skyroute
