#include "service/cli/dds_cli_common.hpp"

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "service/cli/dds_commands.hpp"

namespace skyroute::cli {

namespace {
std::atomic<dds_entity_t> g_stop_waitset{0};
std::string g_security_dir;  // --security of the command being run

extern "C" void onStopSignal(int) {
  const dds_entity_t ws = g_stop_waitset.load();
  if (ws > 0) (void)dds_waitset_set_trigger(ws, true);
}
}  // namespace

CLI::Option* addSecurityOption(CLI::App& command) {
  return command.add_option("--security", g_security_dir,
                     "DDS Security: this program's identity folder, made by scripts/make-pki.sh (DIR/station to send "
                     "requests, DIR/observer to watch); default: unsecured (docs/dds.md)");
}

dds::Entity openParticipant(const std::string& tool, int domain) {
  if (domain < 0 || domain > 232) fail(tool, kExitUsage, "--domain " + std::to_string(domain) + " is outside [0, 232]");
  auto participant = dds::createParticipant(static_cast<dds_domainid_t>(domain), "", g_security_dir);
  if (!participant) {
    if (!g_security_dir.empty()) fail(tool, kExitBadInput, "--security " + participant.error().describe());
    fail(tool, kExitServiceUnavailable, "domain " + std::to_string(domain) + ": " + participant.error().describe());
  }
  return std::move(*participant);
}

void stopOnSignals(dds_entity_t waitset) {
  g_stop_waitset.store(waitset);
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
}

std::string describe(const TrajectoryData& t) {
  std::ostringstream out;
  out << "trajectory vehicle=" << t.vehicle_id << " plan=" << t.plan_id << " revision=" << t.revision
      << " request=" << t.request_id << " samples=" << t.samples.size();
  if (!t.samples.empty()) {
    char buf[256];
    const auto& a = t.samples.front();
    const auto& b = t.samples.back();
    std::snprintf(buf, sizeof buf, " duration_s=%.2f start=%.6f,%.6f,%.1f end=%.6f,%.6f,%.1f", b.t_rel_s - a.t_rel_s,
                  a.geo.lat_deg, a.geo.lon_deg, a.geo.alt_amsl_m, b.geo.lat_deg, b.geo.lon_deg, b.geo.alt_amsl_m);
    out << buf;
  }
  out << " legs=" << t.legs.size() << " order=";
  for (std::size_t i = 0; i < t.visiting_order.size(); ++i) out << (i ? "," : "") << t.visiting_order[i];
  // Which daemon it comes from: with a hot standby, the primary or (after a takeover) the standby.
  if (!t.source_instance.empty()) out << " from=" << t.source_instance << " role=" << t.source_role;
  return out.str();
}

std::string describe(const PlanStatusData& s) {
  std::ostringstream out;
  out << "status request=" << s.request_id << " vehicle=" << s.vehicle_id << " state=" << to_string(s.state)
      << " error=" << to_string(s.error_code) << " planning_time_s=" << s.planning_time_s;
  if (!s.field.empty()) out << " field=" << s.field;
  if (!s.message.empty()) out << " message=\"" << s.message << "\"";
  return out.str();
}

}  // namespace skyroute::cli
