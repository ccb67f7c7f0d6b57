// Path length against planning time on the two real DEMs: our RRT* (+ LOSPO) against OMPL's
// RRTstar, InformedRRTstar and BITstar (with and without PathSimplifier::simplifyMax), all asking
// the same WorldMotionValidator. Per DEM, seeded start/goal pairs low over the terrain under a
// ceiling, with the straight line blocked; budgets 10, 50, 100 ms plus a long reference budget.
// Each planner's length is divided by the best length any planner found for that pair.
// Two sets of legs, each in its own rows: "easy" (those pairs, per DEM, with the planner rows in a
// corridor of half the leg's length round it) and "hard" (N44W072 only: legs whose straight line
// is blocked by ground above the ceiling and whose every way round leaves the pipeline's corridor;
// planner rows over the whole terrain), see makeHardPairs.
//
// Usage: rrt_star_bench [--pairs N] [--sets easy,hard] [--hard-pairs N] [--max-detour F] [--product-seeds N] [--long-ms MS] [--csv FILE] [--dem hgt|tif|both] [--spacing M]
//                       [--max-vertices N] [--passes N] [--plan-share F] [--ompl-plan-share F]
//                       [--refine 0|1] [--refine-min-step M] [--refine-shortcuts N] [--budgets MS,MS,...]
//                       [--ompl 0|1] [--ompl-planners NAME,...] [--protocols inside,after]
//                       [--knn 0|1] [--prune 0|1] [--goal-bias F] [--product 0|1]
//                       [--variant NAME,PLAN_SHARE,MAX_VERTICES,PASSES,REFINE[,RRT_FLAGS] ...]
// RRT_FLAGS: '+'-separated RRT* settings of the variant: knn, radius (near set), prune, noprune,
// gb=F (goal bias), rf=F (rewire factor), stepx=F (steering range multiple).
// Prints one typed row per run to the CSV and a summary table (median / p90 ratio) on stdout.
//
// Every budget is CPU time of the benchmark thread (clock_gettime(CLOCK_THREAD_CPUTIME_ID)), for
// every planner, so the numbers do not depend on how loaded the shared machine is. Two protocols
// for the post-processing (ours: LOSPO then refinePath; OMPL: PathSimplifier::simplify):
//  - inside: the budget covers planning and post-processing. Ours gives RRT* plan_share of it,
//    OMPL's planner gets ompl_plan_share; the post-processing stops at the end of the budget.
//    Rows are named "skyroute RRT*" and "OMPL <planner> [inside]".
//  - after: the planner gets the whole budget and the post-processing runs to completion after it,
//    untimed (simplifyMax for OMPL). Rows "skyroute RRT* [after]" and "OMPL <planner>".
// The row "skyroute RRT* LOSPO only" is the inside run's path before refinePath.
// Those rows measure the planner. The rows "product rrtstar-lospo" time the product's leg as the
// mission pipeline plans it: the registry's leg planner (legPathPlanner) with the pipeline's
// route options (its own corridor round the leg, RRT* and LOSPO settings, no refinePath), capped
// at the budget in wall-clock time as the product caps it, with no iteration budget; the row
// "product rrtstar-lospo [default budget]" uses the pipeline's default budget (an iteration count
// with a wall-clock cap). On the easy legs the product rows are not counted in a pair's best
// length, so the other rows' ratios stay comparable with earlier runs; on the hard legs they are
// (its guided search often finds a shorter way than any planner row); `--product 0` leaves them out.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "bench/support/bench_progress.hpp"
#include "bench/support/path_refinement.hpp"
#include "planning/sampling/lospo.hpp"
#include "planning/sampling/rrt_star.hpp"
#include "planning/sampling/world_motion_validator.hpp"
#include "service/mission_pipeline.hpp"
#include "service/planner_registry.hpp"
#include "terrain/terrain_world.hpp"

namespace ob = ompl::base;
namespace og = ompl::geometric;
using skyroute::MotionValidator;

namespace {

using skyroute::TerminationCondition;

// Seconds of CPU time used by this thread since `since`.
double cpuSecondsSince(std::chrono::nanoseconds since) {
  return std::chrono::duration<double>(TerminationCondition::threadCpuNow() - since).count();
}

// OMPL's view of a thread CPU deadline `budget_s` from now.
ob::PlannerTerminationCondition cpuPlannerTermination(double budget_s) {
  const auto deadline = TerminationCondition::threadCpuNow() +
                        std::chrono::nanoseconds(static_cast<std::int64_t>(budget_s * 1e9));
  return ob::PlannerTerminationCondition([deadline] { return TerminationCondition::threadCpuNow() >= deadline; });
}

// Our MotionValidator seen by OMPL: the same checks for every planner.
class OmplStateChecker : public ob::StateValidityChecker {
 public:
  OmplStateChecker(const ob::SpaceInformationPtr& si, const MotionValidator& v) : ob::StateValidityChecker(si), v_(v) {}
  bool isValid(const ob::State* s) const override { return v_.isStateValid(toVec(s)); }
  static Eigen::Vector3d toVec(const ob::State* s) {
    const auto* r = s->as<ob::RealVectorStateSpace::StateType>();
    return {r->values[0], r->values[1], r->values[2]};
  }

