// Real-time replanning around moving obstacles (seed 003 section 3-2): the vehicle flies its
// trajectory; every period (t_ref = 0.1 s) the part ahead, up to a horizon, is checked against the
// obstacles where they will be at each instant. When it meets one, the route is replanned from the
// vehicle's predicted state at a takeover time (position, velocity, acceleration and jerk kept, so
// the flown curve stays continuous) with the obstacles frozen at that time and grown by the room
// they can cover meanwhile, and the new trajectory (revision + 1) is re-checked in time.
// Commit horizon: the takeover is at least a reaction delay ahead, later when the vehicle is in
// the middle of a manoeuvre then (a new curve cannot continue a turn at its acceleration limit),
// and the new revision keeps the current trajectory's own curve from the cycle's time up to the
// takeover: it starts where the vehicle is now, with no gap, and the joint is exact.
// When no better plan is found in a cycle, the vehicle holds: the new revision keeps the current
// trajectory as far as it stays clear, then stops (a checked stop from the state there) and waits
// at rest; the mission is not finished, and every cycle tries to plan on from the hold.
// A fixed wing cannot stop: its hold is a loiter (trajectory/loiter.hpp): the current trajectory
// kept as far as it is clear, then a level circle at least loiter_radius_margin times wider than
// its tightest turn at the loiter speed (cruise, never under the minimum airspeed), flown for
// twice the horizon and extended by whole arcs (a new revision) while the hold lasts; the next
// cycles plan on from a point on the circle, with its velocity. With no clear circle, the step
// says so (hold_failure) and the current trajectory stays in force, as without holds.
// DDS-free: the engine and the tests drive it with a world clock.
// Defaults: on the seed-003 Table 1 scenario (obstacles at 60-80 m/s, faster than the vehicle) a
// 30 s horizon with 4 attempts let obstacle B catch the vehicle; 45 s and 8 attempts avoid all three.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "service/route_planner.hpp"
#include "trajectory/loiter.hpp"

