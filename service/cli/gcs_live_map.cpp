#include "service/cli/gcs_live_map.hpp"

#include <filesystem>
#include <iostream>

#include "service/cli/cli_common.hpp"
#include "service/gcs_allowed_hosts.hpp"

namespace skyroute::cli {

std::unique_ptr<GcsLiveMap> GcsLiveMap::start(const std::string& tool, const std::string& serve,
                                              const std::string& dem_path, GcsWebLimits limits) {
  // The address and names first: a typo should not wait for the terrain.
  auto address = parseServeAddress(serve);
  if (!address) fail(tool, kExitUsage, "--serve " + address.error().message);
  for (std::string& name : limits.allowed_hosts) {
    auto canonical = canonicalHostName(name, "--allow-host");
    if (!canonical) fail(tool, kExitUsage, canonical.error().message);
    name = *canonical;
  }

  const std::string dem_file = dem_path.empty() ? demPathOf(tool, DaemonConfig{}) : dem_path;
  auto dem = Dem::load(dem_file);
  if (!dem) fail(tool, kExitBadInput, "--dem " + dem.error().describe());
  auto terrain = Heightfield::build(*dem);
  if (!terrain) fail(tool, kExitBadInput, "--dem " + terrain.error().describe());
  auto image = hillshadePngWgs84(**dem);
  if (!image) fail(tool, kExitBadInput, "--dem " + image.error().describe());

  auto live = std::unique_ptr<GcsLiveMap>(new GcsLiveMap());
  live->state_ = std::make_shared<GcsMapState>(*terrain, std::move(*image),
                                               std::filesystem::path(dem_file).filename().string());
  auto server = GcsWebServer::start(*address, live->state_, limits);
  if (!server) {
    const bool in_use = server.error().kind == ServeError::Kind::kPortInUse;
    fail(tool, in_use ? kExitServiceUnavailable : kExitUsage, "--serve " + serve + ": " + server.error().message);
  }
  live->server_ = std::move(*server);
  return live;
}

void GcsLiveMap::announce() const { std::cout << "live map on " << server_->url() << std::endl; }

}  // namespace skyroute::cli
