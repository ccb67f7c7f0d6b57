// The audit as the flight's last gate (ReplanOptions::audit, service/flight_audit.hpp): every
// trajectory the replanner is about to put in force is audited first, with the revision it would
// be; one the audit refuses is never adopted: the revision in force stays, or a hold that passes.
// On the embedded terrain, with a zone published across the route (what the daemon's engine does
// for a DDS zone), and an audit that refuses on demand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "service/flight_replanner.hpp"
#include "terrain/collision_world.hpp"
#include "tests/terrain_data.hpp"

namespace skyroute {
namespace {

constexpr double kStartS = 1000.0;

struct AuditLog {
  bool refuse = false;                  // refuse every trajectory after the first plan
  std::vector<std::uint32_t> revisions;  // the revision of each audit, in order
};

class FlightAudit : public ::testing::Test {
 protected:
  void SetUp() override {
    terrain_ = testing::defaultTerrainHeightfield();
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
    CollisionWorldOptions options;
    options.min_clearance_m = 30.0;
    options.build_octree = false;
    auto world = CollisionWorld::create(terrain_, options);
    ASSERT_TRUE(world.ok()) << world.error().describe();
    world_ = *world;
  }
  Eigen::Vector3d above(double e, double n, double agl_m) const { return {e, n, terrain_->heightAt(e, n) + agl_m}; }
  // West to east, 8 km at 400 m above the ground, with a budget-free reproducible replan.
  std::unique_ptr<FlightReplanner> fly() {
    ReplanOptions options;
    options.route.seed = 3;
    options.route.leg_budget_ms = 0.0;  // iteration budgets: reproducible
    options.route.leg_max_iterations = 3000;
    options.replan_leg_max_iterations = 400;
    options.replan_budget_ms = 0.0;
    options.audit = [log = log_](const Trajectory&, double, double, std::uint32_t revision) -> std::optional<Error> {
      log->revisions.push_back(revision);
      if (log->refuse && revision > 0) return make_error(ErrorCode::kInternal, "audit", "refused by the test");
      return std::nullopt;
    };
    auto flight = FlightReplanner::start(world_, {above(-4000, 0, 400), above(4000, 0, 400)}, VehicleLimits{}, options,
                                         kStartS);
    EXPECT_TRUE(flight.ok()) << flight.error().describe();
    return flight.ok() ? std::move(*flight) : nullptr;
  }
  // A 600 m square zone across the route, centred `east_m` east, from the ground to above it all.
  void closeAt(double east_m) {
    NoFlyZone z;
    z.name = "closed";
    z.ring_m = {{east_m - 300, -300}, {east_m + 300, -300}, {east_m + 300, 300}, {east_m - 300, 300}};
    z.floor_m = -1000.0;
    z.ceiling_m = 9000.0;
    world_->setNoFlyZones({z});
  }

  std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<CollisionWorld> world_;
  std::shared_ptr<AuditLog> log_ = std::make_shared<AuditLog>();
};

TEST_F(FlightAudit, ARefusedReplanIsNeverAdoptedAndThePassedOneIs) {
  std::unique_ptr<FlightReplanner> flight = fly();
  ASSERT_TRUE(flight);
  ASSERT_EQ(log_->revisions, std::vector<std::uint32_t>{0});  // the first plan was audited
  const double duration_s = flight->route().built.trajectory.duration_s();
  // Far ahead (about 110 s into the flight, 100 s away): re-routed, no hold.
  closeAt(1500.0);
  log_->refuse = true;
  const ReplanStep refused = flight->step(kStartS + 10.0);
  EXPECT_TRUE(refused.conflict_ahead);
  EXPECT_FALSE(refused.replanned);
  EXPECT_FALSE(refused.holding);
  ASSERT_TRUE(refused.failure.has_value());
  EXPECT_EQ(refused.failure->field, "audit") << refused.failure->describe();
  EXPECT_EQ(flight->revision(), 0u);
  EXPECT_EQ(flight->route().built.trajectory.duration_s(), duration_s);  // the revision in force stays
  ASSERT_GE(log_->revisions.size(), 2u);
  EXPECT_EQ(log_->revisions.back(), 1u);

  log_->refuse = false;
  const ReplanStep passed = flight->step(kStartS + 10.1);
  EXPECT_TRUE(passed.replanned) << (passed.failure ? passed.failure->describe() : "");
  EXPECT_FALSE(passed.holding);
  EXPECT_EQ(flight->revision(), 1u);
  EXPECT_EQ(log_->revisions.back(), 1u);
  EXPECT_TRUE(flight->clearAhead(kStartS + 10.1, 45.0));  // round the zone, to the end
}

TEST_F(FlightAudit, AHoldTheAuditRefusesIsNotPutInForceEither) {
  std::unique_ptr<FlightReplanner> flight = fly();
  ASSERT_TRUE(flight);
  // Within the horizon (about 20 s ahead), and every revision refused: no replan, no hold.
  closeAt(-2500.0);
  log_->refuse = true;
  const ReplanStep step = flight->step(kStartS + 10.0);
  EXPECT_TRUE(step.conflict_ahead);
  EXPECT_FALSE(step.replanned);
  EXPECT_FALSE(step.holding);
  EXPECT_EQ(flight->revision(), 0u);
  EXPECT_FALSE(flight->holding());
  // The replan and the hold were both audited (and refused) as revision 1.
  EXPECT_GE(std::count(log_->revisions.begin(), log_->revisions.end(), 1u), 2);
  // Passed, the hold goes in force when no route does: here a route does.
  log_->refuse = false;
  const ReplanStep next = flight->step(kStartS + 10.1);
  EXPECT_TRUE(next.replanned || next.holding);
  EXPECT_EQ(flight->revision(), 1u);
}

}  // namespace
}  // namespace skyroute