namespace skyroute {

struct ReplanOptions {
  double period_s = 0.1;            // t_ref
  double horizon_s = 45.0;          // how far ahead conflicts are looked for
  double check_step_s = 0.25;       // time step of the chords checked against moving obstacles
  double reaction_delay_s = 0.1;    // the new trajectory takes over at least this long after the check
  // The takeover moves up to this much later along the current trajectory (never past a quarter
  // of the time to the conflict) to the first state whose lateral acceleration (across the
  // velocity: turning) is at most calm_accel_share of the limit and whose jerk is at most
  // calm_jerk_mps3; with none, to the calmest one. 0 = always the reaction delay.
  double max_commit_s = 3.0;
  double calm_accel_share = 0.2;
  double calm_jerk_mps3 = 2.0;
  // Share of the acceleration limit the time allocation of a replan uses (at most
  // route.trajectory.time_allocation's). A curve that starts at speed cannot ease into the
  // allocation's profile: at 0.5 the first segment overshot the limit in 89 of 895 replan
  // attempts of engine_replan_bench --rounds 200 (embedded case), at 0.3 in 37 of 904 (holds 18
  // -> 8), but 0.3 cost every seed of replan_bench 6 m of separation from the seed-003
  // obstacles (the turn away is slower), so the default stays the first plan's.
  double replan_accel_fraction = 0.5;
  // No better trajectory within the cycle: adopt the hold (keep the current one as far as it is
  // clear, then stop) instead of keeping a trajectory that meets an obstacle; from the hold the
  // next cycles plan past the deadline until a first candidate. The stop comes to rest off the
  // moving obstacles' tracks when it can (the wait may outlast the horizon), and a clear hold is
  // left only for a candidate clear of the obstacles that keeps 30 m from them over the horizon
  // (or more room than the hold keeps). Off = the current trajectory stays in force and the cycle plans past
  // its deadline until a first candidate at once.
  bool hold_fallback = true;
  // A fixed wing's loiter circle: its radius over the tightest turn at the loiter speed (>= 1;
  // 1.3 flies a 35-degree bank limit at about 28 degrees), tried first and then 1.6 times wider.
  double loiter_radius_margin = 1.3;
  double margin_m = 150.0;          // extra room kept from every moving obstacle when planning
  double window_s = 15.0;           // planning blocks the stretch each obstacle covers this long
  int max_attempts = 8;             // seeds, windows and margins tried per replan; the candidate
                                    // whose first conflict comes latest wins, and it replaces the
                                    // current trajectory only when it is better than it
  // Local repair, tried first: only the stretch that meets the obstacle is replanned, from the
  // takeover state to a knot of the current trajectory this long after the conflict (longer in
  // later attempts), ending in the current trajectory's state there (position to jerk), so the
  // rest of the trajectory is kept, shifted in time. When no local candidate does better, the
  // whole remaining route is replanned.
  bool local_repair = true;
  double rejoin_after_s = 8.0;
  bool local_retime = true;         // local attempts also fly the current path slower
  // The time band of the third attempt's obstacle snapshot: a place at distance d from the
  // takeover point is blocked by where the obstacles are between d / max speed and
  // d / (band_slow_factor V_ref), widened by band_slack_s.
  double band_slow_factor = 0.4;
  double band_slack_s = 3.0;
  RouteOptions route;               // per-leg budget, LOSPO, trajectory options
  // RRT* tree reuse (seed 003 section 3-2): the first leg's RRT* tree of the plan in force is
  // kept (route.tree_reuse.max_nodes at most), and a replan's first leg grows it, re-rooted at
  // the takeover point, instead of a new tree (RouteOptions::first_leg_tree).
  bool rrt_tree_reuse = false;
  // Wall-clock budget of one replan, from the conflict check to the new trajectory, all attempts
  // included (the RRT* and LOSPO stop at it; the trajectory build and check of the path in hand
  // finish). When it runs out the best candidate so far is used; when there is none yet, the
  // vehicle holds (hold_fallback), or, from a hold or without holds, the attempts go on without
  // the deadline until the first candidate. 0 = none (then a run with iteration budgets is
  // reproducible).
  // The first plan (start()) has no such deadline.
  double replan_budget_ms = 12.0;
  // A reproducible stand-in for that budget (tests, benchmarks): a replan's deadline counts as
  // passed once this many of its attempts (local and whole together) have run, as the wall clock
  // would pass it on a loaded machine. 0 = none.
  int replan_budget_attempts = 0;
  // RRT* iterations per leg when replanning; 0 = route.leg_max_iterations.
  std::uint64_t replan_leg_max_iterations = 0;
  // Trajectory repair rounds when replanning (at most route.trajectory.max_repair_rounds; < 0 =
  // those). The build cannot be cut short by the deadline; a cap bounds it, but the first turn
  // away from an obstacle often needs several rounds (capping at 4 failed those avoidance replans
  // in the seed-003 scenario and the vehicle hit an obstacle), so by default there is none.
  int replan_max_repair_rounds = -1;
  // Set from any thread to stop the planning in progress (start() and step() then fail with
  // kCancelled); the engine uses it to cancel in-flight plans.
  std::shared_ptr<std::atomic<bool>> cancel;
  // The audit of every trajectory the flight is about to put in force (service/trajectory_audit.hpp,
  // a check that is not this planner's; the mission pipeline sets it): an error (field "audit")
  // when it refuses `trajectory`, which starts at world time start_world_s, checked at world time
  // now_s as the flight's revision `revision`. A refused trajectory is never adopted: the current
  // one stays in force, or a hold that passes the audit. Empty: no audit.
  std::function<std::optional<Error>(const Trajectory& trajectory, double start_world_s, double now_s,
                                     std::uint32_t revision)>
      audit;
};

struct ReplanStep {
  bool conflict_ahead = false;      // the current trajectory meets an obstacle within the horizon
  bool replanned = false;           // a new revision was made
  bool local = false;               // ... by local repair (the rest of the trajectory kept)
  // No better plan: a new revision that keeps the current trajectory as far as it is clear and
  // then stops and waits at rest (failure says why no plan was found).
  bool holding = false;
  bool loiter = false;              // ... and the hold is a loiter (a fixed wing)
  // A fixed wing whose replan failed and for which no loiter circle is clear (kUnreachable,
  // field "loiter", naming what was tried): the current revision stays in force.
  std::optional<Error> hold_failure;
  double takeover_s = 0.0;          // world time the new revision's plan starts from
  double latency_ms = 0.0;          // wall time of the replan (check included)
  std::size_t reused_tree_nodes = 0;  // nodes of the kept RRT* tree the adopted plan's first leg grew
  std::optional<Error> failure;     // why no new plan could be made (without holding, the old revision is kept)
};

class FlightReplanner {
 public:
  // points_m: the route in visiting order; the first is where the vehicle is at start_world_s.
  // first_legs: the global planner of the first plan (empty: RRT* + LOSPO); its attempts run with
  // the same obstacle windows and margins as a replan's. Replans always use RRT* + LOSPO.
  static Result<std::unique_ptr<FlightReplanner>> start(std::shared_ptr<const CollisionWorld> world,
                                                        std::vector<Eigen::Vector3d> points_m,
                                                        const VehicleLimits& limits, const ReplanOptions& options,
                                                        double start_world_s, const LegPathPlanner& first_legs = {});
  // The same, flying a route planned elsewhere (another global planner; route.built set, starting
  // at start_world_s); replans still use RRT* + LOSPO.
  static Result<std::unique_ptr<FlightReplanner>> startWithRoute(std::shared_ptr<const CollisionWorld> world,
                                                                 std::vector<Eigen::Vector3d> points_m,
                                                                 const VehicleLimits& limits,
                                                                 const ReplanOptions& options, double start_world_s,
                                                                 PlannedRoute route);

