// The live map in a real browser: skyrouted and `skyroute gcs --serve` run as processes, headless
// chromium opens the page before anything is planned, and the page must follow the daemon: the
// vehicle at revision 0 after its mission, then revision 1 with the obstacle listed after an
// obstacle on the route makes the daemon replan.
#include <gtest/gtest.h>

#include <string>

#include "service/dds/loopback.hpp"
#include "terrain/heightfield.hpp"
#include "tests/daemon/daemon_process.hpp"
#include "tests/daemon/ground_station.hpp"
#include "tests/terrain_data.hpp"
#include "tests/test_data.hpp"
#include "tests/daemon/web_driver.hpp"  // last: see its note on httplib and Eigen

namespace skyroute {
namespace {

using testing::ChildProcess;
using testing::eventually;

constexpr int kDomain = 205;  // this file's DDS domain
const std::string kVehicle = "uav-map";

// What the page shows for the vehicle: its row's revision ("" when there is no row).
std::string revisionShown(testing::WebDriver& browser) {
  auto v = browser.script("const row = document.querySelector('#vehicles tr[data-vehicle=\"" + kVehicle +
                          "\"]'); return row ? row.dataset.revision : '';");
  return v && v->is_string() ? v->get<std::string>() : "";
}
std::string pageText(testing::WebDriver& browser) {
  auto v = browser.script("return document.body.innerText;");
  return v && v->is_string() ? v->get<std::string>() : "(no page)";
}
bool exists(testing::WebDriver& browser, const std::string& selector) {
  auto v = browser.script("return document.querySelector('" + selector + "') !== null;");
  return v && *v == true;
}

TEST(GcsMapBrowser, PageFollowsTheDaemonsRevisionsAsTheyArrive) {
  dds::useLoopbackOnly();  // the daemon and the ground station inherit it
  const auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  std::string why;
  auto browser = testing::WebDriver::open(&why);
  ASSERT_TRUE(browser) << why;

  ChildProcess daemon = ChildProcess::spawn({SKYROUTED, "--domain", std::to_string(kDomain)}, "map_skyrouted");
  auto station = testing::Station::open(kDomain);
  ASSERT_TRUE(station);
  ASSERT_TRUE(station->pumpUntil([&] { return station->heartbeats > 0 || !daemon.running(); }, 60.0)) << daemon.err();
  ASSERT_TRUE(daemon.running()) << daemon.err();
  ASSERT_TRUE(station->requests->waitForReaders(1, 20.0).ok());

  ChildProcess gcs = ChildProcess::spawn(
      {SKYROUTE_CLI, "gcs", "--domain", std::to_string(kDomain), "--serve", "127.0.0.1:0"}, "map_gcs");
  std::string url;
  ASSERT_TRUE(eventually(
      [&] {
        const std::string out = gcs.out();
        const std::size_t at = out.find("live map on ");
        if (at != std::string::npos) url = out.substr(at + 12, out.find('\n', at) - at - 12);
        return !url.empty() || !gcs.running();
      },
      30.0));
  ASSERT_FALSE(url.empty()) << gcs.err();
  ASSERT_TRUE(browser->navigate(url));
  ASSERT_TRUE(eventually(
      [&] {
        auto v = browser->script("return document.getElementById('connection').textContent;");
        return v && *v == "live";
      },
      10.0))
      << pageText(*browser);
  EXPECT_EQ(revisionShown(*browser), "");  // nothing planned yet

  auto above = [&](double e, double n) {
    return MissionPointData::enu(Eigen::Vector3d(e, n, terrain->heightAt(e, n) + 400.0));
  };
  MissionRequestData mission;
  mission.request_id = "map-1";
  mission.vehicle_id = kVehicle;
  mission.begin = above(-5000, 0);
  mission.points = {above(0, 200)};
  mission.end = above(5000, 0);
  ASSERT_TRUE(station->requests->write(mission).ok());
  ASSERT_TRUE(station->waitTerminal({mission.request_id}, 60.0)) << daemon.err();
  ASSERT_EQ(station->terminal(mission.request_id)->state, PlanState::kSucceeded);
  ASSERT_TRUE(eventually([&] { return revisionShown(*browser) == "0"; }, 10.0)) << pageText(*browser);
  EXPECT_TRUE(exists(*browser, "#marker-" + kVehicle));
  EXPECT_TRUE(exists(*browser, "#map polyline[data-vehicle=\"" + kVehicle + "\"]"));
  EXPECT_NE(pageText(*browser).find("Altitude profile of " + kVehicle + ", revision 0"), std::string::npos)
      << pageText(*browser);

  // A tall cylinder on the route 25 s ahead of the vehicle: the daemon must replan around it.
  ASSERT_TRUE(station->pumpUntil([&] { return station->latest(kVehicle) != nullptr; }, 10.0));
  const TrajectoryData& first = *station->latest(kVehicle);
  const std::int64_t ahead_ns = utcNowNs() + 25'000'000'000;
  std::size_t k = 0;
  while (k + 1 < first.samples.size() && first.samples[k].utc_ns < ahead_ns) ++k;
  ObstacleUpdateData obstacle;
  obstacle.obstacle.id = 91;
  obstacle.obstacle.shape = ObstacleShape::kCylinder;
  obstacle.obstacle.size_m = Eigen::Vector3d(150.0, 0.0, 3000.0);
  obstacle.obstacle.center_m = first.samples[k].position_enu_m;
  ASSERT_TRUE(station->obstacles->write(obstacle).ok());
  // A loaded machine may answer with a hold first (a replan cut at the cycle's deadline) and the
  // route one cycle later: any revision after the first will do, as long as the vehicle's list
  // entry and the revision shown agree.
  ASSERT_TRUE(eventually(
      [&] {
        const std::string shown = revisionShown(*browser);
        return !shown.empty() && shown != "0" && pageText(*browser).find(kVehicle + " · rev " + shown) != std::string::npos;
      },
      20.0))
      << pageText(*browser) << daemon.err();
  EXPECT_TRUE(exists(*browser, "#obstacles li[data-obstacle=\"91\"]")) << pageText(*browser);
  EXPECT_TRUE(exists(*browser, "#obstacle-91"));

  // No-fly zones are not in the product yet: the state's list is empty, and a zone in the shape
  // the state reserves for them is drawn once one comes.
  EXPECT_FALSE(exists(*browser, "#map polygon.no-fly"));
  auto drawn = browser->script(
      "const m = state.map, lat = (m.south_deg + m.north_deg) / 2, lon = (m.west_deg + m.east_deg) / 2;"
      "receive(Object.assign({}, state, {no_fly_zones: [{ring: [{lat_deg: lat, lon_deg: lon},"
      "  {lat_deg: lat + 0.01, lon_deg: lon}, {lat_deg: lat, lon_deg: lon + 0.01}]}]}));"
      "return document.querySelectorAll('#map polygon.no-fly').length;");
  EXPECT_TRUE(drawn && *drawn == 1) << (drawn ? drawn->dump() : "script failed");

  browser.reset();
  gcs.signal(SIGINT);
  EXPECT_EQ(gcs.wait(10.0), 0) << gcs.err();
  daemon.signal(SIGTERM);
  EXPECT_EQ(daemon.wait(10.0), 0) << daemon.err();
}

}  // namespace
}  // namespace skyroute
