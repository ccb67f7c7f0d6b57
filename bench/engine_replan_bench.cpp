// Obstacle update -> new revision inside the engine, without DDS: the same missions and crossing
// obstacles as e2e_latency_bench, but the engine is driven on this thread with a manual world
// clock, so each number is the engine's own work (update applied, replanning cycle, trajectory
// message built) and the difference to e2e_latency_bench is the DDS and scheduling share.
// A cycle that makes no revision is followed by the next one t_ref later, as in the daemon; its
// wait counts in the latency.
// An update is answered by a new revision: a replanned trajectory, or a hold (the trajectory kept
// as far as it is clear, then a stop; status holding) when no plan is found in the cycle. Between
// updates the flown part of the answer is checked against the obstacle in force (every sample,
// the world's own distance): collisions and the smallest separation are reported.
// Usage: engine_replan_bench [--rounds N] [--verbose] [--debug] [--case embedded|n44|both] [--no-local] [--no-retime]
//                            [--no-band] [--no-commit] [--no-hold] [--tree-reuse off|on|both]
// --tree-reuse (default off) runs each case without and/or with planning.rrt_tree_reuse in the
// same process (the same missions and crossings; an answer that differs changes the later
// crossings, which are placed on the trajectory in force). "answer km" is the mean length of the
// answers that are not holds, from the update's time to the goal.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "bench/latency_scenario.hpp"
#include "bench/support/shared_data.hpp"
#include "service/engine.hpp"
#include "service/moving_obstacle_scenario.hpp"
#include "terrain/terrain_world.hpp"

