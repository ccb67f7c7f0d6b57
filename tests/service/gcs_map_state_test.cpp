// The web map's state: the terrain picture on a WGS84 grid with bounds that fit the DEM, and the
// JSON the page draws (trajectories with the ground under them, statuses, obstacles with their
// predicted tracks, an empty no-fly-zone list), versioned so waiting readers wake on a change.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include <cpl_vsi.h>
#include <gdal.h>
#include <nlohmann/json.hpp>

#include "service/world_model.hpp"
#include "tests/service/gcs_fixtures.hpp"

namespace skyroute {
namespace {

using nlohmann::json;

json stateJson(const GcsMapState& state) { return json::parse(*state.snapshot().json); }

class GcsMapStateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    state_ = testing::embeddedTerrainMapState();
    ASSERT_TRUE(state_);
    terrain_ = testing::defaultTerrainHeightfield();
  }
  const LocalFrame& frame() const { return terrain_->frame(); }

  std::shared_ptr<GcsMapState> state_;
  std::shared_ptr<const Heightfield> terrain_;
};

TEST_F(GcsMapStateTest, HillshadeIsAPngOnALatLonGridWhoseBoundsHoldTheDemTightly) {
  const GeoPng& image = state_->image();
  ASSERT_GT(image.png.size(), 8u);
  EXPECT_EQ(image.png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  // GDAL reads it back at the stated size, with an alpha band (transparent outside the DEM).
  const std::string path = "/vsimem/gcs_map_state_test.png";
  VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(image.png.data())),
                                     image.png.size(), FALSE);
  ASSERT_NE(f, nullptr);
  VSIFCloseL(f);
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(GDALGetRasterXSize(ds), image.width_px);
  EXPECT_EQ(GDALGetRasterYSize(ds), image.height_px);
  EXPECT_EQ(GDALGetRasterCount(ds), 4);
  GDALClose(ds);
  VSIUnlink(path.c_str());

  // The bounds are the DEM's footprint to within a pixel (GDAL rounds the warped size to whole
  // pixels, so an edge may move by up to half a pixel either way).
  const Dem& dem = terrain_->dem();
  double west = 1e9, east = -1e9, south = 1e9, north = -1e9;
  for (const auto& [col, row] : {std::pair{-0.5, -0.5}, {dem.width() - 0.5, -0.5}, {-0.5, dem.height() - 0.5},
                                 {dem.width() - 0.5, dem.height() - 0.5}}) {
    const Eigen::Vector2d en = terrain_->pixelToEn(col, row);
    const GeoPoint g = frame().toGeo(Eigen::Vector3d(en.x(), en.y(), 0.0));
    west = std::min(west, g.lon_deg);
    east = std::max(east, g.lon_deg);
    south = std::min(south, g.lat_deg);
    north = std::max(north, g.lat_deg);
  }
  const double pixel_lon = (image.east_deg - image.west_deg) / image.width_px;
  const double pixel_lat = (image.north_deg - image.south_deg) / image.height_px;
  EXPECT_LT(std::abs(image.west_deg - west), pixel_lon);
  EXPECT_LT(std::abs(image.east_deg - east), pixel_lon);
  EXPECT_LT(std::abs(image.south_deg - south), pixel_lat);
  EXPECT_LT(std::abs(image.north_deg - north), pixel_lat);
}

TEST_F(GcsMapStateTest, StartsEmptyWithTheMapAndAnEmptyNoFlyZoneList) {
  const json s = stateJson(*state_);
  EXPECT_EQ(s["format"], "skyroute-gcs-state");
  EXPECT_EQ(s["version"], 1);
  EXPECT_EQ(state_->version(), 1u);
  EXPECT_TRUE(s["vehicles"].is_array() && s["vehicles"].empty());
  EXPECT_TRUE(s["obstacles"].is_array() && s["obstacles"].empty());
  EXPECT_TRUE(s["no_fly_zones"].is_array() && s["no_fly_zones"].empty());
  EXPECT_EQ(s["map"]["image"], "hillshade.png");
  EXPECT_EQ(s["map"]["width_px"], state_->image().width_px);
  EXPECT_DOUBLE_EQ(s["map"]["west_deg"].get<double>(), state_->image().west_deg);
  EXPECT_DOUBLE_EQ(s["map"]["north_deg"].get<double>(), state_->image().north_deg);
  EXPECT_EQ(s["map"]["terrain"], "default_terrain.tif");
}