  // One cycle at world time now_s.
  ReplanStep step(double now_s);
  // The loiter in force (a fixed wing's hold), if any.
  const std::optional<LoiterCircle>& loiterCircle() const { return loiter_circle_; }
  // The points still to visit are to be flown in a new order (mission_reorder.hpp; defined in
  // flight_reroute.cpp): the whole rest of the route is planned again through points_m, from the
  // takeover a step at now_s would use (takeoverS), as a whole replan is. The new revision is
  // adopted when its first conflict comes no sooner than the current trajectory's; otherwise
  // failure says why and the current revision stays. Within the replan budget first, then, when
  // it ran out with nothing, until a first candidate (a new order is not worth less for being late).
  ReplanStep reroute(double now_s, const std::vector<Eigen::Vector3d>& points_m);
  // The takeover time of a replan at now_s (see ReplanOptions::max_commit_s).
  double takeoverS(double now_s) const;

  TrajectoryState stateAt(double world_s) const;
  // A holding vehicle has not finished: its route points are still ahead.
  bool finished(double world_s) const {
    return !holding_ && world_s >= start_world_s_ + route_.built.trajectory.duration_s();
  }
  // The revision in force is a hold (no plan reaches the goal yet); every cycle plans again.
  bool holding() const { return holding_; }
  double arrivalWorldS() const { return start_world_s_ + route_.built.trajectory.duration_s(); }
  const PlannedRoute& route() const { return route_; }
  double trajectoryStartWorldS() const { return start_world_s_; }
  std::uint32_t revision() const { return revision_; }
  // The route points not yet reached at world_s (the goal always stays).
  std::vector<Eigen::Vector3d> remainingPoints(double world_s) const;
  // Whether the trajectory from now_s on is clear: of the moving obstacles up to now_s +
  // horizon_s, of what stays in force (below) to its end.
  bool clearAhead(double now_s, double horizon_s) const;
  // World time of the first conflict of `trajectory` (started at start_world_s) from from_s on;
  // infinity when there is none. The moving obstacles are checked where they will be over
  // [from_s, from_s + horizon_s] (their predictions further ahead are not worth acting on: the
  // next cycles look again); what stays in force (the terrain, the ceiling, fixed obstacles and
  // the no-fly zones in force at each moment) over the whole rest of the trajectory, so a zone far
  // ahead is seen when it appears, not when it comes within the horizon.
  double firstConflictS(const Trajectory& trajectory, double start_world_s, double from_s, double horizon_s) const;
  // The least room between the vehicle's sphere on `trajectory` and any obstacle over
  // [from_s, from_s + horizon_s] (CollisionWorld::obstacleDistance, sampled finely near them),
  // at most cap_m.
  double roomAlong(const Trajectory& trajectory, double start_world_s, double from_s, double horizon_s,
                   double cap_m) const;