 private:
  const skyroute::MotionValidator& v_;
};

class OmplMotionChecker : public ob::MotionValidator {
 public:
  OmplMotionChecker(const ob::SpaceInformationPtr& si, const skyroute::MotionValidator& v) : ob::MotionValidator(si), v_(v) {}
  bool checkMotion(const ob::State* a, const ob::State* b) const override {
    const bool ok = v_.isMotionValid(OmplStateChecker::toVec(a), OmplStateChecker::toVec(b));
    if (ok) ++valid_; else ++invalid_;
    return ok;
  }
  // Exact checks report no partial progress: the last valid state is the start.
  bool checkMotion(const ob::State* a, const ob::State* b, std::pair<ob::State*, double>& last_valid) const override {
    if (checkMotion(a, b)) return true;
    if (last_valid.first != nullptr) si_->copyState(last_valid.first, a);
    last_valid.second = 0.0;
    return false;
  }

 private:
  const skyroute::MotionValidator& v_;
};

struct Run {
  std::string dem;
  int pair = 0;
  std::string planner;
  double budget_ms = 0;
  bool solved = false;
  double plan_s = 0;                 // CPU time of the planner
  double length_m = NAN;             // planner's own path
  double simplified_m = NAN;         // after LOSPO + refinement (ours) or simplifyMax (OMPL)
  double simplify_s = 0;             // CPU time of the post-processing
  double lospo_m = NAN;              // ours after LOSPO, before the refinement
  double refine_s = 0;
  std::size_t tree_size = 0;
};

struct Pair {
  Eigen::Vector3d start, goal;
};

struct OurOptions {
  std::string name = "skyroute RRT*";
  double spacing_m = 100.0;
  // One LOSPO pass over at most 30 vertices, then the refinement, with RRT* at 75% of the budget:
  // the refinement tightens corners for less time than LOSPO's second pass and wider vertex set
  // (docs/benchmarks/rrt_star.md compares the two in one run).
  int max_vertices = 30;
  int passes = 1;
  double plan_share = 0.75;
  bool refine = true;
  double step_factor = 1.0;  // multiple of the common steering range (20% of the box diagonal)
  bool inside = true;  // post-processing inside the budget; false: RRT* gets all, LOSPO + refinement untimed
  skyroute::PathRefinementOptions refinement;
  // Seed and steering range are set per run; hopeless checks skipped. Goal bias 0.1 (library
  // default 0.05): in CPU-time runs it solved one more pair at 10 ms and cut the 10 and 50 ms p90
  // of the raw tree (1.108 -> 1.074, 1.060 -> 1.033) with the same medians. Rewire factor 2
  // (library default 1.1, kept there for the replanner's per-iteration cost): larger near sets,
  // raw 10 ms median 1.0067 -> 1.0024 and 50 ms 1.0040 -> 1.0015 (docs/benchmarks/rrt_star.md).
  skyroute::RrtStarOptions rrt = [] {
    skyroute::RrtStarOptions o;
    o.goal_bias = 0.1;
    o.rewire_factor = 2.0;
    o.skip_hopeless_checks = true;
    return o;
  }();
};

// Inside protocol: our budget covers every step: RRT* gets plan_share of it, LOSPO and the
// refinement the rest (each stops at the deadline with the valid path it has so far). After
// protocol: RRT* gets the whole budget, LOSPO and the refinement run to completion.
Run runOurs(const MotionValidator& v, const Pair& p, double budget_ms, std::uint64_t seed, double step_m,
            const OurOptions& ours) {
  const double spacing_m = ours.spacing_m, plan_share = ours.plan_share;
  const int max_vertices = ours.max_vertices, passes = ours.passes;
  Run run;
  run.planner = ours.name;
  run.budget_ms = budget_ms;
  skyroute::RrtStarOptions o = ours.rrt;
  o.seed = seed;
  o.max_step_m = ours.step_factor * step_m;
  const auto t0 = TerminationCondition::threadCpuNow();
  const auto lospo_stop = ours.inside ? TerminationCondition::afterThreadCpuMilliseconds(budget_ms) : TerminationCondition();
  auto r = skyroute::RrtStar(v, o).plan(
      p.start, p.goal, TerminationCondition::afterThreadCpuMilliseconds((ours.inside ? plan_share : 1.0) * budget_ms));
  run.plan_s = cpuSecondsSince(t0);
  if (!r.ok() || !r->solved()) return run;
  run.solved = true;
  run.length_m = r->length_m;
  run.tree_size = r->tree_size;
  const auto t1 = TerminationCondition::threadCpuNow();
  auto opt = skyroute::lospo(v, r->path_m, skyroute::LospoOptions{.spacing_m = spacing_m, .max_vertices = max_vertices, .max_passes = passes}, lospo_stop);
  run.simplified_m = opt.ok() ? opt->length_m : r->length_m;
  run.lospo_m = run.simplified_m;
  if (opt.ok() && ours.refine) {
    skyroute::PathRefinementOptions refinement = ours.refinement;
    refinement.check_input = false;  // LOSPO verified every segment of its result
    const auto t2 = TerminationCondition::threadCpuNow();
    auto refined = skyroute::refinePath(v, opt->path_m, refinement, lospo_stop);
    run.refine_s = cpuSecondsSince(t2);
    if (refined.ok()) run.simplified_m = refined->length_m;
  }
  run.simplify_s = cpuSecondsSince(t1);
  return run;
}

// The product's name for the leg planner these rows time.
std::string productRowName(bool default_budget) {
  const std::string name(skyroute::routePlanner(skyroute::RoutePlannerKind::kRrtStarLospo).name);
  return "product " + name + (default_budget ? " [default budget]" : "");
}

// The product's leg from p.start to p.goal, planned as the mission pipeline plans it. budget_ms >
// 0: a wall-clock cap of that much and no iteration budget; 0: the pipeline's default budget.
Run runProduct(const std::shared_ptr<const skyroute::CollisionWorld>& world, const Pair& p, double budget_ms,
               std::uint64_t seed) {
  const skyroute::PipelineOptions pipeline;
  skyroute::PlanBudget budget = pipeline.budget;
  if (budget_ms > 0.0) {
    budget.leg_max_iterations = 0;
    budget.leg_time_cap_s = budget_ms * 1e-3;
  }
  const skyroute::RouteOptions options = skyroute::pipelineReplanOptions(pipeline, budget, seed).route;
  const skyroute::LegPathPlanner legs = skyroute::legPathPlanner(skyroute::RoutePlannerKind::kRrtStarLospo, pipeline.grid_legs);
  Run run;
  run.planner = productRowName(budget_ms <= 0.0);
  run.budget_ms = budget_ms;
  const auto t0 = TerminationCondition::threadCpuNow();
  auto route = legs(world, {p.start, p.goal}, options, TerminationCondition());
  run.plan_s = cpuSecondsSince(t0);
  if (!route.ok() || route->legs.size() != 1) return run;
  const skyroute::RouteLeg& leg = route->legs.front();
  run.solved = true;
  run.length_m = leg.rrt.length_m;
  run.simplified_m = leg.lospo_length_m;
  run.lospo_m = leg.lospo_length_m;
  run.tree_size = leg.rrt.tree_size;
  return run;
}

// plan_share < 1: inside protocol (the planner gets plan_share of the budget, the simplifier the
// rest of it); plan_share = 1: after protocol (the whole budget, then simplifyMax untimed).
Run runOmpl(const std::string& name, const MotionValidator& v, const Pair& p, double budget_ms, double step_m,
            double plan_share) {
  const bool inside = plan_share < 1.0;
  Run run;
  run.planner = "OMPL " + name + (inside ? " [inside]" : "");
  run.budget_ms = budget_ms;
  auto space = std::make_shared<ob::RealVectorStateSpace>(3);
  const Eigen::AlignedBox3d box = v.samplingBounds();
  ob::RealVectorBounds bounds(3);
  for (int i = 0; i < 3; ++i) {
    bounds.setLow(i, box.min()[i]);
    bounds.setHigh(i, box.max()[i]);
  }
  space->setBounds(bounds);
  og::SimpleSetup ss(space);
  const ob::SpaceInformationPtr si = ss.getSpaceInformation();
  ss.setStateValidityChecker(std::make_shared<OmplStateChecker>(si, v));
  si->setMotionValidator(std::make_shared<OmplMotionChecker>(si, v));
  auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
  objective->setCostThreshold(ob::Cost(0.0));  // never "good enough": use the whole budget
  ss.setOptimizationObjective(objective);
  ob::ScopedState<> s(space), g(space);
  for (int i = 0; i < 3; ++i) {
    s[i] = p.start[i];
    g[i] = p.goal[i];
  }
  ss.setStartAndGoalStates(s, g);
  if (name == "RRTstar") {
    auto planner = std::make_shared<og::RRTstar>(si);
    planner->setRange(step_m);
    ss.setPlanner(planner);
  } else if (name == "InformedRRTstar") {
    auto planner = std::make_shared<og::InformedRRTstar>(si);
    planner->setRange(step_m);
    ss.setPlanner(planner);
  } else {
    ss.setPlanner(std::make_shared<og::BITstar>(si));
  }
  ss.setup();
  const auto t0 = TerminationCondition::threadCpuNow();
  // The simplifier's share starts when the planner returns (it may overrun its share a little).
  const ob::PlannerStatus status = ss.getPlanner()->solve(cpuPlannerTermination(plan_share * budget_ms / 1000.0));
  run.plan_s = cpuSecondsSince(t0);
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return run;
  auto path = ss.getProblemDefinition()->getSolutionPath()->as<og::PathGeometric>();
  run.solved = true;
  run.length_m = path->length();
  ob::PlannerData data(si);
  ss.getPlanner()->getPlannerData(data);
  run.tree_size = data.numVertices();
  og::PathGeometric simplified(*path);
  og::PathSimplifier simplifier(si);
  const auto t1 = TerminationCondition::threadCpuNow();
  if (inside) {
    // What is left of the budget; no forced first round (ours gets none either).
    const double left_s = std::max(0.0, budget_ms / 1000.0 - cpuSecondsSince(t0));
    simplifier.simplify(simplified, cpuPlannerTermination(left_s), /*atLeastOnce=*/false);
  } else {
    simplifier.simplifyMax(simplified);
  }
  run.simplify_s = cpuSecondsSince(t1);
  run.simplified_m = simplified.length();
  return run;
}

struct DemCase {
  std::string name;
  std::string path;
  double ceiling_m;
  double min_dist_m, max_dist_m;
  // Hard legs: the way round the terrain above the ceiling leaves the leg's corridor (the box the
  // pipeline samples first); every planner row samples the whole terrain.
  bool hard = false;
};

std::vector<Pair> makePairs(const skyroute::TerrainWorld& world, const DemCase& dc, int count, std::uint64_t seed,
                            double margin_factor, std::vector<std::unique_ptr<skyroute::WorldMotionValidator>>& validators) {
  std::mt19937_64 rng(seed);
  auto u = [&rng](double a, double b) { return a + (b - a) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  const auto& hf = *world.heightfield;
  const Eigen::AlignedBox2d en = hf.boundsEn();
  const double clearance = world.collision->options().min_clearance_m;
  const skyroute::WorldMotionValidator whole(world.collision);
  auto lowPoint = [&](double e, double n) -> std::optional<Eigen::Vector3d> {
    const double ground = hf.heightAt(e, n);
    if (!std::isfinite(ground)) return std::nullopt;
    const Eigen::Vector3d p(e, n, ground + clearance + u(40.0, 150.0));
    if (p.z() > dc.ceiling_m - 30.0 || !whole.isStateValid(p)) return std::nullopt;
    return p;
  };
  std::vector<Pair> pairs;
  int attempts = 0;
  while (static_cast<int>(pairs.size()) < count && attempts < 100000) {
    ++attempts;
    const double e = u(en.min().x() + 0.05 * en.sizes().x(), en.max().x() - 0.05 * en.sizes().x());
    const double n = u(en.min().y() + 0.05 * en.sizes().y(), en.max().y() - 0.05 * en.sizes().y());
    const auto s = lowPoint(e, n);
    if (!s) continue;
    const double d = u(dc.min_dist_m, dc.max_dist_m), a = u(0, 2 * M_PI);
    const auto g = lowPoint(e + d * std::cos(a), n + d * std::sin(a));
    if (!g || !en.contains(g->head<2>())) continue;
    // Not trivial: the straight line is blocked even 200 m higher (a real detour, not a hop).
    const Eigen::Vector3d up(0, 0, 200);
    if (whole.isMotionValid(*s, *g) || world.collision->isSegmentValid(*s + up, *g + up)) continue;
    auto v = std::make_unique<skyroute::WorldMotionValidator>(
        world.collision, skyroute::WorldMotionValidator::corridor(*s, *g, margin_factor * d));
    if (!v->isStateValid(*s) || !v->isStateValid(*g)) continue;
    // Keep pairs our planner can solve in 1 s (a pair nobody solves says nothing about quality).
    auto probe = skyroute::RrtStar(*v).plan(*s, *g, TerminationCondition::afterThreadCpuMilliseconds(1000));
    if (!probe.ok() || !probe->solved()) continue;
    pairs.push_back({*s, *g});
    validators.push_back(std::move(v));
  }
  return pairs;
}

// Seeded legs low over the terrain whose straight line is blocked by ground above the ceiling and
// whose every way round leaves the pipeline's corridor (corridor_margin_m round the leg's box):
// the flyable regions prove no path stays inside it, and prove one may exist beyond it; each kept
// leg is solved by our RRT* over the whole terrain within 2 s (so its best length is known) with a
// path at most max_detour times the straight line (a way round a range, not through a maze).
std::vector<Pair> makeHardPairs(const skyroute::TerrainWorld& world, const DemCase& dc, int count, std::uint64_t seed,
                                double corridor_margin_m, double max_detour,
                                std::vector<std::unique_ptr<skyroute::WorldMotionValidator>>& validators) {
  std::mt19937_64 rng(seed);
  auto u = [&rng](double a, double b) { return a + (b - a) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  const auto& hf = *world.heightfield;
  const Eigen::AlignedBox2d en = hf.boundsEn();
  const double clearance = world.collision->options().min_clearance_m;
  const skyroute::FlyableRegions& regions = world.collision->flyableRegions();
  auto lowPoint = [&](double e, double n) -> std::optional<Eigen::Vector3d> {
    const double ground = hf.heightAt(e, n);
    if (!std::isfinite(ground)) return std::nullopt;
    const Eigen::Vector3d p(e, n, ground + clearance + u(40.0, 150.0));
    if (p.z() > dc.ceiling_m - 30.0 || !world.collision->isPointValid(p)) return std::nullopt;
    return p;
  };
  std::vector<Pair> pairs;
  int attempts = 0;
  while (static_cast<int>(pairs.size()) < count && attempts < 200000) {
    ++attempts;
    const auto s = lowPoint(u(en.min().x(), en.max().x()), u(en.min().y(), en.max().y()));
    if (!s) continue;
    const double d = u(dc.min_dist_m, dc.max_dist_m), a = u(0, 2 * M_PI);
    const Eigen::Vector2d g2 = s->head<2>() + d * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (!en.contains(g2)) continue;
    const auto g = lowPoint(g2.x(), g2.y());
    if (!g || !regions.connected(s->head<2>(), g->head<2>())) continue;
    const Eigen::AlignedBox3d corridor = skyroute::WorldMotionValidator::corridor(*s, *g, corridor_margin_m);
    const Eigen::AlignedBox2d corridor_en(corridor.min().head<2>(), corridor.max().head<2>());
    if (regions.connectedWithin(s->head<2>(), g->head<2>(), corridor_en)) continue;
    auto v = std::make_unique<skyroute::WorldMotionValidator>(world.collision);
    auto probe = skyroute::RrtStar(*v).plan(*s, *g, TerminationCondition::afterThreadCpuMilliseconds(2000));
    if (!probe.ok() || !probe->solved()) continue;
    // A detour round a range, not a maze: at most max_detour times the straight line.
    if (probe->length_m > max_detour * (*g - *s).norm()) continue;
    pairs.push_back({*s, *g});
    validators.push_back(std::move(v));
  }
  return pairs;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double idx = q * (v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = std::min(lo + 1, v.size() - 1);
  if (std::isinf(v[hi])) return idx - lo < 1e-12 ? v[lo] : v[hi];
  return v[lo] + (idx - lo) * (v[hi] - v[lo]);
}

}  // namespace

int main(int argc, char** argv) {
  int pairs_per_dem = 20;
  double long_ms = 1000.0;
  std::string csv_path = "rrt_star_bench.csv";
  std::string which = "both";
  std::string sets = "easy,hard";
  int hard_pairs = 20;
  double max_detour = 1.5;
  int product_seeds = 1;  // product rows per pair, each with its own seed
  OurOptions ours;
  std::vector<OurOptions> variants;  // extra configurations of ours, run next to it
  bool with_ompl = true;
  bool with_product = true;
  std::vector<std::string> ompl_planners{"RRTstar", "InformedRRTstar", "BITstar"};
  double ompl_plan_share = 0.9;
  bool protocol_inside = true, protocol_after = true;
  std::vector<double> budgets{10.0, 50.0, 100.0};
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--pairs") pairs_per_dem = std::atoi(argv[i + 1]);
    else if (a == "--long-ms") long_ms = std::atof(argv[i + 1]);
    else if (a == "--csv") csv_path = argv[i + 1];
    else if (a == "--dem") which = argv[i + 1];
    else if (a == "--sets") sets = argv[i + 1];
    else if (a == "--hard-pairs") hard_pairs = std::atoi(argv[i + 1]);
    else if (a == "--max-detour") max_detour = std::atof(argv[i + 1]);
    else if (a == "--product-seeds") product_seeds = std::max(1, std::atoi(argv[i + 1]));
    else if (a == "--spacing") ours.spacing_m = std::atof(argv[i + 1]);
    else if (a == "--passes") ours.passes = std::atoi(argv[i + 1]);
    else if (a == "--max-vertices") ours.max_vertices = std::atoi(argv[i + 1]);
    else if (a == "--plan-share") ours.plan_share = std::atof(argv[i + 1]);
    else if (a == "--knn") ours.rrt.k_nearest = std::atoi(argv[i + 1]) != 0;
    else if (a == "--prune") ours.rrt.prune_tree = std::atoi(argv[i + 1]) != 0;
    else if (a == "--goal-bias") ours.rrt.goal_bias = std::atof(argv[i + 1]);
    else if (a == "--ompl-plan-share") ompl_plan_share = std::atof(argv[i + 1]);
    else if (a == "--ompl-planners") {
      ompl_planners.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');) ompl_planners.push_back(item);
    }
    else if (a == "--protocols") {
      const std::string list = argv[i + 1];
      protocol_inside = list.find("inside") != std::string::npos;
      protocol_after = list.find("after") != std::string::npos;
    }
    else if (a == "--refine") ours.refine = std::atoi(argv[i + 1]) != 0;
    else if (a == "--refine-min-step") ours.refinement.min_step_m = std::atof(argv[i + 1]);
    else if (a == "--refine-shortcuts") ours.refinement.shortcut_attempts = std::atoi(argv[i + 1]);
    else if (a == "--variant") {  // NAME,PLAN_SHARE,MAX_VERTICES,PASSES,REFINE: another of ours, same run
      OurOptions variant = ours;
      std::stringstream fields(argv[i + 1]);
      std::string name, share, maxv, npasses, refine;
      std::getline(fields, name, ',');
      std::getline(fields, share, ',');
      std::getline(fields, maxv, ',');
      std::getline(fields, npasses, ',');
      std::getline(fields, refine, ',');
      std::string flags;
      std::getline(fields, flags, ',');
      std::stringstream flag_list(flags);
      for (std::string flag; std::getline(flag_list, flag, '+');) {
        if (flag == "knn") variant.rrt.k_nearest = true;
        else if (flag == "radius") variant.rrt.k_nearest = false;
        else if (flag == "prune") variant.rrt.prune_tree = true;
        else if (flag == "noprune") variant.rrt.prune_tree = false;
        else if (flag.rfind("gb=", 0) == 0) variant.rrt.goal_bias = std::atof(flag.c_str() + 3);
        else if (flag.rfind("rf=", 0) == 0) variant.rrt.rewire_factor = std::atof(flag.c_str() + 3);
        else if (flag.rfind("stepx=", 0) == 0) variant.step_factor = std::atof(flag.c_str() + 6);
        else if (!flag.empty()) {
          std::fprintf(stderr, "unknown variant flag %s\n", flag.c_str());
          return 2;
        }
      }
      variant.name = "skyroute " + name;
      variant.plan_share = std::atof(share.c_str());
      variant.max_vertices = std::atoi(maxv.c_str());
      variant.passes = std::atoi(npasses.c_str());
      variant.refine = std::atoi(refine.c_str()) != 0;
      variants.push_back(variant);
    }
    else if (a == "--product") with_product = std::atoi(argv[i + 1]) != 0;
    else if (a == "--ompl") with_ompl = std::atoi(argv[i + 1]) != 0;  // 0: ours only (tuning runs)
    else if (a == "--budgets") {  // comma-separated, replaces 10,50,100 (the long one is added)
      budgets.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');) budgets.push_back(std::atof(item.c_str()));
    }
    else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  ompl::RNG::setSeed(12345);
  const std::string dir = SKYROUTE_SHARED_DATA_DIR;
  std::vector<DemCase> cases;
  const bool easy_set = sets.find("easy") != std::string::npos, hard_set = sets.find("hard") != std::string::npos;
  if (easy_set && which != "tif") cases.push_back({"N44W072", dir + "/dem/N44W072.hgt", 900.0, 8000.0, 15000.0});
  if (easy_set && which != "hgt") cases.push_back({"davosdorf", dir + "/dem/davosdorf.tif", 2500.0, 4000.0, 8000.0});
  if (hard_set && which != "tif") {
    cases.push_back({"N44W072 hard", dir + "/dem/N44W072.hgt", 900.0, 15000.0, 30000.0, true});
  }
  if (long_ms > 0) budgets.push_back(long_ms);
  if (!with_ompl) ompl_planners.clear();
  OurOptions ours_after = ours;
  ours_after.name = "skyroute RRT* [after]";
  ours_after.inside = false;

  std::ofstream csv(csv_path);
  csv << "dem,pair,planner,budget_ms,solved,plan_s,length_m,simplified_m,simplify_s,tree_size,best_m,lospo_m,refine_s\n";
  // (planner, budget, simplified?) -> ratios
  std::map<std::tuple<std::string, double, bool>, std::vector<double>> ratios;
  std::map<std::tuple<std::string, double>, std::vector<double>> simplify_times;
  std::map<std::tuple<std::string, double>, int> solved_count;
  std::map<std::tuple<std::string, double>, int> run_count;  // runs per row (product rows: pairs x seeds)
  std::map<std::string, std::vector<double>> plan_times;  // CPU ms of the whole leg, product default budget
  std::map<std::tuple<std::string, double>, std::vector<double>> leg_times;  // CPU ms of the planner (product: the leg)
  int total_pairs = 0;
  std::size_t planned_pairs = 0;
  for (const DemCase& dc : cases) planned_pairs += static_cast<std::size_t>(dc.hard ? hard_pairs : pairs_per_dem);
  skyroute::bench::BenchProgress progress("rrt_star_bench", planned_pairs);
  std::map<std::string, int> set_pairs;  // "easy" / "hard" -> pairs run
  for (const DemCase& dc : cases) {
    skyroute::CollisionWorldOptions wo;
    wo.ceiling_m = dc.ceiling_m;
    wo.build_octree = false;
    auto world = skyroute::loadTerrainWorld(dc.path, wo);
    if (!world.ok()) {
      std::fprintf(stderr, "%s: %s\n", dc.path.c_str(), world.error().describe().c_str());
      return 1;
    }
    std::vector<std::unique_ptr<skyroute::WorldMotionValidator>> validators;
    const auto labelling_started = std::chrono::steady_clock::now();
    const skyroute::FlyableRegions& regions = world->collision->flyableRegions();
    const double labelling_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - labelling_started).count();
    const double corridor_margin_m = skyroute::pipelineReplanOptions(skyroute::PipelineOptions{}, skyroute::PlanBudget{}, 1)
                                         .route.corridor_margin_m;
    const std::vector<Pair> pairs = dc.hard ? makeHardPairs(*world, dc, hard_pairs, 2027, corridor_margin_m, max_detour, validators)
                                            : makePairs(*world, dc, pairs_per_dem, 2026, 0.5, validators);
    std::printf("%s: %zu pairs, ceiling %.0f m, %.0f-%.0f km apart; flyable regions labelled in %.1f ms (%d x %d "
                "blocks of %d cells, %d regions)\n",
                dc.name.c_str(), pairs.size(), dc.ceiling_m, dc.min_dist_m / 1000, dc.max_dist_m / 1000, labelling_ms,
                regions.blocksWide(), regions.blocksHigh(), regions.pool(), regions.regionCount());
    std::fflush(stdout);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const MotionValidator& v = *validators[k];
      const double step_m = 0.2 * v.samplingBounds().diagonal().norm();
      std::vector<Run> runs;
      for (double b : budgets) {
        if (protocol_inside) {
          runs.push_back(runOurs(v, pairs[k], b, 1000 + k, step_m, ours));
          for (const OurOptions& variant : variants) runs.push_back(runOurs(v, pairs[k], b, 1000 + k, step_m, variant));
          for (const auto& name : ompl_planners) runs.push_back(runOmpl(name, v, pairs[k], b, step_m, ompl_plan_share));
        }
        if (protocol_after) {
          runs.push_back(runOurs(v, pairs[k], b, 1000 + k, step_m, ours_after));
          for (const auto& name : ompl_planners) runs.push_back(runOmpl(name, v, pairs[k], b, step_m, 1.0));
        }
      }
      double best = INFINITY;
      for (const Run& r : runs) {
        if (r.solved) best = std::min({best, r.length_m, r.simplified_m});
      }
      if (with_product) {  // after `best`: the product rows are measured against the others' best
        const std::size_t first_product = runs.size();
        for (int seed = 0; seed < product_seeds; ++seed) {
          const std::uint64_t product_seed = 1000 + k + 7919 * static_cast<std::uint64_t>(seed);
          for (double b : budgets) runs.push_back(runProduct(world->collision, pairs[k], b, product_seed));
          runs.push_back(runProduct(world->collision, pairs[k], 0.0, product_seed));
        }
        // On the hard legs the product's guided search can beat every planner row over the whole
        // terrain: there the best known length counts every row.
        for (std::size_t r = first_product; dc.hard && r < runs.size(); ++r) {
          if (runs[r].solved) best = std::min({best, runs[r].length_m, runs[r].simplified_m});
        }
      }
      progress.done(dc.name + " pair " + std::to_string(k));
      const std::string set = dc.hard ? "hard" : "easy";
      ++set_pairs[set];
      for (Run& r : runs) {
        const std::string key = set + "|" + r.planner;
        r.dem = dc.name;
        r.pair = static_cast<int>(k);
        csv << r.dem << ',' << r.pair << ',' << r.planner << ',' << r.budget_ms << ',' << r.solved << ',' << r.plan_s
            << ',' << r.length_m << ',' << r.simplified_m << ',' << r.simplify_s << ',' << r.tree_size << ','
            << best << ',' << r.lospo_m << ',' << r.refine_s << '\n';
        // Unsolved runs count as infinitely long (they push medians up, as they should).
        ratios[{key, r.budget_ms, false}].push_back(r.solved ? r.length_m / best : INFINITY);
        ratios[{key, r.budget_ms, true}].push_back(r.solved ? r.simplified_m / best : INFINITY);
        simplify_times[{key, r.budget_ms}].push_back(r.simplify_s * 1000);
        solved_count[{key, r.budget_ms}] += r.solved ? 1 : 0;
        ++run_count[{key, r.budget_ms}];
        leg_times[{key, r.budget_ms}].push_back(r.plan_s * 1000);
        if (r.budget_ms == 0.0) plan_times[key].push_back(r.plan_s * 1000);
        if (r.planner == "skyroute RRT*") {  // the same run before the refinement
          const std::string before = set + "|skyroute RRT* LOSPO only";
          ratios[{before, r.budget_ms, false}].push_back(r.solved ? r.length_m / best : INFINITY);
          ratios[{before, r.budget_ms, true}].push_back(r.solved ? r.lospo_m / best : INFINITY);
          simplify_times[{before, r.budget_ms}].push_back((r.simplify_s - r.refine_s) * 1000);
          solved_count[{before, r.budget_ms}] += r.solved ? 1 : 0;
          ++run_count[{before, r.budget_ms}];
        }
      }
      ++total_pairs;
      std::printf("  pair %2zu: %.0f m straight, best %.0f m\n", k, (pairs[k].goal - pairs[k].start).norm(), best);
      std::fflush(stdout);
    }
  }
  std::printf("\n%d pairs. Ratio = length / best length any planner found for the pair (all budgets).\n", total_pairs);
  std::printf("Budgets in thread CPU time. post = LOSPO + refinePath %s (skyroute, %.0f m spacing, at most %d vertices, "
              "up to %d passes) or PathSimplifier (OMPL). Inside protocol: RRT* gets %.0f%% of the budget, OMPL's planner "
              "%.0f%%, post-processing the rest. After protocol ([after] for ours, no tag for OMPL): the planner gets the "
              "whole budget, then LOSPO + refinePath / simplifyMax untimed. post ms = CPU ms of the post-processing.\n\n",
              ours.refine ? "on" : "off", ours.spacing_m, ours.max_vertices, ours.passes, 100 * ours.plan_share,
              100 * ompl_plan_share);
  std::printf("| legs | planner | budget ms | solved | median raw | p90 raw | median post | p90 post | median post ms | median plan ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> names;
  if (protocol_inside) {
    names = {"skyroute RRT*", "skyroute RRT* LOSPO only"};
    for (const OurOptions& variant : variants) names.push_back(variant.name);
    for (const auto& n : ompl_planners) names.push_back("OMPL " + n + " [inside]");
  }
  if (protocol_after) {
    names.push_back(ours_after.name);
    for (const auto& n : ompl_planners) names.push_back("OMPL " + n);
  }
  if (with_product) names.push_back(productRowName(false));
  for (const auto& [set, count] : set_pairs) {
    for (double b : budgets) {
      for (const auto& n : names) {
        const std::string key = set + "|" + n;
        std::printf("| %s | %s | %.0f | %d/%d | %.3f | %.3f | %.3f | %.3f | %.1f | %.1f |\n", set.c_str(), n.c_str(), b,
                    solved_count[{key, b}], run_count[{key, b}], quantile(ratios[{key, b, false}], 0.5),
                    quantile(ratios[{key, b, false}], 0.9), quantile(ratios[{key, b, true}], 0.5),
                    quantile(ratios[{key, b, true}], 0.9), quantile(simplify_times[{key, b}], 0.5),
                    quantile(leg_times[{key, b}], 0.5));
      }
    }
    if (with_product) {
      const std::string n = productRowName(true), key = set + "|" + n;
      std::printf("| %s | %s | %llu it, cap %.0f s | %d/%d | %.3f | %.3f | %.3f | %.3f | - | %.1f |\n", set.c_str(),
                  n.c_str(), static_cast<unsigned long long>(skyroute::PlanBudget{}.leg_max_iterations),
                  skyroute::PlanBudget{}.leg_time_cap_s, solved_count[{key, 0.0}], run_count[{key, 0.0}],
                  quantile(ratios[{key, 0.0, false}], 0.5), quantile(ratios[{key, 0.0, false}], 0.9),
                  quantile(ratios[{key, 0.0, true}], 0.5), quantile(ratios[{key, 0.0, true}], 0.9),
                  quantile(plan_times[key], 0.5));
    }
  }
  if (with_product) {
    std::printf("\nproduct rows: raw = RRT*, post = after LOSPO (no refinePath); budgets are the product's wall-clock "
                "cap; their post ms is not measured, except the [default budget] row's, which is the CPU ms of the "
                "whole leg.\n");
  }
  // The headline comparison: ours against InformedRRTstar + simplifier under the same protocol.
  std::printf("\nMedian post ratio to five places, ours against OMPL InformedRRTstar + simplifier:\n\n");
  std::printf("| legs | protocol | budget ms | ours | InformedRRTstar | ours raw | InformedRRTstar raw |\n|---|---|---|---|---|---|---|\n");
  const std::vector<std::tuple<std::string, std::string, std::string>> protocols{
      {"inside", "skyroute RRT*", "OMPL InformedRRTstar [inside]"}, {"after", ours_after.name, "OMPL InformedRRTstar"}};
  for (const auto& [set, count] : set_pairs) {
    for (const auto& [protocol, mine_name, theirs_name] : protocols) {
      const std::string mine = set + "|" + mine_name, theirs = set + "|" + theirs_name;
      if (!ratios.count({mine, budgets.front(), true}) || !ratios.count({theirs, budgets.front(), true})) continue;
      for (double b : budgets) {
        std::printf("| %s | %s | %.0f | %.5f | %.5f | %.5f | %.5f |\n", set.c_str(), protocol.c_str(), b,
                    quantile(ratios[{mine, b, true}], 0.5), quantile(ratios[{theirs, b, true}], 0.5),
                    quantile(ratios[{mine, b, false}], 0.5), quantile(ratios[{theirs, b, false}], 0.5));
      }
    }
  }
  return 0;
}
