// One obstacle update written by a ground station and the answers it gets: every vehicle whose
// current trajectory the obstacle will meet (obstacle_reach.hpp, decided here, not by the daemon)
// must get a new revision or a replan status with an error (nothing better found, the revision in
// force kept). Used by the load e2e test and the latency benchmark.
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "tests/daemon/ground_station.hpp"
#include "tests/daemon/obstacle_reach.hpp"

namespace skyroute::testing {

struct UpdateAnswers {
  std::vector<std::string> affected;          // vehicles the obstacle will meet
  std::map<std::string, double> answer_ms;    // affected vehicle -> ms from write to its answer
  std::map<std::string, bool> by_status;      // ... answered by a status (no new revision)
  std::vector<std::string> unanswered;        // affected vehicles without an answer in time
};

// The vehicles whose latest trajectory the update will meet within horizon_s.
inline std::vector<std::string> affectedVehicles(const Station& station, const std::vector<std::string>& vehicles,
                                                 const ObstacleUpdateData& update, double horizon_s, double margin_m) {
  std::vector<std::string> out;
  const std::int64_t now_ns = utcNowNs();
  for (const std::string& v : vehicles) {
    const TrajectoryData* t = station.latest(v);
    if (t && obstacleMeets(*t, update, now_ns, horizon_s, margin_m)) out.push_back(v);
  }
  return out;
}

// Writes the update and waits up to timeout_s for every affected vehicle's answer.
inline UpdateAnswers writeAndAwaitAnswers(Station& station, const std::vector<std::string>& vehicles,
                                          const ObstacleUpdateData& update, double timeout_s, double horizon_s = 45.0,
                                          double margin_m = 5.0) {
  UpdateAnswers out;
  out.affected = affectedVehicles(station, vehicles, update, horizon_s, margin_m);
  std::map<std::string, std::uint32_t> revision;
  for (const std::string& v : out.affected) revision[v] = station.latest(v)->revision;
  const std::size_t trajectories_seen = station.trajectory_log.size();
  const std::size_t statuses_seen = station.status_log.size();
  const auto t0 = std::chrono::steady_clock::now();
  (void)station.obstacles->write(update);
  auto collect = [&] {
    const auto now = std::chrono::steady_clock::now();
    for (std::size_t i = trajectories_seen; i < station.trajectory_log.size(); ++i) {
      const TrajectoryData& t = station.trajectory_log[i];
      if (revision.count(t.vehicle_id) && t.revision > revision[t.vehicle_id] && !out.answer_ms.count(t.vehicle_id)) {
        out.answer_ms[t.vehicle_id] = std::chrono::duration<double, std::milli>(station.trajectory_times[i] - t0).count();
        out.by_status[t.vehicle_id] = false;
      }
    }
    for (std::size_t i = statuses_seen; i < station.status_log.size(); ++i) {
      const PlanStatusData& s = station.status_log[i];
      if (revision.count(s.vehicle_id) && (s.state == PlanState::kReplanned || s.state == PlanState::kHolding) && s.error_code != PlanErrorCode::kNone &&
          !out.answer_ms.count(s.vehicle_id)) {
        out.answer_ms[s.vehicle_id] = std::chrono::duration<double, std::milli>(now - t0).count();
        out.by_status[s.vehicle_id] = true;
      }
    }
    return out.answer_ms.size() == out.affected.size();
  };
  station.pumpUntil(collect, timeout_s);
  for (const std::string& v : out.affected) {
    if (!out.answer_ms.count(v)) out.unanswered.push_back(v);
  }
  return out;
}

}  // namespace skyroute::testing