 private:
  // The cycle's stop: the replan budget (`share` of it) counted from `started` (the start of the
  // cycle), and the cancel flag.
  TerminationCondition cycleStop(std::chrono::steady_clock::time_point started, double share = 1.0) const;
  // Whether the cycle's deadline has passed: `stop`'s own, or ReplanOptions::replan_budget_attempts.
  bool deadlinePassed(const TerminationCondition& stop) const;
  FlightReplanner() = default;
  // Where a local repair joins the current trajectory again.
  struct Rejoin {
    std::size_t knot = 0;       // index of the current trajectory's knot
    double time_s = 0.0;        // its trajectory time
    std::size_t points_before = 0;  // route points (after the first) reached before it, or at it
    bool at_point = false;      // the knot is the last of those route points
  };
  // One attempt's problem: the points to plan through (the whole remaining route, or the local
  // stretch up to the rejoin), and the current path over the same stretch (not worth trying again).
  struct AttemptPlan {
    std::vector<Eigen::Vector3d> points;
    std::optional<Rejoin> rejoin;
    std::vector<Eigen::Vector3d> current_path;
    std::vector<Eigen::Vector3d> route_points;  // the whole remaining route's, for adopt()
    int variant = 0;            // how far ahead the obstacles block, and how much room (0..3)
    // < 1: no new path, the current one flown slower to the rejoin (a crossing obstacle passes
    // ahead of the vehicle); the reference speed is scaled by this.
    double retime_speed_factor = 1.0;
    double conflict_in_s = 0.0;  // how far ahead of the takeover the current trajectory meets an obstacle
  };
  struct Candidate {
    PlannedRoute route;
    std::vector<Eigen::Vector3d> points;  // the whole route's points, for adopt()
    double conflict_s = 0.0;              // world time of its first conflict (infinity: none)
  };
  RouteOptions attemptOptions(const std::vector<Eigen::Vector3d>& points, double at_world_s,
                              const TrajectoryState* state, int attempt, int variant, double conflict_in_s,
                              const std::optional<Rejoin>& rejoin) const;
  // The local stretch for an attempt: from the takeover state to the rejoin knot, the first
  // past the attempt's time after the conflict that is clear of what stays in force there;
  // nullopt when the rejoin would be the end of the trajectory anyway (a whole replan is the same
  // problem), or for a retimed attempt when the conflict is with what stays in force
  // (static_conflict: a no-fly zone does not pass while the vehicle slows down).
  std::optional<AttemptPlan> localPlan(const std::vector<Eigen::Vector3d>& route_points, double takeover_s,
                                       double conflict_s, int attempt, bool static_conflict) const;
  AttemptPlan wholePlan(const std::vector<Eigen::Vector3d>& route_points,
                        const std::vector<Eigen::Vector3d>& current_path, int attempt) const;
  // The current path over a local stretch as a planned route (no search), for retiming.
  Result<PlannedRoute> currentStretch(const AttemptPlan& plan) const;
  // The local candidate joined with the current trajectory from the rejoin knot on.
  Candidate splice(PlannedRoute local, const Rejoin& rejoin, const std::vector<Eigen::Vector3d>& route_points) const;
  // Tries the attempts (until one is conflict-free or `stop` fires) and returns the candidate
  // whose first conflict is latest. A path equal to the attempt's current path or to an earlier
  // attempt's is not built nor checked again: it cannot do better. With first_only, the first
  // candidate built is returned.
  // legs: the global planner of whole-route attempts (empty: RRT* + LOSPO).
  Result<Candidate> bestCandidate(const std::function<std::optional<AttemptPlan>(int)>& plan_of, double at_world_s,
                                  const TrajectoryState* state, const TerminationCondition& stop,
                                  bool first_only = false, const LegPathPlanner& legs = {}) const;
  // The current route's waypoints not yet reached at world_s, with `from` in front.
  std::vector<Eigen::Vector3d> waypointsAhead(const Eigen::Vector3d& from, double world_s) const;
  void adopt(PlannedRoute route, std::vector<Eigen::Vector3d> points, double start_world_s);
  // The takeover time of a replan at now_s whose current trajectory first meets an obstacle at
  // conflict_s (see ReplanOptions::max_commit_s).
  double takeoverTime(double now_s, double conflict_s) const;
  // The candidate (planned from the takeover) with the current trajectory's curve from from_s to
  // the takeover in front: it then starts at from_s (world times).
  Candidate withKeptPart(Candidate candidate, double from_s, double takeover_s) const;
  // Adopts the hold for a current trajectory meeting an obstacle at conflict_s, when one does
  // better than it (a later conflict, or none); false when none does.
  bool adoptHold(double now_s, double takeover_s, double conflict_s);
  // A fixed wing's hold (defined in flight_loiter.cpp): the current trajectory up to an entry
  // time, then a loiter; false, with why_not set, when no circle does better than the current
  // trajectory.
  bool adoptLoiter(double now_s, double takeover_s, double conflict_s, std::optional<Error>& why_not);
  // A loiter in force that ends within the horizon gets more turns of the same circle (the same
  // curve from now on, so a new revision continuous to the jerk); true when it did.
  bool extendLoiter(double now_s);
  // The takeover from a loiter at now_s: within the next turn, where the vehicle heads most
  // nearly for the next route point.
  double loiterExitTime(double now_s) const;
  // Puts `hold` (starting at world time from_s) in force as a hold: the route points the kept
  // part reaches by kept_until_s keep their times, the others are not reached.
  void installHold(Trajectory hold, double from_s, double kept_until_s);
  ReplanStep stepOnce(double now_s);
  // firstConflictS's two parts: the moving obstacles (and everything else) over the horizon, and
  // what stays in force from from_s to the end of the trajectory.
  double conflictWithinS(const Trajectory& trajectory, double start_world_s, double from_s, double horizon_s) const;
  double staticConflictAfterS(const Trajectory& trajectory, double start_world_s, double from_s) const;
  // The current trajectory's first conflict from now_s (firstConflictS). The part beyond the
  // horizon is checked again only when the world or the trajectory changed since it was last
  // found clear (what stays in force does not move, and that part only shrinks as time passes).
  double currentConflictS(double now_s);
  // The audit's verdict on a trajectory about to be adopted as `revision` (nothing: it passes, or
  // there is no audit).
  std::optional<Error> auditRefusal(const Trajectory& trajectory, double start_world_s, double now_s,
                                    std::uint32_t revision) const;

