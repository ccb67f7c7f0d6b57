#include "service/request_footprint.hpp"

#include <algorithm>
#include <cmath>

#include "service/number_text.hpp"
#include "service/trajectory_data.hpp"

namespace skyroute {
namespace {

// Bytes per unit of work, from the structures each stage keeps (rounded up):
// - a published sample lives at once as a TrajectoryState (112 B), a GeoSample (136 B), a
//   TrajectorySampleData (120 B), the IDL sample (120 B) and its serialized copy in the writer's
//   history (~130 B);
// - a spline knot is a segment (3 axes x 8 coefficients + duration), its knot, time and repair
//   bookkeeping;
// - an RRT* node is its position, cost, parent and children, and its k-d tree entry;
// - the ordering grid keeps a cost and a key per cell for each mission point's search.
constexpr double kBytesPerSample = 640.0;
constexpr double kBytesPerKnot = 512.0;
constexpr double kBytesPerRrtNode = 160.0;
constexpr double kBytesPerOrderCell = 24.0;
// RRT* nodes grown per millisecond of a time budget (a fast machine; the estimate errs high).
constexpr double kRrtNodesPerMs = 50.0;

double shortestRouteM(const std::vector<Eigen::Vector3d>& p, bool fixed_order) {
  if (p.size() < 2) return 0.0;
  if (fixed_order) {
    double sum = 0.0;
    for (std::size_t i = 1; i < p.size(); ++i) sum += (p[i] - p[i - 1]).norm();
    return sum;
  }
  // In any order the route goes from the begin through every point to the end, so it is at
  // least as long as the detour through any single point.
  const Eigen::Vector3d& begin = p.front();
  const Eigen::Vector3d& end = p.back();
  double longest = (end - begin).norm();
  for (std::size_t i = 1; i + 1 < p.size(); ++i) longest = std::max(longest, (p[i] - begin).norm() + (end - p[i]).norm());
  return longest;
}

std::string megabytes(double bytes) { return numberText(bytes / (1024.0 * 1024.0), 4) + " MB"; }

}  // namespace

RequestFootprint estimateFootprint(const std::vector<Eigen::Vector3d>& points_m, bool fixed_order, double v_ref_mps,
                                   const FootprintOptions& options) {
  RequestFootprint f;
  f.min_route_m = shortestRouteM(points_m, fixed_order);
  f.min_duration_s = v_ref_mps > 0.0 ? f.min_route_m / v_ref_mps : INFINITY;
  f.min_samples = sampleCount(f.min_duration_s, options.sample_dt_s);
  const double knots = options.waypoint_spacing_m > 0.0 ? f.min_route_m / options.waypoint_spacing_m + static_cast<double>(points_m.size())
                                                        : static_cast<double>(points_m.size());
  const double rrt_nodes = options.leg_max_iterations > 0 ? static_cast<double>(options.leg_max_iterations)
                                                          : options.leg_budget_ms * kRrtNodesPerMs;
  const double order_cells = static_cast<double>(options.order_cells_per_axis) * options.order_cells_per_axis;
  f.memory_bytes = static_cast<double>(f.min_samples) * kBytesPerSample + knots * kBytesPerKnot +
                   rrt_nodes * kBytesPerRrtNode +
                   (fixed_order ? 0.0 : order_cells * static_cast<double>(points_m.size()) * kBytesPerOrderCell);
  return f;
}

std::optional<PlanError> checkFootprint(const RequestFootprint& f, double v_ref_mps, const FootprintOptions& options) {
  const std::string route = "the route through the points is at least " + numberText(f.min_route_m / 1000.0, 4) +
                            " km: at v_ref_mps " + numberText(v_ref_mps) + " m/s it takes at least " +
                            numberText(f.min_duration_s) + " s";
  if (f.min_duration_s > options.trajectory.max_duration_s) {
    return PlanError{PlanErrorCode::kTooLarge, "limits.v_ref_mps",
                     route + ", more than the longest trajectory the service makes (" +
                         numberText(options.trajectory.max_duration_s) + " s)"};
  }
  if (f.min_samples > options.trajectory.max_samples) {
    return PlanError{PlanErrorCode::kTooLarge, "limits.v_ref_mps",
                     route + ", " + std::to_string(f.min_samples) + " samples at " + numberText(options.sample_dt_s) +
                         " s, more than the " + std::to_string(options.trajectory.max_samples) + " a trajectory may have"};
  }
  if (options.memory_share_bytes > 0.0 && f.memory_bytes > options.memory_share_bytes) {
    return PlanError{PlanErrorCode::kTooLarge, "points",
                     "planning this mission would take about " + megabytes(f.memory_bytes) +
                         ", more than one planning thread's share of the memory budget (" +
                         megabytes(options.memory_share_bytes) + ")"};
  }
  return std::nullopt;
}

std::optional<PlanError> checkTrajectorySize(double duration_s, double sample_dt_s, const TrajectorySizeBounds& bounds) {
  if (!(duration_s <= bounds.max_duration_s)) {
    return PlanError{PlanErrorCode::kTooLarge, "trajectory",
                     "the trajectory lasts " + numberText(duration_s) + " s, more than the longest the service makes (" +
                         numberText(bounds.max_duration_s) + " s)"};
  }
  const std::size_t samples = sampleCount(duration_s, sample_dt_s);
  if (samples > bounds.max_samples) {
    return PlanError{PlanErrorCode::kTooLarge, "trajectory",
                     "the trajectory would have " + std::to_string(samples) + " samples at " + numberText(sample_dt_s) +
                         " s, more than the " + std::to_string(bounds.max_samples) + " a trajectory may have"};
  }
  return std::nullopt;
}

}  // namespace skyroute
