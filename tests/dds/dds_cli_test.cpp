// The DDS tools as separate processes on loopback: replay -> record keeps a feed's content and
// timing; gcs joining late receives and exports every vehicle's current trajectory; request
// publishes a mission and its exit code follows the status a (test-played) service returns.
// The CLI is SKYROUTE_CLI, or $SKYROUTE_DDS_CLI when set (to test another build of the tools).
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "service/dds/loopback.hpp"
#include "service/dds/service_instance.hpp"
#include "service/dds/typed_io.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/height_datum.hpp"
#include "service/obstacle_feed.hpp"
#include "terrain/heightfield.hpp"
#include "tests/dds/fake_planning_service.hpp"
#include "tests/dds/named_trajectory.hpp"
#include "tests/terrain_data.hpp"
#include "tests/text_file.hpp"

extern char** environ;

namespace skyroute {
namespace {

class LoopbackEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { dds::useLoopbackOnly(); }  // inherited by the CLI processes
};
const auto* const kLoopback = ::testing::AddGlobalTestEnvironment(new LoopbackEnvironment);

std::string cli() {
  const char* override_path = std::getenv("SKYROUTE_DDS_CLI");
  return override_path != nullptr ? override_path : SKYROUTE_CLI;
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("skyroute_dds_cli_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string slurp(const std::string& path) { return skyroute::testing::readTextFile(path); }

// A child process running `sh -c command` with stdout and stderr in files.
struct Child {
  pid_t pid = -1;
  std::string out_path, err_path;

  static Child start(const std::string& args, const std::string& name) {
    Child c;
    c.out_path = tempPath(name + ".out");
    c.err_path = tempPath(name + ".err");
    const std::string command = cli() + " " + args + " > " + c.out_path + " 2> " + c.err_path;
    const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
    if (posix_spawn(&c.pid, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) c.pid = -1;
    return c;
  }
  // Exit code, or -1 if it did not end within timeout_s (it is then killed).
  int wait(double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    return -1;
  }
  std::string out() const { return slurp(out_path); }
  std::string err() const { return slurp(err_path); }
  ~Child() {
    std::filesystem::remove(out_path);
    std::filesystem::remove(err_path);
  }
};

int run(const std::string& args, const std::string& name, std::string* out = nullptr, std::string* err = nullptr,
        double timeout_s = 60.0) {
  Child c = Child::start(args, name);
  const int code = c.wait(timeout_s);
  if (out) *out = c.out();
  if (err) *err = c.err();
  return code;
}

// main.cpp registers the DDS tools, so a CLI without them is a defect: a failure, not a skip.
#define ASSERT_TOOLS_REGISTERED()                                                                    \
  if (std::string help; run("replay --help", "probe", &help) != 0 || help.find("--speed") == std::string::npos) \
  GTEST_FAIL() << cli() << " has no DDS tools (addGcsCommand etc. of service/cli/dds_commands.hpp are not "  \
                          "registered in main.cpp)"

FeedEntry sphereAt(std::uint64_t id, double t_s, const Eigen::Vector3d& at) {
  FeedEntry e;
  e.t_s = t_s;
  e.update.obstacle.id = id;
  e.update.obstacle.shape = ObstacleShape::kSphere;
  e.update.obstacle.size_m = {25.0 + static_cast<double>(id), 0.0, 0.0};
  e.update.obstacle.center_m = at;
  e.valid_for_s = 30.0;
  return e;
}

// Domain ids 120..124 belong to this file.
TEST(DdsCli, ReplayThenRecordKeepsContentAndTiming) {
  ASSERT_TOOLS_REGISTERED();
  const std::string feed_path = tempPath("in.jsonl");
  const std::string recorded_path = tempPath("recorded.jsonl");
  std::vector<FeedEntry> entries = {sphereAt(1, 0.0, {0, 0, 500}), sphereAt(2, 0.4, {100, 0, 500}),
                                    sphereAt(1, 0.8, {200, 50, 520})};
  FeedEntry bounce;
  bounce.t_s = 1.2;
  bounce.update.obstacle.id = 3;
  bounce.update.obstacle.shape = ObstacleShape::kEllipsoid;
  bounce.update.obstacle.size_m = {600, 600, 300};
  bounce.update.obstacle.motion = BackAndForth{{4900, 5400, 400}, {10400, 5400, 400}, 60.0, 0.0};
  bounce.update.obstacle.center_m = bounce.update.obstacle.motion->from_m;
  entries.push_back(bounce);
  ASSERT_TRUE(writeObstacleFeed(feed_path, entries).ok());
  {  // a malformed line in the middle: reported by number, skipped
    std::ofstream append(feed_path, std::ios::app);
    append << "{\"t_s\": 2.0, \"obstacle\": {\"id\": 9, \"shape\": \"blob\"}}\n";
  }

  Child recorder = Child::start("record " + recorded_path + " --domain 120 --count 4 --timeout 30", "record");
  std::string replay_out, replay_err;
  const int replay_code = run("replay " + feed_path + " --domain 120 --readers 1 --wait 20", "replay", &replay_out, &replay_err);
  EXPECT_EQ(replay_code, 0) << replay_err;
  EXPECT_NE(replay_err.find(feed_path + ":6:"), std::string::npos) << replay_err;
  EXPECT_NE(replay_err.find("obstacle.shape"), std::string::npos) << replay_err;
  EXPECT_NE(replay_out.find("published 4"), std::string::npos) << replay_out;
  ASSERT_EQ(recorder.wait(30.0), 0) << recorder.err();

  auto recorded = readObstacleFeed(recorded_path);
  std::filesystem::remove(feed_path);
  std::filesystem::remove(recorded_path);
  ASSERT_TRUE(recorded.ok()) << recorded.error().describe();
  ASSERT_EQ(recorded->entries.size(), entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const FeedEntry& got = recorded->entries[i];
    const FeedEntry& sent = entries[i];
    EXPECT_EQ(got.update.obstacle.id, sent.update.obstacle.id);
    EXPECT_EQ(got.update.obstacle.shape, sent.update.obstacle.shape);
    EXPECT_EQ(got.update.obstacle.size_m, sent.update.obstacle.size_m);
    EXPECT_EQ(got.update.obstacle.center_m, sent.update.obstacle.center_m);
    EXPECT_EQ(got.update.obstacle.motion.has_value(), sent.update.obstacle.motion.has_value());
    // Timing: the recorder counts from the first update, loopback adds milliseconds.
    EXPECT_NEAR(got.t_s, sent.t_s, 0.15) << i;
    ASSERT_EQ(got.valid_for_s.has_value(), sent.valid_for_s.has_value());
    if (sent.valid_for_s) {
      EXPECT_NEAR(*got.valid_for_s, *sent.valid_for_s, 0.15);
    }
  }
}

// An obstacle the feed places in WGS84 is published at the ENU position of the daemon's frame
// (the embedded terrain's, as skyrouted's by default).
TEST(DdsCli, ReplayPlacesPositionsInDegreesInTheDemsFrame) {
  ASSERT_TOOLS_REGISTERED();
  const auto terrain = testing::defaultTerrainHeightfield();
  ASSERT_TRUE(terrain);
  const GeoPoint anchor = terrain->frame().anchor();
  const GeoPoint at{anchor.lat_deg + 0.01, anchor.lon_deg + 0.02, 1500.0};
  const std::string feed_path = tempPath("geo.jsonl");
  const std::string recorded_path = tempPath("geo_recorded.jsonl");
  {
    std::ofstream feed(feed_path);
    feed << obstacleFeedHeaderLine() << "\n"
         << nlohmann::json{{"t_s", 0},
                           {"obstacle",
                            {{"id", 7},
                             {"shape", "sphere"},
                             {"size_m", {100, 0, 0}},
                             {"position_deg", {at.lat_deg, at.lon_deg, at.alt_amsl_m}}}}}
                .dump()
         << "\n";
  }
  Child recorder = Child::start("record " + recorded_path + " --domain 217 --count 1 --timeout 30", "geo_record");
  std::string out, err;
  EXPECT_EQ(run("replay " + feed_path + " --domain 217 --readers 1 --wait 20", "geo_replay", &out, &err), 0) << err;
  ASSERT_EQ(recorder.wait(30.0), 0) << recorder.err();
  auto recorded = readObstacleFeed(recorded_path);
  ASSERT_TRUE(recorded.ok()) << recorded.error().describe();
  ASSERT_EQ(recorded->entries.size(), 1u);
  const Eigen::Vector3d expected = terrain->frame().toEnu(at);
  EXPECT_LT((recorded->entries[0].update.obstacle.center_m - expected).norm(), 1e-3)
      << recorded->entries[0].update.obstacle.center_m.transpose() << " vs " << expected.transpose();
  EXPECT_GT(expected.head<2>().norm(), 1000.0);
  // A DEM that cannot be read is a bad input file.
  EXPECT_EQ(run("replay " + feed_path + " --domain 217 --dem /nonexistent/dem.tif", "geo_nodem", &out, &err), 3);
  EXPECT_NE(err.find("--dem"), std::string::npos) << err;
  std::filesystem::remove(feed_path);
  std::filesystem::remove(recorded_path);
}

TrajectoryData trajectoryOf(const std::string& vehicle, std::uint32_t revision, std::size_t n) {
  TrajectoryData t = testing::namedTrajectory(vehicle, revision);
  t.created_utc_ns = utcNowNs();
  t.visiting_order = {0, 1, 2};
  t.legs = {{0, 1, 0.0, 5.0}, {1, 2, 5.0, 10.0}};
  for (std::size_t i = 0; i < n; ++i) {
    TrajectorySampleData s;
    s.t_rel_s = 0.5 * static_cast<double>(i);
    s.utc_ns = t.created_utc_ns + static_cast<std::int64_t>(s.t_rel_s * 1e9);
    s.position_enu_m = {20.0 * s.t_rel_s, 5.0 * revision, 900.0};
    s.velocity_enu_mps = {20.0, 0.0, 0.0};
    s.heading_deg = 90.0;
    s.geo = GeoPoint{44.25 + 0.001 * static_cast<double>(revision), -71.30 + 0.0002 * static_cast<double>(i), 900.0};
    t.samples.push_back(s);
  }
  return t;
}

TEST(DdsCli, LateGroundStationGetsEveryVehicleAndExports) {
  ASSERT_TOOLS_REGISTERED();
  auto participant = dds::createParticipant(121);
  ASSERT_TRUE(participant.ok());
  auto writer = dds::Writer<TrajectoryData>::create(participant->get());
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->write(trajectoryOf("alpha", 1, 11)).ok());
  ASSERT_TRUE(writer->write(trajectoryOf("bravo", 1, 7)).ok());
  ASSERT_TRUE(writer->write(trajectoryOf("alpha", 2, 13)).ok());  // replaces alpha's revision 1

  const std::string csv = tempPath("gcs.csv"), geojson = tempPath("gcs.geojson"), kml = tempPath("gcs.kml");
  const std::string plans = tempPath("gcs_plans");
  std::string out, err;
  const int code = run("gcs --domain 121 --count 2 --timeout 30 --csv " + csv + " --geojson " + geojson + " --kml " + kml +
                           " --plan " + plans,
                       "gcs", &out, &err);
  ASSERT_EQ(code, 0) << out << err;
  EXPECT_NE(out.find("vehicle=alpha plan=plan-alpha revision=2"), std::string::npos) << out;
  EXPECT_EQ(out.find("vehicle=alpha plan=plan-alpha revision=1"), std::string::npos) << out;
  EXPECT_NE(out.find("vehicle=bravo"), std::string::npos) << out;

  // CSV: header, then 13 + 7 rows; the first alpha row is revision 2's first sample.
  std::istringstream lines(slurp(csv));
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header, "vehicle_id,time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg,"
                    "alt_ellipsoid_m");
  std::vector<std::string> rows;
  while (std::getline(lines, row)) rows.push_back(row);
  ASSERT_EQ(rows.size(), 20u);
  EXPECT_EQ(rows[0].rfind("alpha,0.000,44.25200000,-71.30000000,900.000,0.000,10.000,900.000,20.0000", 0), 0u) << rows[0];

  // GeoJSON: two 3D lines with lon, lat and the height above the WGS 84 ellipsoid.
  auto geoid = Egm96Geoid::load();
  ASSERT_TRUE(geoid.ok()) << geoid.error().describe();
  const nlohmann::json gj = nlohmann::json::parse(slurp(geojson), nullptr, false);
  ASSERT_FALSE(gj.is_discarded());
  ASSERT_EQ(gj["features"].size(), 2u);
  for (const auto& f : gj["features"]) {
    const std::string vehicle = f["properties"]["vehicle_id"];
    const auto& coords = f["geometry"]["coordinates"];
    ASSERT_EQ(coords.size(), vehicle == "alpha" ? 13u : 7u);
    EXPECT_NEAR(coords[0][0].get<double>(), -71.30, 1e-9);
    EXPECT_NEAR(coords[0][2].get<double>(),
                *geoid->ellipsoidFromAmslM(coords[0][1].get<double>(), coords[0][0].get<double>(), 900.0), 1e-6);
    if (vehicle == "alpha") {
      EXPECT_EQ(f["properties"]["revision"], 2);
      EXPECT_NEAR(coords[0][1].get<double>(), 44.252, 1e-9);
    }
  }
  const std::string kml_text = slurp(kml);
  EXPECT_NE(kml_text.find("alpha"), std::string::npos);
  EXPECT_NE(kml_text.find("bravo"), std::string::npos);
  EXPECT_NE(kml_text.find("<coordinates>"), std::string::npos);
  EXPECT_NE(kml_text.find("<altitudeMode>absolute</altitudeMode>"), std::string::npos);
  // One QGroundControl plan per vehicle, altitudes AMSL.
  for (const std::string vehicle : {"alpha", "bravo"}) {
    const nlohmann::json plan = nlohmann::json::parse(slurp(plans + "/" + vehicle + ".plan"), nullptr, false);
    ASSERT_FALSE(plan.is_discarded()) << vehicle;
    EXPECT_EQ(plan["mission"]["globalPlanAltitudeMode"], 2);
    EXPECT_NEAR(plan["mission"]["items"][0]["Altitude"].get<double>(), 900.0, 1e-9);
  }
  for (const auto& p : {csv, geojson, kml}) std::filesystem::remove(p);
  std::filesystem::remove_all(plans);
}

TEST(DdsCli, RequestExitCodeFollowsTheServiceAnswer) {
  ASSERT_TOOLS_REGISTERED();
  // The test plays the planning service: it reads requests and answers with statuses.
  const auto service = testing::startFakePlanningService(122);
  ASSERT_TRUE(service);
  auto& loop = service->loop;
  auto& statuses = service->statuses;
  auto& heard = service->heard;

  struct Answer {
    PlanState state;
    PlanErrorCode code;
    const char* field;
    int exit_code;
  };
  const Answer answers[] = {{PlanState::kFailed, PlanErrorCode::kUnderGround, "points[1].alt_amsl_m", 1},
                            {PlanState::kSucceeded, PlanErrorCode::kNone, "", 0}};
  int round = 0;
  for (const Answer& answer : answers) {
    // The first round spells the points the old way (hidden aliases); the second sets limits
    // from the command line, which the request carries.
    const std::string points = round == 0 ? "--begin 44.20,-71.30,1000 --points \"44.21,-71.31,1100;44.22,-71.29,1150\" "
                                            "--end 44.23,-71.28,1000"
                                          : "--from 44.20,-71.30,1000 --via \"44.21,-71.31,1100;44.22,-71.29,1150\" "
                                            "--to 44.23,-71.28,1000 --max-speed-mps 25 --clearance-m 80";
    Child request = Child::start("request --domain 122 --vehicle uav-9 " + points + " --wait 30",
                                 "request" + std::to_string(round));
    heard.clear();
    ASSERT_TRUE(loop->run(30.0).ok());
    ASSERT_EQ(heard.size(), 1u) << request.err();
    const MissionRequestData& m = heard.front();
    EXPECT_EQ(m.vehicle_id, "uav-9");
    ASSERT_EQ(m.points.size(), 2u);
    EXPECT_EQ(m.points[1].geo.alt_amsl_m, 1150.0);
    EXPECT_EQ(m.end.geo.lon_deg, -71.28);
    EXPECT_FALSE(m.request_id.empty());
    EXPECT_EQ(m.limits.max_speed_mps, round == 0 ? VehicleLimitsData{}.max_speed_mps : 25.0);
    EXPECT_EQ(m.limits.min_clearance_agl_m, round == 0 ? VehicleLimitsData{}.min_clearance_agl_m : 80.0);
    EXPECT_EQ(m.limits.max_accel_mps2, VehicleLimitsData{}.max_accel_mps2);

    PlanStatusData planning{m.request_id, m.vehicle_id, PlanState::kPlanning, PlanErrorCode::kNone, "", "", 0.0};
    ASSERT_TRUE(statuses->write(planning).ok());
    PlanStatusData other = planning;  // someone else's request: ignored by the tool
    other.request_id = "not-yours";
    other.state = PlanState::kFailed;
    ASSERT_TRUE(statuses->write(other).ok());
    PlanStatusData final_status{m.request_id, m.vehicle_id, answer.state, answer.code, answer.field,
                                std::string(answer.field) + " is under the ground", 0.25};
    ASSERT_TRUE(statuses->write(final_status).ok());
    EXPECT_EQ(request.wait(30.0), answer.exit_code) << request.out() << request.err();
    const std::string out = request.out();
    EXPECT_NE(out.find("state=planning"), std::string::npos) << out;
    EXPECT_EQ(out.find("not-yours"), std::string::npos) << out;
    if (answer.exit_code != 0) {
      EXPECT_NE(request.err().find("points[1].alt_amsl_m"), std::string::npos) << request.err();
    }
    ++round;
    ASSERT_TRUE(service->listen());
  }
}

TEST(DdsCli, RequestWithoutServiceOrWithBadInputFailsClearly) {
  ASSERT_TOOLS_REGISTERED();
  std::string out, err;
  EXPECT_EQ(run("request --domain 123 --vehicle v --begin 44.2,-71.3,1000 --points 44.21,-71.31,1100 "
                "--end 44.23,-71.28,1000 --wait 1",
                "noservice", &out, &err),
            4);  // the service is unavailable
  EXPECT_NE(err.find("no planning service"), std::string::npos) << err;
  // --begin, --points and --end are the hidden old names of --from, --via and --to: errors name
  // the options as --help shows them.
  EXPECT_EQ(run("request --domain 123 --vehicle v --begin 44.2,-71.3 --end 44.23,-71.28,1000 --wait 1", "badbegin", &out, &err),
            2);
  EXPECT_NE(err.find("--from"), std::string::npos) << err;
  EXPECT_EQ(run("request --domain 123 --vehicle v --from 44.2,-71.3,9 --via \"1,2,3;4,x,6\" --to 44.23,-71.28,1000",
                "badpoints", &out, &err),
            2);
  EXPECT_NE(err.find("--via[1]"), std::string::npos) << err;
  EXPECT_EQ(run("replay /nonexistent/feed.jsonl --domain 123", "nofeed", &out, &err), 3);  // an unreadable input file
  EXPECT_NE(err.find("/nonexistent/feed.jsonl"), std::string::npos) << err;
}

// Domain 220 belongs to this test: nobody publishes there. A ground station that received
// nothing timed out: exit 4, and no export that would look like a result. With --progress it says
// every 5 s what it is waiting for.
TEST(DdsCli, GroundStationThatReceivedNothingTimesOutAndWritesNothing) {
  ASSERT_TOOLS_REGISTERED();
  const std::string csv = tempPath("nothing.csv"), kml = tempPath("nothing.kml");
  std::filesystem::remove(csv);
  std::filesystem::remove(kml);
  std::string out, err;
  EXPECT_EQ(run("gcs --domain 220 --timeout 6 --progress --csv " + csv + " --kml " + kml, "gcs_nothing", &out, &err), 4)
      << err;
  EXPECT_NE(err.find("no trajectory arrived on domain 220 within 6 s"), std::string::npos) << err;
  EXPECT_NE(err.find("waiting on domain 220: 0 vehicle(s), 0 trajectories so far, "), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(csv));
  EXPECT_FALSE(std::filesystem::exists(kml));
  EXPECT_EQ(out.find("wrote"), std::string::npos) << out;
}

// A limit the request breaks is refused before anything is sent, named with where its value came
// from: an option, the mission file, or the default.
TEST(DdsCli, RequestNamesTheLimitABadValueBreaksAndWhereItCameFrom) {
  ASSERT_TOOLS_REGISTERED();
  const std::string points = " --vehicle v --from 44.2,-71.3,1000 --to 44.23,-71.28,1000 --wait 1";
  std::string out, err;
  // The default cruise speed (20 m/s) above a speed limit set lower.
  EXPECT_EQ(run("request --domain 216" + points + " --max-speed-mps 10", "slow", &out, &err), 2);
  EXPECT_NE(err.find("limits.v_ref_mps (default; --vref-mps sets it)"), std::string::npos) << err;
  EXPECT_EQ(run("request --domain 216" + points + " --max-speed-mps 500", "fast", &out, &err), 2);
  EXPECT_NE(err.find("--max-speed-mps: "), std::string::npos) << err;
  EXPECT_NE(err.find("500"), std::string::npos) << err;
  // The mission file's value, and the option that overrides it.
  const std::string file = ::testing::TempDir() + "/fast_mission.json";
  nlohmann::json mission{{"request_id", "r"},
                         {"vehicle_id", "v"},
                         {"begin", {{"lat_deg", 44.2}, {"lon_deg", -71.3}, {"alt_amsl_m", 1000}}},
                         {"points", nlohmann::json::array()},
                         {"end", {{"lat_deg", 44.23}, {"lon_deg", -71.28}, {"alt_amsl_m", 1000}}},
                         {"limits", {{"max_speed_mps", 500}}}};
  std::ofstream(file) << mission.dump();
  EXPECT_EQ(run("request --domain 216 --wait 1 --file " + file, "fastfile", &out, &err), 3);
  EXPECT_NE(err.find("--file " + file + ": limits.max_speed_mps"), std::string::npos) << err;
  // Overridden, the request is valid and goes to the (absent) service.
  EXPECT_EQ(run("request --domain 216 --wait 1 --max-speed-mps 25 --file " + file, "fixedfile", &out, &err), 4) << err;
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace skyroute
