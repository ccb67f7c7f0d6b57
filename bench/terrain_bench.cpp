// Terrain world model benchmark: time to load N44W072.hgt and have collision checks ready, peak
// RSS, point checks per second, and the median time of a 1 km swept-segment check, next to two
// baselines run in the same process (dense sampling at 1 m, FCL capsule against the octree).
//
//   build-bench/bench/terrain_bench [DEM]  (default ../shared/data/dem/N44W072.hgt)
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <fcl/geometry/octree/octree.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/collision.h>

#include "terrain/terrain_world.hpp"

using namespace skyroute;
using Clock = std::chrono::steady_clock;

namespace {

double peakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

// Runs in a child process so each resolution's peak RSS is its own.
void readyAt(const std::string& dem, double resolution_m) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    const auto t0 = Clock::now();
    CollisionWorldOptions options;
    options.octree_resolution_m = resolution_m;
    auto world = loadTerrainWorld(dem, options);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    if (!world.ok()) {
      std::printf("error: %s\n", world.error().describe().c_str());
      std::_Exit(1);
    }
    const auto& stats = world->collision->octree()->stats();
    std::printf("| %5.0f m | %7.3f s | %7.3f s | %10zu | %8.0f MiB | %8.0f MiB |\n", resolution_m, seconds,
                stats.build_seconds, stats.leaf_count, stats.memory_bytes / 1048576.0, peakRssMiB());
    std::fflush(stdout);
    std::_Exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
}

template <class F>
double medianMicros(int n, F&& f) {
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    f(i);
    t[i] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
  }
  std::nth_element(t.begin(), t.begin() + n / 2, t.end());
  return t[n / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dem = argc > 1 ? argv[1] : std::string(SKYROUTE_SHARED_DATA_DIR) + "/dem/N44W072.hgt";
  std::printf("DEM: %s\n\n## Load to collision-ready (child process per resolution)\n\n", dem.c_str());
  std::printf("| octree | ready | octree build | leaves | octree mem | peak RSS |\n|---|---|---|---|---|---|\n");
  readyAt(dem, 90.0);
  readyAt(dem, 30.0);

  CollisionWorldOptions options;
  options.octree_resolution_m = 90.0;
  options.min_clearance_m = 30.0;
  auto world_result = loadTerrainWorld(dem, options);
  if (!world_result.ok()) {
    std::fprintf(stderr, "%s\n", world_result.error().describe().c_str());
    return 1;
  }
  const CollisionWorld& world = *world_result->collision;
  const Heightfield& hf = *world_result->heightfield;
  const auto box = hf.boundsEn();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ue(box.min().x() + 2000, box.max().x() - 2000);
  std::uniform_real_distribution<double> un(box.min().y() + 2000, box.max().y() - 2000);
  std::uniform_real_distribution<double> ua(0.0, 600.0);
  std::uniform_real_distribution<double> uang(0.0, 2 * M_PI);

  // Point checks: points from the ground to 600 m above it.
  const int points = 2000000;
  std::vector<Eigen::Vector3d> pts(points);
  for (auto& p : pts) {
    const double e = ue(rng);
    const double n = un(rng);
    p = Eigen::Vector3d(e, n, hf.heightAt(e, n) + ua(rng));
  }
  auto t0 = Clock::now();
  long valid = 0;
  for (const auto& p : pts) valid += world.isPointValid(p) ? 1 : 0;
  const double point_rate = points / std::chrono::duration<double>(Clock::now() - t0).count();

  // 1 km segments between random points at 30 to 600 m above the ground.
  const int segments = 20000;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segs(segments);
  for (auto& s : segs) {
    const double e = ue(rng);
    const double n = un(rng);
    const double a = uang(rng);
    const double e2 = e + 1000.0 * std::cos(a);
    const double n2 = n + 1000.0 * std::sin(a);
    s = {Eigen::Vector3d(e, n, hf.heightAt(e, n) + ua(rng)), Eigen::Vector3d(e2, n2, hf.heightAt(e2, n2) + ua(rng))};
    // Keep the 3D length at 1 km.
    s.second = s.first + (s.second - s.first).normalized() * 1000.0;
  }
  long seg_valid = 0;
  const double exact_us = medianMicros(segments, [&](int i) { seg_valid += world.isSegmentValid(segs[i].first, segs[i].second); });
  const double dense_us = medianMicros(2000, [&](int i) {
    bool ok = true;
    for (int k = 0; k <= 1000 && ok; ++k) ok = world.isPointValid(segs[i].first + (segs[i].second - segs[i].first) * (k / 1000.0));
    seg_valid += ok;
  });
  fcl::OcTreed octree(world.octree()->tree());
  const double fcl_us = medianMicros(2000, [&](int i) {
    const Eigen::Vector3d a = segs[i].first;
    const Eigen::Vector3d b = segs[i].second;
    fcl::Capsuled capsule(options.vehicle_radius_m, (b - a).norm());
    fcl::Transform3d tf = fcl::Transform3d::Identity();
    tf.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), b - a).toRotationMatrix();
    tf.translation() = 0.5 * (a + b);
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    fcl::collide(&capsule, tf, &octree, fcl::Transform3d::Identity(), request, result);
    seg_valid += result.isCollision();
  });

  std::printf("\n## Checks (single thread)\n\n| check | result | target |\n|---|---|---|\n");
  std::printf("| point validity | %.2f M checks/s (%.0f%% valid) | >= 1 M/s |\n", point_rate / 1e6, 100.0 * valid / points);
  std::printf("| 1 km swept segment, exact on the heightfield | %.2f us median | <= 50 us |\n", exact_us);
  std::printf("| baseline: 1 km by 1001 point samples | %.2f us median (%.0fx slower) | |\n", dense_us, dense_us / exact_us);
  std::printf("| baseline: 1 km FCL capsule vs 90 m octree | %.2f us median (%.0fx slower) | |\n", fcl_us, fcl_us / exact_us);
  std::printf("\n(checksum %ld)\n", seg_valid);
  return 0;
}