  std::shared_ptr<const CollisionWorld> world_;
  VehicleLimits limits_;
  ReplanOptions options_;
  PlannedRoute route_;
  std::vector<Eigen::Vector3d> points_;        // points of the current trajectory, in order
  std::vector<double> point_times_world_s_;    // when the current trajectory reaches each
  std::vector<double> waypoint_times_world_s_; // when it reaches each of route_.waypoints_m
  double start_world_s_ = 0.0;
  std::uint32_t revision_ = 0;
  int failed_cycles_ = 0;  // replanning cycles in a row that found nothing better
  mutable int cycle_attempts_ = 0;  // attempts run in this cycle (ReplanOptions::replan_budget_attempts)
  bool holding_ = false;
  std::optional<LoiterCircle> loiter_circle_;  // the loiter in force
  double loiter_end_rad_ = 0.0;               // where its last arc ends
  std::shared_ptr<const RrtTree> leg_tree_;  // ReplanOptions::rrt_tree_reuse: the first leg's tree in force
  // A replan whose deadline may answer with a hold: the trajectory build stops at the deadline
  // too. Off when a hold is no answer (one in force, none allowed, or a conflict beyond the horizon).
  bool deadline_holds_ = true;
  // currentConflictS's memory: the current trajectory (counted by trajectory_changes_) was found
  // clear beyond the horizon with what stayed in force at CollisionWorld::staticVersion().
  std::uint64_t trajectory_changes_ = 0;
  std::optional<std::pair<std::uint64_t, std::uint64_t>> clear_beyond_;  // (static version, trajectory_changes_)
};

}  // namespace skyroute
