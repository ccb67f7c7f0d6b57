#include "trajectory/knot_stops.hpp"

#include <algorithm>

#include "planning/core/enum_names.hpp"

namespace skyroute {

std::string_view to_string(FixedWaypointMode mode) {
  constexpr EnumName<FixedWaypointMode> kNames[] = {{FixedWaypointMode::kPass, "pass"},
                                                    {FixedWaypointMode::kStop, "stop"}};
  return enumName(kNames, mode);
}

std::optional<FixedWaypointMode> parseFixedWaypointMode(std::string_view text) {
  if (text == "pass") return FixedWaypointMode::kPass;
  if (text == "stop") return FixedWaypointMode::kStop;
  return std::nullopt;
}

namespace {

// Knot ranges [first, last] of the pieces between the stops.
std::vector<std::pair<std::size_t, std::size_t>> pieces(std::size_t knot_count, std::vector<std::size_t> stops) {
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t first = 0;
  for (std::size_t s : stops) {
    if (s == 0 || s + 1 >= knot_count) continue;  // the ends are the boundary's
    out.emplace_back(first, s);
    first = s;
  }
  out.emplace_back(first, knot_count - 1);
  return out;
}

std::vector<Eigen::Vector3d> slice(const std::vector<Eigen::Vector3d>& v, std::size_t first, std::size_t last) {
  return {v.begin() + static_cast<std::ptrdiff_t>(first), v.begin() + static_cast<std::ptrdiff_t>(last + 1)};
}

}  // namespace

Result<std::vector<double>> allocateTimesWithStops(const std::vector<Eigen::Vector3d>& knots,
                                                   const VehicleLimits& limits, const TimeAllocationOptions& options,
                                                   const std::vector<std::size_t>& stop_knots) {
  if (knots.size() < 2 || stop_knots.empty()) return allocateTimes(knots, limits, options);
  const auto ranges = pieces(knots.size(), stop_knots);
  std::vector<double> durations;
  durations.reserve(knots.size() - 1);
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    TimeAllocationOptions piece = options;
    if (k > 0) piece.start_speed_mps = 0.0;
    if (k + 1 < ranges.size()) piece.end_speed_mps = 0.0;
    Result<std::vector<double>> allocated = allocateTimes(slice(knots, ranges[k].first, ranges[k].second), limits, piece);
    if (!allocated) return allocated.error();
    durations.insert(durations.end(), allocated->begin(), allocated->end());
  }
  return durations;
}

Result<std::vector<Segment>> solveMinimumSnapSplineWithStops(const std::vector<Eigen::Vector3d>& knots,
                                                             const std::vector<double>& durations_s,
                                                             const SplineBoundary& boundary,
                                                             const std::vector<std::size_t>& stop_knots) {
  if (knots.size() < 2 || stop_knots.empty() || durations_s.size() + 1 != knots.size()) {
    return solveMinimumSnapSpline(knots, durations_s, boundary);
  }
  const auto ranges = pieces(knots.size(), stop_knots);
  std::vector<Segment> segments;
  segments.reserve(durations_s.size());
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    const auto [first, last] = ranges[k];
    SplineBoundary piece;  // rest to rest between stops
    if (k == 0) piece.start = boundary.start;
    if (k + 1 == ranges.size()) piece.end = boundary.end;
    const std::vector<double> times(durations_s.begin() + static_cast<std::ptrdiff_t>(first),
                                    durations_s.begin() + static_cast<std::ptrdiff_t>(last));
    Result<std::vector<Segment>> solved = solveMinimumSnapSpline(slice(knots, first, last), times, piece);
    if (!solved) return solved.error();
    segments.insert(segments.end(), solved->begin(), solved->end());
  }
  return segments;
}

}  // namespace skyroute
