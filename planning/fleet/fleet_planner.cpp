#include "planning/fleet/fleet_planner.hpp"

#include <chrono>

#include "planning/core/enum_names.hpp"
#include "planning/fleet/gmtpa.hpp"

namespace skyroute {

namespace {
constexpr EnumName<FleetAllocator> kAllocatorNames[] = {
    {FleetAllocator::kGreedy, "greedy"}, {FleetAllocator::kGenetic, "ga"}, {FleetAllocator::kExact, "exact"}};
}  // namespace

std::string_view to_string(FleetAllocator allocator) { return enumName(kAllocatorNames, allocator); }

std::optional<FleetAllocator> parseFleetAllocator(std::string_view name) { return enumNamed(kAllocatorNames, name); }

std::vector<std::vector<GridCell>> pathsOf(const FleetPaths& paths) {
  std::vector<std::vector<GridCell>> out;
  for (const VehiclePlan& v : paths.vehicles) out.push_back(v.cells);
  return out;
}

std::vector<std::vector<int>> sequencesOf(const FleetPaths& paths) {
  std::vector<std::vector<int>> out;
  for (const VehiclePlan& v : paths.vehicles) out.push_back(v.tasks);
  return out;
}

Result<FleetPlan> planFleet(const GridLayer& grid, const FleetProblem& problem, const FleetPlannerOptions& options,
                            const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  if (Status valid = validateFleetProblem(grid, problem); !valid) return valid.error();

  FleetPlan plan;
  const TravelTimeTable table = TravelTimeTable::build(grid, problem);
  plan.table_time_s = table.buildSeconds();

  Result<FleetAllocation> allocation = [&]() -> Result<FleetAllocation> {
    switch (options.allocator) {
      case FleetAllocator::kGreedy: return allocateGreedy(problem, table);
      case FleetAllocator::kGenetic: return allocateGenetic(problem, table, options.ga, stop);
      case FleetAllocator::kExact: return allocateExact(problem, table, options.exact, stop);
    }
    return make_error(ErrorCode::kInvalidArgument, "algo", "unknown allocator");
  }();
  if (!allocation) return allocation.error();
  plan.allocation = std::move(allocation).value();
  if (options.allocator == FleetAllocator::kGreedy) {
    plan.allocation = improveAllocation(problem, table, plan.allocation, options.improvement, &plan.improvement);
  }

  plan.paths = buildFleetPaths(grid, problem, table, plan.allocation, options.paths, stop);
  switch (plan.paths.status) {
    case PlannerStatus::kSolved: break;
    case PlannerStatus::kCancelled: return make_error(ErrorCode::kCancelled, "fleet paths", plan.paths.detail);
    case PlannerStatus::kTimeout: return make_error(ErrorCode::kTimeout, "fleet paths", plan.paths.detail);
    default: return make_error(ErrorCode::kUnreachable, "fleet paths", plan.paths.detail);
  }
  plan.check = checkFleetPlan(grid, problem, pathsOf(plan.paths), sequencesOf(plan.paths));
  if (!plan.check.ok()) {
    return make_error(ErrorCode::kInternal, "fleet paths",
                      "the checker rejects the plan: " + plan.check.summary());
  }
  plan.total_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return plan;
}

}  // namespace skyroute
