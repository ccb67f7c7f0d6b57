// Sampled trajectory with WGS84 coordinates, and its CSV form (the `skyroute plan` output).
#pragma once

#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "planning/core/result.hpp"
#include "terrain/local_frame.hpp"
#include "trajectory/trajectory.hpp"

namespace skyroute {

struct GeoSample {
  TrajectoryState state;
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double alt_amsl_m = 0.0;  // up_m + the frame anchor's altitude (== up_m with the default anchor)
  // Above the WGS 84 ellipsoid: needs the geoid model, which lives in the service
  // (service/height_datum.hpp), so toGeoSamples leaves it unknown and the CSV writer refuses that.
  double alt_ellipsoid_m = std::numeric_limits<double>::quiet_NaN();
};

// Adds latitude, longitude (one bulk conversion through the frame) and altitude AMSL.
std::vector<GeoSample> toGeoSamples(const std::vector<TrajectoryState>& samples, const LocalFrame& frame);

// Exactly this header, then one row per sample:
// time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg,
// then a_east_mps2,a_north_mps2,a_up_mps2,j_east_mps3,j_north_mps3,j_up_mps3,speed_mps,alt_ellipsoid_m
// (alt_ellipsoid_m last, so readers that index the other columns by position keep working).
inline constexpr const char* kTrajectoryCsvHeader =
    "time_s,lat_deg,lon_deg,alt_amsl_m,east_m,north_m,up_m,v_east_mps,v_north_mps,v_up_mps,heading_deg,"
    "a_east_mps2,a_north_mps2,a_up_mps2,j_east_mps3,j_north_mps3,j_up_mps3,speed_mps,alt_ellipsoid_m";

Status writeTrajectoryCsv(std::ostream& out, const std::vector<GeoSample>& samples);
// Both: error kInvalidArgument naming the first sample whose alt_ellipsoid_m is unknown (nothing is
// written then). The file version: error kFileNotFound naming the path when it cannot be written.
Status writeTrajectoryCsv(const std::string& path, const std::vector<GeoSample>& samples);

}  // namespace skyroute
