// skyroute px4: flies a vehicle's current skyroute trajectory with PX4 offboard control. It
// follows the vehicle's trajectories as `skyroute gcs` receives them and streams, at --rate-hz,
// OffboardControlMode and TrajectorySetpoint (NED from PX4's EKF origin, position with velocity
// and acceleration feed-forward, yaw from the heading) to PX4's uXRCE-DDS topics. What it streams
// and when it holds: service/offboard_follower.hpp; PX4 topics and layouts: service/dds/px4_io.hpp.
//
// Timestamps (microseconds) come from the monotonic clock, anchored once at start to the system
// clock (UTC): PX4's uXRCE-DDS client translates incoming timestamps from the agent's clock, which
// is the system clock, and a monotonic source keeps them increasing even if the system clock steps.
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

#include "service/cli/dds_cli_common.hpp"
#include "service/cli/dds_commands.hpp"
#include "service/dds/px4_io.hpp"
#include "service/dds/vehicle_feed.hpp"
#include "service/dds/wait_loop.hpp"
#include "service/offboard_follower.hpp"
#include "service/ros_names.hpp"

namespace skyroute::cli {

namespace {

constexpr const char* kTool = "px4";
constexpr double kOriginWaitS = 5.0;  // how long PX4 has to tell its EKF origin
constexpr double kMinRateHz = 20.0, kMaxRateHz = 50.0;

struct Px4Options {
  std::string vehicle;
  std::string ros_namespace;
  std::string rate_hz = "50";
  std::string origin;  // LAT,LON,ALT_AMSL; empty = PX4's VehicleLocalPosition
  int domain = 0;
  double silence_timeout_s = 3.0;
  double duration_s = 0.0;  // 0 = until Ctrl-C
};

// The monotonic clock as UTC nanoseconds: its reading at start is the system clock's.
class StreamClock {
 public:
  StreamClock() : utc0_ns_(utcNowNs()), steady0_(std::chrono::steady_clock::now()) {}
  std::int64_t utcNs(std::chrono::steady_clock::time_point t) const {
    return utc0_ns_ + std::chrono::duration_cast<std::chrono::nanoseconds>(t - steady0_).count();
  }

 private:
  std::int64_t utc0_ns_;
  std::chrono::steady_clock::time_point steady0_;
};

double parseRate(const std::string& text) {
  double rate = 0.0;
  try {
    std::size_t used = 0;
    rate = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    fail(kTool, kExitUsage, "--rate-hz '" + text + "' is not a number");
  }
  if (!(rate >= kMinRateHz && rate <= kMaxRateHz)) {
    fail(kTool, kExitUsage, "--rate-hz " + text + " is outside [20, 50] Hz");
  }
  return rate;
}

std::optional<GeoPoint> parseOrigin(const std::string& text) {
  if (text.empty()) return std::nullopt;
  auto point = parseGeoTriple(text, "--origin");
  if (!point) fail(kTool, kExitUsage, point.error().message);
  const GeoPoint& g = point->geo;
  if (std::abs(g.lat_deg) > 90.0 || std::abs(g.lon_deg) > 180.0) {
    fail(kTool, kExitUsage, "--origin '" + text + "': latitude must be in [-90, 90] and longitude in [-180, 180]");
  }
  return g;
}

std::string describeOrigin(const GeoPoint& g) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "lat=%.7f lon=%.7f alt_amsl_m=%.2f", g.lat_deg, g.lon_deg, g.alt_amsl_m);
  return buf;
}

void printEvents(OffboardFollower& follower) {
  for (const std::string& e : follower.takeEvents()) std::cout << "px4 " << e << std::endl;
}

