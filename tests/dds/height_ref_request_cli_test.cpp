// `skyroute request --height-ref ellipsoid` publishes the mission in AMSL, the service's datum:
// the test plays the planning service (heartbeat, request reader, status writer) on DDS domain
// 231 and reads what the tool sends. An unknown reference is a usage error naming the option.
#include <cmath>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "service/dds/loopback.hpp"
#include "service/height_datum.hpp"
#include "tests/cli_run.hpp"
#include "tests/dds/fake_planning_service.hpp"

namespace skyroute {
namespace {

constexpr int kDomain = 231;

std::string triple(double lat_deg, double lon_deg, double alt_m) {
  std::ostringstream s;
  s.precision(17);
  s << lat_deg << "," << lon_deg << "," << alt_m;
  return s.str();
}

TEST(HeightRefRequestCli, EllipsoidalHeightsArePublishedAsAmsl) {
  dds::useLoopbackOnly();  // inherited by the CLI process
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  struct Geo {
    double lat_deg, lon_deg, alt_amsl_m;
  };
  const Geo begin{44.20, -71.30, 1000.0}, via{44.21, -71.31, 1100.0}, end{44.23, -71.28, 1050.0};
  auto ellipsoidal = [&](const Geo& g) {
    return triple(g.lat_deg, g.lon_deg, *geoid->ellipsoidFromAmslM(g.lat_deg, g.lon_deg, g.alt_amsl_m));
  };

  const auto service = testing::startFakePlanningService(kDomain);
  ASSERT_TRUE(service);
  auto& loop = service->loop;
  auto& statuses = service->statuses;
  auto& heard = service->heard;

  testing::CliOutput request;
  std::thread tool([&] {
    request = testing::runCli("request --domain " + std::to_string(kDomain) + " --vehicle uav-h --height-ref ellipsoid" +
                              " --begin " + ellipsoidal(begin) + " --points \"" + ellipsoidal(via) + "\" --end " +
                              ellipsoidal(end) + " --wait 30");
  });
  ASSERT_TRUE(loop->run(30.0).ok());
  if (heard.size() == 1) {
    const MissionRequestData& m = heard.front();
    PlanStatusData done{m.request_id, m.vehicle_id, PlanState::kSucceeded, PlanErrorCode::kNone, "", "", 0.1};
    EXPECT_TRUE(statuses->write(done).ok());
  }
  tool.join();
  ASSERT_EQ(heard.size(), 1u) << request.text;
  EXPECT_EQ(request.exit_code, 0) << request.text;
  const MissionRequestData& m = heard.front();
  ASSERT_EQ(m.points.size(), 1u);
  EXPECT_NEAR(m.begin.geo.alt_amsl_m, begin.alt_amsl_m, 1e-6);
  EXPECT_NEAR(m.points[0].geo.alt_amsl_m, via.alt_amsl_m, 1e-6);
  EXPECT_NEAR(m.end.geo.alt_amsl_m, end.alt_amsl_m, 1e-6);
  EXPECT_DOUBLE_EQ(m.begin.geo.lat_deg, begin.lat_deg);  // only heights change
  // Here the geoid lies tens of metres below the ellipsoid, so a missed conversion would show.
  EXPECT_GT(std::abs(*geoid->undulationM(begin.lat_deg, begin.lon_deg)), 10.0);
}

TEST(HeightRefRequestCli, UnknownReferenceIsAUsageErrorNamingTheOption) {
  const auto r = testing::runCli("request --domain " + std::to_string(kDomain) +
                                 " --vehicle v --height-ref wgs84 --begin 44.2,-71.3,1000 --end 44.23,-71.28,1000 --wait 1");
  EXPECT_EQ(r.exit_code, 2) << r.text;
  EXPECT_NE(r.text.find("--height-ref"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("'wgs84' is not a height reference"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace skyroute
