// The engine with a no-fly zone published while a vehicle flies (the daemon's DDS edge calls
// updateNoFlyZone for each NoFlyZone sample): the next replanning cycle publishes a revision that
// goes round the zone; a zone with bad geometry is refused naming it; a lifted zone is gone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "service/engine.hpp"
#include "tests/terrain_data.hpp"
#include "tests/service/recording_sink.hpp"

namespace skyroute {
namespace {

using testing::RecordingSink;

constexpr std::int64_t kStartNs = 1'800'000'000'000'000'000LL;
constexpr double kHalfSideM = 300.0;  // the zone: a 600 m square

class NoFlyEngine : public ::testing::Test {
 protected:
  void SetUp() override {
    terrain_ = testing::defaultTerrainHeightfield();
    ASSERT_TRUE(terrain_) << "data/default_terrain.tif did not load";
    world_ = WorldModel::create(terrain_, WorldModelOptions{}, "default_terrain").value();
    EngineOptions options;
    options.pipeline.sample_dt_s = 0.05;
    engine_ = Engine::create(world_, options, sink_, [this] { return now_ns_; }).value();
  }
  MissionPointData above(double e, double n, double agl_m) const {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain_->heightAt(e, n) + agl_m));
  }
  // A square round `center` (ENU) as the DDS edge receives it: WGS84 ring, heights AMSL.
  NoFlyZoneData square(const std::string& id, const Eigen::Vector2d& center) const {
    NoFlyZoneData z;
    z.zone_id = id;
    for (const auto& [de, dn] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, std::pair{-1.0, 1.0}}) {
      z.ring.push_back(terrain_->frame().toGeo(
          Eigen::Vector3d(center.x() + de * kHalfSideM, center.y() + dn * kHalfSideM, 0.0)));
    }
    z.floor_amsl_m = -1000.0;
    z.ceiling_amsl_m = 4900.0;
    return z;
  }

  std::shared_ptr<const Heightfield> terrain_;
  std::shared_ptr<WorldModel> world_;
  RecordingSink sink_;
  std::int64_t now_ns_ = kStartNs;
  std::unique_ptr<Engine> engine_;
};

TEST_F(NoFlyEngine, ZoneAheadOfAFlyingVehicleGivesARevisionRoundIt) {
  MissionRequestData r;
  r.request_id = "flight";
  r.vehicle_id = "uav-1";
  r.begin = above(-4500, -4500, 200);
  r.points = {above(0, 0, 200)};
  r.end = above(4500, 4500, 200);
  ASSERT_FALSE(engine_->submit(r).has_value());
  ASSERT_TRUE(engine_->planNext());
  ASSERT_EQ(sink_.trajectories.size(), 1u);
  const TrajectoryData first = sink_.trajectories.front();

  // 20 s into the flight a zone appears round where the vehicle will be 30 s later.
  now_ns_ += 20'000'000'000LL;
  const std::size_t ahead = static_cast<std::size_t>(50.0 / 0.05);
  ASSERT_LT(ahead, first.samples.size());
  const Eigen::Vector2d center = first.samples[ahead].position_enu_m.head<2>();
  ASSERT_FALSE(engine_->updateNoFlyZone(square("closed", center)).has_value());
  // The first cycle answers: with the route round the zone, or, when building it would miss the
  // cycle's deadline, with a hold (the trajectory as far as it is clear, then a stop) and the
  // route round the zone a cycle later.
  ASSERT_EQ(engine_->replanCycle(), 1u);
  for (int cycle = 0; cycle < 5 && (sink_.trajectories.back().samples.back().position_enu_m - r.end.enu_m).norm() > 0.01;
       ++cycle) {
    now_ns_ += 100'000'000LL;
    engine_->replanCycle();
  }
  ASSERT_GE(sink_.trajectories.size(), 2u);
  const TrajectoryData& second = sink_.trajectories.back();
  EXPECT_EQ(second.revision, sink_.trajectories.size() - 1);
  // Reference: the 5 m vehicle sphere never reaches into the square's column, in any revision.
  const double r_m = WorldModelOptions{}.vehicle_radius_m;
  for (std::size_t k = 1; k < sink_.trajectories.size(); ++k) {
    for (const TrajectorySampleData& s : sink_.trajectories[k].samples) {
      const double dx = std::max(0.0, std::abs(s.position_enu_m.x() - center.x()) - kHalfSideM);
      const double dy = std::max(0.0, std::abs(s.position_enu_m.y() - center.y()) - kHalfSideM);
      ASSERT_GT(std::hypot(dx, dy), r_m) << "revision " << k << ", t = " << s.t_rel_s << " s";
    }
  }
  EXPECT_LT((second.samples.back().position_enu_m - r.end.enu_m).norm(), 0.01);

  // Clear now: nothing more to publish; lifting the zone changes nothing for the new route.
  now_ns_ += 100'000'000LL;
  EXPECT_EQ(engine_->replanCycle(), 0u);
  NoFlyZoneData lift;
  lift.zone_id = "closed";
  lift.remove = true;
  ASSERT_FALSE(engine_->updateNoFlyZone(lift).has_value());
  EXPECT_TRUE(world_->noFlyZones().empty());
}

