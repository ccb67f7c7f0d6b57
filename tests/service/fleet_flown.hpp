// What a fleet flew, judged from what was published only: each vehicle's revisions in publish
// order, a revision in force from its first sample until the next revision of that vehicle, and
// positions linear between the published samples (0.2 s apart: what a follower flies).
#pragma once

#include <algorithm>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "service/mission_types.hpp"

namespace skyroute::testing {

inline double startS(const TrajectoryData& t) { return static_cast<double>(t.samples.front().utc_ns) * 1e-9; }
inline double endS(const TrajectoryData& t) { return startS(t) + t.samples.back().t_rel_s; }

inline Eigen::Vector3d sampledAt(const TrajectoryData& t, double world_s) {
  const auto& s = t.samples;
  const double rel = world_s - startS(t);
  if (rel <= 0.0) return s.front().position_enu_m;
  if (rel >= s.back().t_rel_s) return s.back().position_enu_m;
  const auto after = std::upper_bound(s.begin(), s.end(), rel,
                                      [](double r, const TrajectorySampleData& x) { return r < x.t_rel_s; });
  const auto& b = *after;
  const auto& a = *(after - 1);
  const double w = (rel - a.t_rel_s) / std::max(1e-9, b.t_rel_s - a.t_rel_s);
  return (1.0 - w) * a.position_enu_m + w * b.position_enu_m;
}

struct FleetFlown {
  std::map<std::string, std::vector<TrajectoryData>> revisions;

  // Only the trajectories of request_id (another request's are ignored).
  FleetFlown(const std::vector<TrajectoryData>& published, const std::string& request_id) {
    for (const TrajectoryData& t : published) {
      if (t.request_id == request_id && !t.samples.empty()) revisions[t.vehicle_id].push_back(t);
    }
  }
  const TrajectoryData& inForce(const std::string& vehicle, double world_s) const {
    const auto& list = revisions.at(vehicle);
    std::size_t k = 0;
    while (k + 1 < list.size() && startS(list[k + 1]) <= world_s) ++k;
    return list[k];
  }
  Eigen::Vector3d positionAt(const std::string& vehicle, double world_s) const {
    return sampledAt(inForce(vehicle, world_s), world_s);
  }
  double endOf(const std::string& vehicle) const { return endS(revisions.at(vehicle).back()); }
  double beginOf(const std::string& vehicle) const { return startS(revisions.at(vehicle).front()); }
  // Task j served by the revisions in force: a leg ending at it, inside that revision's window.
  std::vector<std::pair<std::string, double>> servings(std::uint32_t task) const {
    std::vector<std::pair<std::string, double>> out;
    for (const auto& [vehicle, list] : revisions) {
      for (std::size_t k = 0; k < list.size(); ++k) {
        const double from = startS(list[k]);
        const double to = k + 1 < list.size() ? startS(list[k + 1]) : std::numeric_limits<double>::infinity();
        for (const LegBoundaryData& leg : list[k].legs) {
          const double at = from + leg.end_s;
          if (leg.to_point == task + 1 && at >= from && at < to) out.emplace_back(vehicle, at);
        }
      }
    }
    return out;
  }
};

}  // namespace skyroute::testing
