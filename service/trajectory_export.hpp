// Writing trajectories to files a ground station or GIS opens: CSV (the columns of
// `skyroute plan`), and GeoJSON and KML through GDAL's OGR drivers (one 3D line per trajectory,
// WGS84, with vehicle, plan, revision and request as attributes).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/mission_types.hpp"

namespace skyroute {

// Header: time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg
inline constexpr const char* kTrajectoryDataCsvHeader =
    "time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg";

void writeTrajectoryCsv(std::ostream& out, const TrajectoryData& trajectory, bool header = true);
// Several trajectories in one CSV: a vehicle_id column is prepended.
Status writeTrajectoriesCsv(const std::string& path, const std::vector<TrajectoryData>& trajectories);

// driver: "GeoJSON" or "KML" (any OGR vector driver that takes 3D line strings works).
Status writeTrajectoriesOgr(const std::string& path, const std::string& driver,
                            const std::vector<TrajectoryData>& trajectories);

}  // namespace skyroute
