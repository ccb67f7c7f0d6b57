// Writing trajectories to files a ground station or GIS opens: CSV, and GeoJSON and KML through
// GDAL's OGR drivers (one 3D line per trajectory, WGS84, with vehicle, plan, revision, request,
// duration, sample count and height datum as attributes). Each format's heights mean what the format
// says: GeoJSON z is above the WGS 84 ellipsoid (RFC 7946), KML `absolute` is above sea level (AMSL),
// and the CSV names the datum in its columns (alt_amsl_m and alt_ellipsoid_m).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "service/geo_samples.hpp"
#include "service/height_datum.hpp"
#include "service/mission_types.hpp"

namespace skyroute {

// time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg,
// alt_ellipsoid_m (last, so readers that index the other columns by position keep working).
inline constexpr const char* kTrajectoryDataCsvHeader =
    "time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg,"
    "alt_ellipsoid_m";

Status writeTrajectoryCsv(std::ostream& out, const TrajectoryData& trajectory, const Egm96Geoid& geoid,
                          bool header = true);
// Several trajectories in one CSV: a vehicle_id column is prepended. Needs the EGM96 grid (the
// ellipsoidal heights): without it, an error and no file.
Status writeTrajectoriesCsv(const std::string& path, const std::vector<TrajectoryData>& trajectories,
                            const GeoidOptions& geoid = {});

// `skyroute plan`'s CSV (trajectory/geo_samples.hpp's columns) with the ellipsoidal heights filled in.
Status writeGeoSamplesCsv(const std::string& path, std::vector<GeoSample> samples, const GeoidOptions& geoid = {});

// driver: "GeoJSON" (z above the ellipsoid: needs the EGM96 grid) or "KML" (altitudeMode absolute,
// AMSL; one line style per vehicle, with distinct colours). Other drivers are refused, since the
// height datum is each format's own.
Status writeTrajectoriesOgr(const std::string& path, const std::string& driver,
                            const std::vector<TrajectoryData>& trajectories, const GeoidOptions& geoid = {});

// The KML line colour of the index-th vehicle of a file, "#RRGGBB": a palette of well separated
// colours first, then hues spread by the golden angle, so no two vehicles of a file look alike.
std::string vehicleColourHex(std::size_t index);

}  // namespace skyroute