void runPx4(const Px4Options& o) {
  if (o.vehicle.empty()) fail(kTool, kExitUsage, "--vehicle is required");
  const double rate_hz = parseRate(o.rate_hz);
  std::string ns = o.ros_namespace;
  while (!ns.empty() && ns.front() == '/') ns.erase(ns.begin());
  while (!ns.empty() && ns.back() == '/') ns.pop_back();
  if (!o.ros_namespace.empty() && !isValidRosName(ns)) {
    fail(kTool, kExitUsage, "--namespace '" + o.ros_namespace +
                                "' is not a ROS name ([A-Za-z0-9_/], no part starting with a digit)");
  }
  std::optional<GeoPoint> origin = parseOrigin(o.origin);
  if (!(o.silence_timeout_s > 0.0)) fail(kTool, kExitUsage, "--silence-timeout must be > 0 s");

  dds::Entity participant = openParticipant(kTool, o.domain);
  const dds_entity_t p = participant.get();
  auto feed = dds::VehicleFeed::create(p, o.vehicle);
  if (!feed) fail(kTool, kExitServiceUnavailable, feed.error().describe());
  auto setpoints = dds::Px4SetpointWriter::create(p, ns);
  if (!setpoints) fail(kTool, kExitServiceUnavailable, setpoints.error().describe());
  // Also with --origin, to learn when PX4 moves its origin away from the one given.
  auto origins = dds::Px4OriginReader::create(p, ns);
  if (!origins) fail(kTool, kExitServiceUnavailable, origins.error().describe());
  // A waitset with no reader: an interruptible sleep between ticks that Ctrl-C ends.
  auto loop = dds::WaitLoop::create(p);
  if (!loop) fail(kTool, kExitServiceUnavailable, loop.error().describe());
  stopOnSignals(loop->waitsetHandle());

  using Clock = std::chrono::steady_clock;
  const std::string local_position = dds::px4Topic(ns, dds::kPx4LocalPositionPath);
  if (!origin) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(kOriginWaitS);
    while (!origin) {
      const double left_s = std::chrono::duration<double>(deadline - Clock::now()).count();
      if (left_s <= 0.0) {
        fail(kTool, kExitServiceUnavailable,
             "no EKF origin from PX4 within 5 s: nothing with ref_lat/ref_lon/ref_alt set arrived on " + local_position +
                 " (domain " + std::to_string(o.domain) +
                 "); is the uXRCE-DDS agent running with that namespace? Or give --origin LAT,LON,ALT_AMSL");
      }
      auto outcome = loop->runOnce(std::min(left_s, 0.05));
      if (outcome && *outcome == dds::WaitLoop::Outcome::kStopped) return;
      auto taken = origins->takeOrigin();
      if (!taken) fail(kTool, kExitServiceUnavailable, taken.error().describe());
      origin = *taken;
    }
    std::cout << "px4 origin " << describeOrigin(*origin) << " from " << local_position << std::endl;
  } else {
    std::cout << "px4 origin " << describeOrigin(*origin) << " from --origin" << std::endl;
  }
  std::cout << "px4 vehicle=" << o.vehicle << " rate_hz=" << rate_hz << " setpoints="
            << dds::px4Topic(ns, dds::kPx4SetpointPath) << "," << dds::px4Topic(ns, dds::kPx4OffboardModePath)
            << " domain=" << o.domain << std::endl;

  OffboardFollower follower(*origin, {o.silence_timeout_s});
  const StreamClock clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  const auto started = Clock::now();
  auto next = started;
  std::uint64_t last_stamp_us = 0;
  bool streaming = false;
  for (;;) {
    const auto now = Clock::now();
    if (now < next) {
      auto outcome = loop->runOnce(std::chrono::duration<double>(next - now).count());
      if (!outcome) fail(kTool, kExitServiceUnavailable, outcome.error().describe());
      if (*outcome == dds::WaitLoop::Outcome::kStopped) break;
      continue;
    }
    const std::int64_t now_utc_ns = clock.utcNs(now);
    // The setpoint first, from what is known, so its timing never waits for the work below.
    const std::optional<OffboardSetpoint> setpoint = follower.step(now_utc_ns);
    printEvents(follower);
    if (setpoint) {
      // Strictly increasing, whatever the arithmetic: PX4 drops stale setpoints.
      const std::uint64_t stamp_us =
          std::max(last_stamp_us + 1, static_cast<std::uint64_t>(setpoint->time_utc_ns / 1000));
      Status written = setpoints->write(*setpoint, stamp_us);
      if (!written) fail(kTool, kExitServiceUnavailable, written.error().describe());
      last_stamp_us = stamp_us;
      if (!streaming) std::cout << "px4 streaming setpoints" << std::endl;
      streaming = true;
    }

    // Then what arrived since the last tick (preparing a new trajectory takes milliseconds); it
    // counts from the next tick on.
    auto update = feed->take();
    if (!update) fail(kTool, kExitServiceUnavailable, update.error().describe());
    for (const Error& e : update->rejected) std::cerr << "skyroute px4: skipped a bad sample: " << e.describe() << std::endl;
    if (update->heard_daemon) follower.heardFromDaemon(now_utc_ns);
    for (const TrajectoryData& t : update->trajectories) {
      std::cout << describe(t) << std::endl;
      (void)follower.offer(t, now_utc_ns);  // a rejected one is reported as an event
    }
    if (update->retracted) follower.retract();
    auto moved = origins->takeOrigin();
    if (moved && *moved && (std::abs((*moved)->lat_deg - origin->lat_deg) > 1e-9 ||
                            std::abs((*moved)->lon_deg - origin->lon_deg) > 1e-9 ||
                            std::abs((*moved)->alt_amsl_m - origin->alt_amsl_m) > 1e-3)) {
      origin = **moved;
      follower.setOrigin(*origin);
      std::cout << "px4 origin moved to " << describeOrigin(*origin) << " (" << local_position << ")" << std::endl;
    }
    printEvents(follower);
    if (o.duration_s > 0.0 && std::chrono::duration<double>(now - started).count() >= o.duration_s) break;
    next += period;
    // Late by more than a period (a stalled machine): skip the lost ticks instead of bursting.
    if (next + period < Clock::now()) next = Clock::now() + period;
  }
  std::cout << "px4 stopped; mode=" << to_string(follower.mode()) << std::endl;
}

}  // namespace

