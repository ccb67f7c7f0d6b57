// skyrouted: the planning daemon. Configuration from --config (TOML) with command-line overrides;
// the node goes configure -> activate, then the main thread waits for signals: SIGINT or SIGTERM
// deactivate it (in-flight plans are cancelled and answered, the waitset is triggered, writers
// flushed) and clean it up; SIGHUP reloads the configuration file (a reload that fails changes
// nothing and is logged); SIGUSR1 comes from the node itself when an older daemon serves the same
// service_id. The signals are blocked in every thread and taken with sigwait here, so no handler
// runs inside Cyclone's or the engine's threads.
// Exit codes: 0 stopped by a signal, 2 bad configuration, 3 could not start (a refused state
// journal among the causes), 5 another daemon
// serves this service_id on the domain (refused to start, or stopped for it).
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "service/cli/exit_codes.hpp"
#include "service/daemon_config.hpp"
#include "service/dds/mission_service.hpp"
#include "service/logging.hpp"
#include "service/shipped_data.hpp"
#include "service/state_dir_lock.hpp"

namespace {

struct Overrides {
  std::string config_path;
  std::optional<std::string> dem;
  std::optional<int> domain;
  std::optional<std::string> security_dir;
  std::optional<std::string> state_dir;
  std::optional<std::string> role;
  std::optional<std::string> shard_group;
  std::optional<std::string> log_level;
  std::optional<std::string> log_format;
  std::optional<std::uint64_t> seed;
};

skyroute::Result<skyroute::DaemonConfig> buildConfig(const Overrides& o) {
  auto loaded = o.config_path.empty() ? skyroute::Result<skyroute::DaemonConfig>(skyroute::DaemonConfig{})
                                      : skyroute::loadDaemonConfig(o.config_path);
  if (!loaded.ok()) return loaded.error();
  skyroute::DaemonConfig config = std::move(*loaded);
  if (o.dem) config.dem_path = *o.dem;
  if (o.domain) config.domain = *o.domain;
  if (o.security_dir) config.security_dir = *o.security_dir;
  if (o.state_dir) config.state_dir = *o.state_dir;
  if (o.role) config.role = *o.role;
  if (o.shard_group) config.shard_group = *o.shard_group;
  if (skyroute::Status s = skyroute::validateDaemonConfig(config); !s.ok()) return s.error();
  if (o.log_level) config.log_level = *o.log_level;
  if (o.log_format) config.log_format = *o.log_format;
  if (o.seed) config.engine.pipeline.seed = *o.seed;
  return config;
}

// terrain.dem "" means the embedded default terrain, found beside the binary (shipped data).
skyroute::Status resolveDefaultDem(skyroute::DaemonConfig& config) {
  if (!config.dem_path.empty()) return skyroute::Status::success();
  auto shipped = skyroute::defaultTerrainPath();
  if (!shipped) return shipped.error();
  config.dem_path = *shipped;
  return skyroute::Status::success();
}

constexpr int kExitConflict = 5;

int fail(const skyroute::Error& e, int code) {
  spdlog::critical("event=fatal field={} message=\"{}\"", e.field, e.message);
  std::cerr << "skyrouted: " << e.describe() << std::endl;
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("skyrouted: terrain-aware 3D trajectory planning service over Cyclone DDS", "skyrouted");
  app.set_version_flag("--version", std::string("skyrouted ") + SKYROUTE_VERSION);
  Overrides overrides;
  bool print_config = false;
  app.add_option("--config", overrides.config_path,
                 "TOML configuration file: the keys of skyroute plan --config (--print-config shows every key)")
      ->check(CLI::ExistingFile);
  app.add_option("--dem", overrides.dem, "DEM raster (any GDAL raster) (config terrain.dem; default: the embedded terrain)");
  app.add_option("--domain", overrides.domain, "DDS domain id (config dds.domain, default 0)")->check(CLI::Range(0, 232));
  app.add_option("--security", overrides.security_dir,
                 "DDS Security: this daemon's identity folder, made by scripts/make-pki.sh (DIR/daemon) (config "
                 "security.dir; default: unsecured)");
  app.add_option("--state-dir", overrides.state_dir,
                 "Keep the state journal (DIR/journal.sqlite) so a restart after a crash republishes every "
                 "vehicle's trajectory and plans unfinished missions again; docs/journal.md (config "
                 "service.state_dir; default: none)");
  app.add_option("--role", overrides.role,
                 "primary | standby: a hot standby serves the primary's domain and service_id, plans every request "
                 "too, and ground stations take its samples when the primary dies; docs/dds.md (config service.role, "
                 "default primary)")
      ->check(CLI::IsMember({"primary", "standby"}));
  app.add_option("--shard-group", overrides.shard_group,
                 "daemons on one domain with the same shard group split the vehicles between them, each with its own "
                 "dds.service_id; docs/dds.md (config service.shard_group, default \"\": not sharded)");
  app.add_option("--seed", overrides.seed, "Seed of every plan (config planning.seed, default 1)");
  app.add_option("--log-level", overrides.log_level, "trace | debug | info | warn | error (config log.level, default info)");
  app.add_option("--log-format", overrides.log_format, "text | json (config log.format, default text)");
  app.add_flag("--print-config", print_config, "print the effective configuration as TOML and exit");
  app.footer("Example:\n  skyrouted --dem ../shared/data/dem/N44W072.hgt --domain 7\n\n"
             "Exit codes: 0 stopped cleanly, 2 usage, 3 the configuration, the DEM or the state journal unreadable "
             "or invalid, "
             "4 DDS unavailable, 5 another daemon serves its service_id, 6 another daemon holds its state folder.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;  // --help and --version succeed; anything else is a usage error
  }

  // Blocked before any thread exists, so every thread inherits the mask and only sigwait sees them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGHUP);
  sigaddset(&signals, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  auto config = buildConfig(overrides);
  if (!config.ok()) {
    std::cerr << "skyrouted: " << config.error().describe() << std::endl;
    return 3;
  }
  if (print_config) {
    std::cout << skyroute::describeDaemonConfig(*config);
    return 0;
  }
  if (skyroute::Status s = resolveDefaultDem(*config); !s.ok()) return fail(s.error(), 3);
  if (skyroute::Status s = skyroute::setupLogging(config->log_level, config->log_format); !s.ok()) {
    std::cerr << "skyrouted: " << s.error().describe() << std::endl;
    return 2;
  }
  spdlog::info("event=starting version={} dem={} domain={} role={} shard_group={} strength={} security={} state_dir={}",
               SKYROUTE_VERSION, config->dem_path, config->domain, config->role,
               config->shard_group.empty() ? "none" : config->shard_group, skyroute::ownershipStrength(*config),
               config->security_dir.empty() ? "off" : config->security_dir,
               config->state_dir.empty() ? "none" : config->state_dir);

  skyroute::dds::MissionService service;
  std::string conflict;  // why the node must stop for another daemon (written before SIGUSR1)
  std::mutex conflict_mutex;
  service.onConflict([&](const std::string& message) {
    {
      std::lock_guard lock(conflict_mutex);
      conflict = message;
    }
    ::kill(::getpid(), SIGUSR1);  // taken by sigwait below
  });
  if (skyroute::Status s = service.configure(*config); !s.ok()) {
    return fail(s.error(), skyroute::isStateDirLocked(s.error()) ? skyroute::cli::kExitStateDirLocked : 3);
  }
  if (skyroute::Status s = service.activate(); !s.ok()) {
    (void)service.cleanup();
    return fail(s.error(), s.error().field == "dds.service_id" ? kExitConflict : 3);
  }
  spdlog::info("event=ready domain={} service_id={} role={} instance={}", config->domain, config->service_id,
               config->role, service.instance().instance_id);
  int exit_code = 0;

  for (;;) {
    int signal_number = 0;
    if (sigwait(&signals, &signal_number) != 0) continue;
    if (signal_number == SIGHUP) {
      spdlog::info("event=sighup config={}", overrides.config_path.empty() ? "(none)" : overrides.config_path);
      auto reloaded = buildConfig(overrides);
      if (reloaded.ok()) {
        if (skyroute::Status s = resolveDefaultDem(*reloaded); !s.ok()) reloaded = s.error();
      }
      if (!reloaded.ok()) {
        // A broken file must not take a running service down: keep the configuration in force.
        spdlog::error("event=reload_failed field={} message=\"{}\"", reloaded.error().field, reloaded.error().message);
        continue;
      }
      // A reload that fails (a missing DEM, an unusable domain, a terrain change while missions
      // fly) leaves the service exactly as it was.
      if (skyroute::Status s = service.reload(*reloaded); !s.ok()) {
        spdlog::error("event=reload_failed field={} message=\"{}\"", s.error().field, s.error().message);
        continue;
      }
      if (skyroute::Status s = skyroute::setupLogging(reloaded->log_level, reloaded->log_format); !s.ok()) {
        spdlog::error("event=reload_failed field={} message=\"{}\"", s.error().field, s.error().message);
      }
      continue;
    }
    if (signal_number == SIGUSR1) {
      std::lock_guard lock(conflict_mutex);
      if (conflict.empty()) continue;  // not from the node
      std::cerr << "skyrouted: " << conflict << std::endl;
      exit_code = kExitConflict;
      spdlog::info("event=stopping reason=service_conflict");
      break;
    }
    spdlog::info("event=stopping signal={}", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    break;
  }
  (void)service.deactivate();
  (void)service.cleanup();
  spdlog::info("event=stopped");
  return exit_code;
}