TEST_F(NoFlyEngine, BadGeometryIsRefusedNamingTheZone) {
  NoFlyZoneData bow = square("bow", Eigen::Vector2d::Zero());
  std::swap(bow.ring[1], bow.ring[2]);
  const auto refused = engine_->updateNoFlyZone(bow);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field, "ring");
  EXPECT_NE(refused->message.find("zone 'bow': self-intersection"), std::string::npos) << refused->message;
  NoFlyZoneData upside = square("upside", Eigen::Vector2d::Zero());
  upside.floor_amsl_m = 5000.0;
  ASSERT_TRUE(engine_->updateNoFlyZone(upside).has_value());
  EXPECT_TRUE(world_->noFlyZones().empty());
}

TEST_F(NoFlyEngine, PublishedZonesTogetherKeepTheVertexBound) {
  // Ten zones at the bound of one zone fill the bound of them all; an eleventh is refused, a
  // changed one of the ten (same id) is not, and a lift makes room again.
  auto circle = [&](const std::string& id, double east_m) {
    NoFlyZoneData z;
    z.zone_id = id;
    for (std::size_t i = 0; i < kMaxNoFlyZoneVertices; ++i) {
      const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(kMaxNoFlyZoneVertices);
      z.ring.push_back(terrain_->frame().toGeo(Eigen::Vector3d(east_m + 200.0 * std::cos(a), 200.0 * std::sin(a), 0.0)));
    }
    z.floor_amsl_m = -1000.0;
    z.ceiling_amsl_m = 4900.0;
    return z;
  };
  ASSERT_EQ(kMaxPublishedNoFlyVertices, 10 * kMaxNoFlyZoneVertices);
  for (int k = 0; k < 10; ++k) {
    ASSERT_FALSE(engine_->updateNoFlyZone(circle("c" + std::to_string(k), -4500.0 + 900.0 * k)).has_value()) << k;
  }
  const auto refused = engine_->updateNoFlyZone(circle("c10", 4500.0));
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field, "ring");
  EXPECT_NE(refused->message.find("zone 'c10': the published zones in force would have 110000 vertices together, "
                                  "more than the 100000"),
            std::string::npos)
      << refused->message;
  EXPECT_FALSE(engine_->updateNoFlyZone(circle("c3", -1500.0)).has_value());  // replaces c3
  NoFlyZoneData lift;
  lift.zone_id = "c0";
  lift.remove = true;
  ASSERT_FALSE(engine_->updateNoFlyZone(lift).has_value());
  EXPECT_FALSE(engine_->updateNoFlyZone(circle("c10", 4500.0)).has_value());
  EXPECT_EQ(world_->publishedNoFlyZones().size(), 10u);
}

TEST_F(NoFlyEngine, ZonesOffTheTerrainAreRefusedNamingTheRing) {
  NoFlyZoneData swapped = square("swapped", Eigen::Vector2d::Zero());
  for (GeoPoint& p : swapped.ring) std::swap(p.lat_deg, p.lon_deg);
  auto refused = engine_->updateNoFlyZone(swapped);
  ASSERT_TRUE(refused.has_value());
  EXPECT_EQ(refused->field, "ring");
  EXPECT_NE(refused->message.find("latitude and longitude may be swapped"), std::string::npos) << refused->message;
  refused = engine_->updateNoFlyZone(square("off", Eigen::Vector2d(0.0, 50000.0)));
  ASSERT_TRUE(refused.has_value());
  EXPECT_NE(refused->message.find("zone 'off': lies entirely outside the DEM"), std::string::npos) << refused->message;
  // Partly over the DEM is over it.
  const Eigen::Vector2d corner = terrain_->boundsEn().max();
  EXPECT_FALSE(engine_->updateNoFlyZone(square("edge", corner)).has_value());
  EXPECT_EQ(world_->publishedNoFlyZones().size(), 1u);
}

}  // namespace
}  // namespace skyroute