namespace {

using namespace skyroute;
using Clock = std::chrono::steady_clock;

class LastTrajectorySink : public EngineSink {
 public:
  void publishStatus(const PlanStatusData& status) override { last_status = status; }
  void publishTrajectory(const TrajectoryData& trajectory) override { latest = trajectory; }
  TrajectoryData latest;
  PlanStatusData last_status;
};

struct ManualClock {
  std::int64_t now_ns = 1'800'000'000'000'000'000LL;
  void advance(double seconds) { now_ns += static_cast<std::int64_t>(std::llround(seconds * 1e9)); }
};

struct Outcome {
  std::vector<double> latency_ms;
  std::vector<int> cycles;
  int misses = 0;
  int holds = 0;       // answered by a hold
  int collisions = 0;  // flown samples inside the obstacle (grown by the vehicle radius)
  double min_separation_m = std::numeric_limits<double>::infinity();
  std::vector<double> answer_m;  // per answer that is not a hold: its length from now to the goal
};

struct Switches {
  bool verbose = false;
  bool local = true;
  bool retime = true;
  bool band = true;
  bool commit = true;
  bool hold = true;
  bool tree_reuse = false;
};

Outcome run(std::shared_ptr<const Heightfield> terrain, const MissionRequestData& mission, int rounds,
            const Switches& switches) {
  const bool verbose = switches.verbose;
  Outcome out;
  auto model = WorldModel::create(terrain, WorldModelOptions{}, "bench");
  if (!model.ok()) return out;
  LastTrajectorySink sink;
  ManualClock clock;
  EngineOptions options;
  options.pipeline.replan.local_repair = switches.local;
  options.pipeline.replan.local_retime = switches.retime;
  if (!switches.band) options.pipeline.replan.band_slow_factor = 0.0;
  if (!switches.commit) options.pipeline.replan.max_commit_s = 0.0;
  options.pipeline.replan.hold_fallback = switches.hold;
  options.pipeline.replan.rrt_tree_reuse = switches.tree_reuse;
  auto engine = Engine::create(*model, options, sink, [&] { return clock.now_ns; });
  if (!engine.ok()) return out;
  (*engine)->submit(mission);
  (*engine)->planNext();
  if (sink.latest.samples.empty()) {
    std::fprintf(stderr, "mission failed: %s\n", sink.last_status.message.c_str());
    return out;
  }
  // The vehicle flies on 2 s between updates; each update removes the previous obstacle first.
  clock.now_ns = sink.latest.samples.front().utc_ns;
  std::uint64_t previous_id = 0;
  for (int u = 0; u < rounds; ++u) {
    if (previous_id != 0) {
      ObstacleUpdateData gone;
      gone.obstacle.id = previous_id;
      gone.remove = true;
      (*engine)->updateObstacle(gone);
      (*engine)->replanCycle();
    }
    const double meet_s = 15.0 + (u % 4) * 5.0;
    // Near the goal a crossing would sit on the goal itself (no detour can reach it): fly the
    // mission again from the start instead, so every update meets the vehicle en route.
    const double left_s = static_cast<double>(sink.latest.samples.back().utc_ns - clock.now_ns) * 1e-9;
    if (left_s < meet_s + 30.0) {
      MissionRequestData again = mission;
      again.request_id = mission.request_id + "-" + std::to_string(u);
      (*engine)->submit(again);
      (*engine)->planNext();
      clock.now_ns = sink.latest.samples.front().utc_ns;
    }
    const std::uint32_t revision = sink.latest.revision;
    const ObstacleUpdateData update = bench::crossing(sink.latest, clock.now_ns, 1000 + u, meet_s);
    previous_id = update.obstacle.id;
    const auto t0 = Clock::now();
    (*engine)->updateObstacle(update);
    // The world with this obstacle, for the collision check after the answer (outside the timing).
    Result<std::shared_ptr<const CollisionWorld>> collision_world = make_error(ErrorCode::kInternal, "world", "not made");
    int cycles = 0;
    double waited_ms = 0.0;
    while (sink.latest.revision == revision && cycles < 50) {
      if (cycles > 0) {
        clock.advance(0.1);
        waited_ms += 100.0;
      }
      (*engine)->replanCycle();
      ++cycles;
    }
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() + waited_ms;
    collision_world = (*model)->worldFor(mission.limits.min_clearance_agl_m, mission.limits.ceiling_amsl_m);
    const bool hold = sink.last_status.state == PlanState::kHolding;
    if (sink.latest.revision == revision) {
      ++out.misses;
      if (verbose) std::printf("update %d: no revision in %d cycles\n", u, cycles);
    } else {
      out.latency_ms.push_back(ms);
      out.cycles.push_back(cycles);
      out.holds += hold ? 1 : 0;
      if (!hold) {
        double length = 0.0;
        const TrajectorySampleData* last = nullptr;
        for (const TrajectorySampleData& s : sink.latest.samples) {
          if (s.utc_ns < clock.now_ns) continue;
          if (last) length += (s.position_enu_m - last->position_enu_m).norm();
          last = &s;
        }
        out.answer_m.push_back(length);
      }
      if (verbose) std::printf("update %d: %.1f ms, %d cycle(s)%s\n", u, ms, cycles, hold ? " (hold)" : "");
    }
    // The next 2 s are flown on the answer (or the revision kept): the vehicle sphere never touches the obstacle.
    if (collision_world.ok()) {
      const std::int64_t until_ns = clock.now_ns + 2'000'000'000LL;
      for (const TrajectorySampleData& s : sink.latest.samples) {
        if (s.utc_ns < clock.now_ns || s.utc_ns > until_ns) continue;
        const double d = (*collision_world)->obstacleDistance(s.position_enu_m, static_cast<double>(s.utc_ns) * 1e-9);
        out.min_separation_m = std::min(out.min_separation_m, d);
        if (d <= 0.0) {  // the vehicle sphere touches it
          ++out.collisions;
          if (verbose) std::printf("update %d: collision at %.2f s\n", u, static_cast<double>(s.utc_ns - clock.now_ns) * 1e-9);
          break;
        }
      }
    }
    clock.advance(2.0);
  }
  return out;
}

void row(const char* what, const Outcome& o) {
  if (o.latency_ms.empty()) {
    std::printf("| %-44s | 0 | - | - | - | - | - | %d | %d | - | - |\n", what, o.misses, o.collisions);
    return;
  }
  std::vector<double> v = o.latency_ms;
  std::sort(v.begin(), v.end());
  auto q = [&](double f) { return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(f * v.size())) - 1)]; };
  const int multi = static_cast<int>(std::count_if(o.cycles.begin(), o.cycles.end(), [](int c) { return c > 1; }));
  double answer_m = 0.0;
  for (double m : o.answer_m) answer_m += m;
  if (!o.answer_m.empty()) answer_m /= static_cast<double>(o.answer_m.size());
  std::printf("| %-44s | %zu | %.1f | %.1f | %.1f | %d | %d | %d | %d | %.0f | %.3f |\n", what, v.size(), q(0.5), q(0.9),
              q(0.99), multi, o.holds, o.misses, o.collisions, o.min_separation_m, answer_m / 1e3);
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 20;
  bool verbose = false;
  bool retime = true, local = true, band = true, commit = true, hold = true;
  std::string only = "both";  // embedded | n44 | both
  std::string tree_reuse = "off";  // off | on | both
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) rounds = std::atoi(argv[++i]);
    if (std::strcmp(argv[i], "--verbose") == 0) verbose = true;
    if (std::strcmp(argv[i], "--no-retime") == 0) retime = false;
    if (std::strcmp(argv[i], "--no-local") == 0) local = false;
    if (std::strcmp(argv[i], "--no-band") == 0) band = false;
    if (std::strcmp(argv[i], "--no-commit") == 0) commit = false;
    if (std::strcmp(argv[i], "--no-hold") == 0) hold = false;
    if (std::strcmp(argv[i], "--case") == 0 && i + 1 < argc) only = argv[++i];
    if (std::strcmp(argv[i], "--tree-reuse") == 0 && i + 1 < argc) tree_reuse = argv[++i];
    if (std::strcmp(argv[i], "--debug") == 0) spdlog::set_level(spdlog::level::debug);
  }
  if (tree_reuse != "off" && tree_reuse != "on" && tree_reuse != "both") {
    std::fprintf(stderr, "unknown --tree-reuse %s (off, on or both)\n", tree_reuse.c_str());
    return 2;
  }
  std::vector<bool> reuse_runs;
  if (tree_reuse != "on") reuse_runs.push_back(false);
  if (tree_reuse != "off") reuse_runs.push_back(true);
  auto runRows = [&](const std::string& what, std::shared_ptr<const Heightfield> t, const MissionRequestData& m) {
    for (bool reuse : reuse_runs) {
      Switches s{verbose, local, retime, band, commit, hold, reuse};
      row((what + (reuse ? " + tree reuse" : "")).c_str(), run(t, m, rounds, s));
    }
  };
  CollisionWorldOptions options;
  options.build_octree = false;
  std::printf("| case | answered | p50 ms | p90 ms | p99 ms | updates needing > 1 cycle | answered by a hold | no revision "
              "| collisions | min separation m | answer km |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");

  const std::string dem = std::string(SKYROUTE_DATA_DIR) + "/default_terrain.tif";
  std::shared_ptr<const Heightfield> terrain = loadTerrainWorld(dem, options).value().heightfield;
  if (only != "n44") {
    const MissionRequestData m = bench::laneMission(*terrain, "lane", 0, 1);
    runRows("embedded terrain, lane mission", terrain, m);
  }

  const std::string n44 = std::string(SKYROUTE_SHARED_DATA_DIR) + "/dem/N44W072.hgt";
  if (only == "embedded") {
  } else if (std::FILE* f = std::fopen(n44.c_str(), "rb")) {
    std::fclose(f);
    std::shared_ptr<const Heightfield> real = loadTerrainWorld(n44, options).value().heightfield;
    const MissionRequestData m = bench::seed003Mission(seed003Table1Scenario(*real), "seed003");
    runRows("N44W072, seed-003 vehicle", real, m);
  } else {
    bench::skipCaseForMissingData("(N44W072 case skipped: " + n44 + " not found)", n44 + " not found");
  }
  return 0;
}