TEST_F(GcsMapStateTest, TrajectoryCarriesItsSamplesAndTheGroundUnderEach) {
  const std::int64_t start_ns = 1'700'000'000'000'000'000;
  const TrajectoryData t = testing::trajectoryThrough(
      frame(), "uav-1", 4, {{-3000, -2000, 1200}, {1000, 500, 1300}, {4000, 2500, 1100}}, start_ns);
  state_->onTrajectory(t);
  EXPECT_EQ(state_->version(), 2u);
  const json s = stateJson(*state_);
  ASSERT_EQ(s["vehicles"].size(), 1u);
  const json& v = s["vehicles"][0];
  EXPECT_EQ(v["vehicle_id"], "uav-1");
  EXPECT_TRUE(v["status"].is_null());
  const json& traj = v["trajectory"];
  EXPECT_EQ(traj["revision"], 4);
  EXPECT_EQ(traj["plan_id"], "uav-1-plan");
  EXPECT_EQ(traj["sample_count"], t.samples.size());
  EXPECT_EQ(traj["start_utc_ms"], start_ns / 1'000'000);
  EXPECT_EQ(traj["end_utc_ms"], t.samples.back().utc_ns / 1'000'000);
  const json& samples = traj["samples"];
  ASSERT_EQ(samples["utc_ms"].size(), t.samples.size());
  for (const char* column : {"lat_deg", "lon_deg", "alt_amsl_m", "ground_amsl_m"}) {
    EXPECT_EQ(samples[column].size(), t.samples.size()) << column;
  }
  for (std::size_t i = 0; i < t.samples.size(); ++i) {
    const auto& p = t.samples[i];
    EXPECT_EQ(samples["utc_ms"][i], p.utc_ns / 1'000'000);
    EXPECT_NEAR(samples["lat_deg"][i].get<double>(), p.geo.lat_deg, 1e-7);
    EXPECT_NEAR(samples["lon_deg"][i].get<double>(), p.geo.lon_deg, 1e-7);
    EXPECT_NEAR(samples["alt_amsl_m"][i].get<double>(), p.geo.alt_amsl_m, 0.05);
    const double ground = terrain_->heightAt(p.position_enu_m.x(), p.position_enu_m.y());
    ASSERT_TRUE(std::isfinite(ground));
    EXPECT_NEAR(samples["ground_amsl_m"][i].get<double>(), ground, 0.06) << "sample " << i;
  }
}

TEST_F(GcsMapStateTest, GroundOffTheDemIsNull) {
  const Eigen::AlignedBox2d box = terrain_->boundsEn();
  const double far_east_m = box.max().x() + 5000.0;
  state_->onTrajectory(testing::trajectoryThrough(frame(), "uav-1", 0, {{0, 0, 1000}, {far_east_m, 0, 1000}}, 0, 20));
  const json ground = stateJson(*state_)["vehicles"][0]["trajectory"]["samples"]["ground_amsl_m"];
  EXPECT_TRUE(ground.front().is_number());
  EXPECT_TRUE(ground.back().is_null());
}