void addPx4Command(CLI::App& app) {
  auto options = std::make_shared<Px4Options>();
  CLI::App* cmd = app.add_subcommand(
      "px4", "Fly a vehicle's current trajectory with PX4 offboard control (uXRCE-DDS setpoints)");
  cmd->add_option("--vehicle", options->vehicle, "The skyroute vehicle id to follow (required)");
  cmd->add_option("--namespace", options->ros_namespace,
                  "PX4's uXRCE-DDS namespace (uxrce_dds_client start -n NS): topics rt/NS/fmu/...; default none: rt/fmu/...");
  cmd->add_option("--rate-hz", options->rate_hz, "Setpoint rate, 20 to 50 Hz")->type_name("HZ")->capture_default_str();
  cmd->add_option("--origin", options->origin,
                  "PX4's EKF origin (default: read from fmu/out/vehicle_local_position)")
      ->type_name("LAT,LON,ALT_AMSL");
  cmd->add_option("--domain", options->domain, "DDS domain id")->capture_default_str();
  addSecurityOption(*cmd);
  cmd->add_option("--silence-timeout", options->silence_timeout_s,
                  "Hold the last position when skyrouted is silent this long, seconds")
      ->capture_default_str();
  cmd->add_option("--duration", options->duration_s, "Stop after S seconds (0 = until Ctrl-C)")->capture_default_str();
  cmd->footer(helpFooter({"skyroute px4 --domain 0 --vehicle uav-1",
                          "skyroute px4 --domain 0 --vehicle uav-1 --namespace px4_1 --origin 46.90,15.03,900 --rate-hz 50"}));
  cmd->callback([options] { runPx4(*options); });
}

}  // namespace skyroute::cli