TEST_F(GcsMapStateTest, LongTrajectoriesAreThinnedKeepingBothEnds) {
  const TrajectoryData t = testing::trajectoryThrough(frame(), "uav-1", 0, {{-4000, 0, 1000}, {4000, 0, 1000}}, 0,
                                                      static_cast<int>(3 * GcsMapState::kMaxSamplesPerVehicle) + 7);
  state_->onTrajectory(t);
  const json traj = stateJson(*state_)["vehicles"][0]["trajectory"];
  const json& utc = traj["samples"]["utc_ms"];
  EXPECT_LE(utc.size(), GcsMapState::kMaxSamplesPerVehicle);
  EXPECT_GT(utc.size(), GcsMapState::kMaxSamplesPerVehicle / 2);
  EXPECT_EQ(utc.front(), t.samples.front().utc_ns / 1'000'000);
  EXPECT_EQ(utc.back(), t.samples.back().utc_ns / 1'000'000);
  EXPECT_EQ(traj["sample_count"], t.samples.size());
}

TEST_F(GcsMapStateTest, AStaleRevisionOfThePlanOnDisplayIsIgnoredButANewPlanReplacesIt) {
  const std::vector<Eigen::Vector3d> route{{0, 0, 1000}, {1000, 0, 1000}};
  state_->onTrajectory(testing::trajectoryThrough(frame(), "uav-1", 3, route, 0));
  state_->onTrajectory(testing::trajectoryThrough(frame(), "uav-1", 2, route, 0));
  EXPECT_EQ(stateJson(*state_)["vehicles"][0]["trajectory"]["revision"], 3);
  TrajectoryData next_plan = testing::trajectoryThrough(frame(), "uav-1", 0, route, 0);
  next_plan.plan_id = "uav-1-plan-2";
  state_->onTrajectory(next_plan);
  const json traj = stateJson(*state_)["vehicles"][0]["trajectory"];
  EXPECT_EQ(traj["revision"], 0);
  EXPECT_EQ(traj["plan_id"], "uav-1-plan-2");
}

TEST_F(GcsMapStateTest, StatusesAreKeptPerVehicleEvenBeforeATrajectory) {
  PlanStatusData failed;
  failed.request_id = "r-1";
  failed.vehicle_id = "uav-2";
  failed.state = PlanState::kFailed;
  failed.error_code = PlanErrorCode::kOutsideMap;
  failed.field = "points[0]";
  failed.message = "points[0] is outside the DEM";
  state_->onStatus(failed);
  PlanStatusData anonymous;  // no vehicle: nothing to show it on
  state_->onStatus(anonymous);
  const json s = stateJson(*state_);
  ASSERT_EQ(s["vehicles"].size(), 1u);
  const json& v = s["vehicles"][0];
  EXPECT_EQ(v["vehicle_id"], "uav-2");
  EXPECT_TRUE(v["trajectory"].is_null());
  EXPECT_EQ(v["status"]["state"], "failed");
  EXPECT_EQ(v["status"]["error"], "outside_map");
  EXPECT_EQ(v["status"]["field"], "points[0]");
  EXPECT_EQ(v["status"]["request_id"], "r-1");
}

TEST_F(GcsMapStateTest, ObstaclesCarryThePredictedTrackInWgs84AndGoWhenRemovedOrExpired) {
  const std::int64_t now_ns = utcNowNs();
  ObstacleUpdateData sweeping;
  sweeping.obstacle.id = 7;
  sweeping.obstacle.shape = ObstacleShape::kEllipsoid;
  sweeping.obstacle.size_m = {600, 400, 1000};
  sweeping.obstacle.center_m = {-1500, -1000, 300};
  sweeping.obstacle.motion = BackAndForth{{-1500, -1000, 300}, {4000, -1000, 300}, 60.0, 0.0};
  sweeping.valid_from_utc_ns = now_ns;
  state_->onObstacle(sweeping);

  ObstacleUpdateData drifting;  // constant velocity: a track to where it is at valid_until
  drifting.obstacle.id = 8;
  drifting.obstacle.shape = ObstacleShape::kSphere;
  drifting.obstacle.size_m = {150, 0, 0};
  drifting.obstacle.center_m = {0, 0, 500};
  drifting.constant_velocity_enu_mps = Eigen::Vector3d(10, 0, 0);
  drifting.valid_from_utc_ns = now_ns;
  drifting.valid_until_utc_ns = now_ns + 100'000'000'000;  // 100 s
  state_->onObstacle(drifting);

  json s = stateJson(*state_);
  ASSERT_EQ(s["obstacles"].size(), 2u);
  const json& a = s["obstacles"][0];
  EXPECT_EQ(a["id"], 7);
  EXPECT_EQ(a["shape"], "ellipsoid");
  EXPECT_EQ(a["size_m"], json({600.0, 400.0, 1000.0}));
  EXPECT_EQ(a["motion"], "back_and_forth");
  EXPECT_TRUE(a["valid_until_utc_ms"].is_null());
  const GeoPoint from = frame().toGeo({-1500, -1000, 300}), to = frame().toGeo({4000, -1000, 300});
  EXPECT_NEAR(a["track"]["from"]["lat_deg"].get<double>(), from.lat_deg, 1e-7);
  EXPECT_NEAR(a["track"]["from"]["lon_deg"].get<double>(), from.lon_deg, 1e-7);
  EXPECT_NEAR(a["track"]["to"]["lat_deg"].get<double>(), to.lat_deg, 1e-7);
  EXPECT_NEAR(a["track"]["to"]["lon_deg"].get<double>(), to.lon_deg, 1e-7);
  EXPECT_DOUBLE_EQ(a["track"]["speed_mps"].get<double>(), 60.0);
  EXPECT_EQ(a["track"]["start_utc_ms"], now_ns / 1'000'000);

  const json& b = s["obstacles"][1];
  EXPECT_EQ(b["motion"], "constant_velocity");
  EXPECT_EQ(b["valid_until_utc_ms"], (now_ns + 100'000'000'000) / 1'000'000);
  const GeoPoint end = frame().toGeo({1000, 0, 500});  // 10 m/s for 100 s
  EXPECT_NEAR(b["track"]["to"]["lon_deg"].get<double>(), end.lon_deg, 1e-7);
  EXPECT_NEAR(b["track"]["to"]["lat_deg"].get<double>(), end.lat_deg, 1e-7);
  EXPECT_DOUBLE_EQ(b["track"]["speed_mps"].get<double>(), 10.0);

  ObstacleUpdateData removal;
  removal.obstacle.id = 7;
  removal.remove = true;
  state_->onObstacle(removal);
  ObstacleUpdateData expired = drifting;
  expired.obstacle.id = 9;
  expired.valid_from_utc_ns = now_ns - 20'000'000'000;
  expired.valid_until_utc_ns = now_ns - 10'000'000'000;
  state_->onObstacle(expired);
  s = stateJson(*state_);
  ASSERT_EQ(s["obstacles"].size(), 1u);
  EXPECT_EQ(s["obstacles"][0]["id"], 8);
}

TEST_F(GcsMapStateTest, WaitersWakeOnAChangeOrOnCloseAndTimeOutOtherwise) {
  const std::uint64_t v0 = state_->version();
  auto started = std::chrono::steady_clock::now();
  EXPECT_EQ(state_->waitForVersionAbove(v0, 0.1), v0);
  EXPECT_GE(std::chrono::steady_clock::now() - started, std::chrono::milliseconds(90));

  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    state_->onTrajectory(testing::trajectoryThrough(frame(), "uav-1", 0, {{0, 0, 1000}, {100, 0, 1000}}, 0));
  });
  started = std::chrono::steady_clock::now();
  EXPECT_EQ(state_->waitForVersionAbove(v0, 10.0), v0 + 1);
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5));
  writer.join();
  const GcsMapState::Snapshot snapshot = state_->snapshot();
  EXPECT_EQ(snapshot.version, v0 + 1);
  EXPECT_EQ(stateJson(*state_)["version"], v0 + 1);

  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    state_->close();
  });
  started = std::chrono::steady_clock::now();
  state_->waitForVersionAbove(v0 + 1, 10.0);
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5));
  EXPECT_TRUE(state_->closed());
  closer.join();
}

}  // namespace
}  // namespace skyroute
