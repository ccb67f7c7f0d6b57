#include "service/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "service/engine_state.hpp"
#include "service/mission_point_check.hpp"
#include "service/no_fly_placement.hpp"
#include "service/number_text.hpp"
#include "service/trajectory_data.hpp"

namespace skyroute {

using engine_detail::cancelledStatus;

namespace {

// Plans of one request on a world that changed while each ran (see Engine::plan), at most.
constexpr int kPlansOnAChangingWorld = 3;

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The request's points in ENU, begin first, end last.
std::vector<Eigen::Vector3d> enuPoints(const MissionRequestData& r, const LocalFrame& frame) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(r.points.size() + 2);
  points.push_back(r.begin.toEnu(frame));
  for (const MissionPointData& p : r.points) points.push_back(p.toEnu(frame));
  points.push_back(r.end.toEnu(frame));
  return points;
}

// Cheap checks on the request's points before anything is planned or estimated: inside the
// terrain (a point far outside it would make every estimate meaningless), then the footprint.
std::optional<PlanError> checkRequestSize(const MissionRequestData& r, const WorldModel& world,
                                          const EngineOptions& options) {
  const std::vector<Eigen::Vector3d> points = enuPoints(r, world.frame());
  const int count = static_cast<int>(points.size());
  for (int i = 0; i < count; ++i) {
    const MissionPointData& point = i == 0 ? r.begin : i == count - 1 ? r.end : r.points[static_cast<std::size_t>(i - 1)];
    if (auto off = checkPointOnTerrain(world.terrain(), point, requestPointName(i, count))) {
      off->point_index = i;
      return off;
    }
  }
  const FootprintOptions footprint = footprintOptions(options);
  return checkFootprint(estimateFootprint(points, r.fixed_order, r.limits.v_ref_mps, footprint), r.limits.v_ref_mps,
                        footprint);
}

// What the order stage chose and the plan's notes (a fired wall-clock cap, a stop at a point), in the log.
void logPlanned(const MissionRequestData& r, const MissionPlan& plan) {
  const MissionOrder& ordering = plan.mission.ordering;
  if (!ordering.fallback_reason.empty()) {
    spdlog::info("event=order_fallback request={} reason=\"{}\"", r.request_id, ordering.fallback_reason);
  }
  spdlog::info("event=order request={} method={} cost_m={:.0f} expansions={} time_ms={:.1f} planner={}", r.request_id,
               ordering.method, ordering.cost_m, ordering.expansions, ordering.time_ms, plan.mission.planner->name);
  for (const std::string& note : plan.notes) {
    spdlog::warn("event=plan_note request={} vehicle={} note=\"{}\"", r.request_id, r.vehicle_id, note);
  }
}

// An update for an obstacle in force that is older than the one applied (valid_from earlier:
// two feeds, or a replayed log) would move it back in time; an update for a new obstacle beyond
// the limit would grow the world without bound. Both are refused, naming the field.
std::optional<PlanError> checkObstacleOrder(const ObstacleUpdateData& update, const WorldModel& world,
                                            const ObstacleBounds& bounds) {
  const std::optional<std::int64_t> in_force = world.validFromOf(update.obstacle.id);
  if (in_force && !update.remove && update.valid_from_utc_ns < *in_force) {
    return PlanError{PlanErrorCode::kInvalidArgument, "valid_from_utc_ns",
                     "obstacle " + std::to_string(update.obstacle.id) + ": valid_from_utc_ns " +
                         std::to_string(update.valid_from_utc_ns) + " is before the update in force (" +
                         std::to_string(*in_force) + "): an update may not go back in time"};
  }
  if (!in_force && !update.remove && world.obstacleCount() >= bounds.max_obstacles) {
    return PlanError{PlanErrorCode::kLimitsOutOfRange, "obstacle_id",
                     "obstacle " + std::to_string(update.obstacle.id) + " refused: " +
                         std::to_string(bounds.max_obstacles) + " obstacles are in force (obstacles.max_active)"};
  }
  return std::nullopt;
}

}  // namespace

std::optional<PlanError> checkMissionAdmission(const MissionRequestData& request, const WorldModel& world,
                                               const EngineOptions& options) {
  std::optional<PlanError> problem = validateMissionRequest(request, options.pipeline.bounds);
  if (!problem && !request.planner.empty()) problem = findRoutePlanner(request.planner, nullptr);
  if (!problem) problem = checkRequestSize(request, world, options);
  return problem;
}

std::optional<PlanError> checkFleetAdmission(const FleetRequestData& request, const EngineOptions& options) {
  return validateFleetRequest(request, fleetMissionOptions(options.pipeline));
}

namespace engine_detail {

PlanStatusData cancelledStatus(const MissionRequestData& r, const std::string& why) {
  return PlanStatusData::failed(r, PlanError{PlanErrorCode::kCancelled, "", why}, 0.0);
}

}  // namespace engine_detail

FootprintOptions footprintOptions(const EngineOptions& o) {
  const PipelineOptions& p = o.pipeline;
  FootprintOptions f;
  f.sample_dt_s = p.sample_dt_s;
  f.trajectory = p.bounds.trajectory;
  f.leg_max_iterations = p.budget.leg_max_iterations;
  f.leg_budget_ms = p.budget.leg_time_cap_s * 1e3;
  f.waypoint_spacing_m = p.replan.route.trajectory.waypoint_spacing_m;
  f.order_cells_per_axis = p.order.max_cells_per_axis;
  f.memory_share_bytes = o.memory_budget_mb * 1024.0 * 1024.0 / std::max(1, o.planning_threads);
  return f;
}

Status validateEngineOptions(const EngineOptions& options) {
  if (options.planning_threads < 1) {
    return make_error(ErrorCode::kInvalidArgument, "planning.threads", "must be at least 1");
  }
  if (!(options.log_repeat_window_s > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "log.repeat_window_s", "must be positive");
  }
  if (auto bad = validatePipelineOptions(options.pipeline)) {
    return make_error(ErrorCode::kInvalidArgument, bad->field, bad->message);
  }
  return Status::success();
}

Result<std::unique_ptr<Engine>> Engine::create(std::shared_ptr<WorldModel> world, const EngineOptions& options,
                                               EngineSink& sink, Clock clock) {
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "no world model");
  if (Status ok = validateEngineOptions(options); !ok.ok()) return ok.error();
  if (!clock) clock = utcNowNs;
  return std::unique_ptr<Engine>(new Engine(std::move(world), options, sink, std::move(clock)));
}

Engine::Engine(std::shared_ptr<WorldModel> world, const EngineOptions& options, EngineSink& sink, Clock clock)
    : sink_(sink),
      clock_(std::move(clock)),
      world_(std::move(world)),
      options_(options),
      registry_(options.max_stored_results),
      throttle_(options.log_repeat_window_s) {
  options_.pipeline.audit_counters = audit_counters_;
}

Engine::~Engine() { stop(); }

Status Engine::setOptions(const EngineOptions& options) {
  if (Status ok = validateEngineOptions(options); !ok.ok()) return ok;
  std::vector<std::thread> retired;
  {
    std::lock_guard lock(mutex_);
    options_ = options;
    options_.pipeline.audit_counters = audit_counters_;  // the counts go on across reloads
    registry_.setCapacity(options.max_stored_results);
    throttle_.setWindowS(options.log_repeat_window_s);
    if (running_ && !stopping_) {
      startWorkers(options.planning_threads);
      // Workers that retired from an earlier reload have ended: join them now.
      for (auto it = workers_.begin(); it != workers_.end();) {
        if (std::find(retired_.begin(), retired_.end(), it->get_id()) != retired_.end()) {
          retired.push_back(std::move(*it));
          it = workers_.erase(it);
        } else {
          ++it;
        }
      }
      retired_.clear();
    }
  }
  work_cv_.notify_all();  // workers beyond the new count retire after their current plan
  for (std::thread& t : retired) t.join();
  return Status::success();
}

EngineOptions Engine::options() const {
  std::lock_guard lock(mutex_);
  return options_;
}

std::shared_ptr<WorldModel> Engine::world() const {
  std::lock_guard lock(mutex_);
  return world_;
}

Status Engine::canReplaceWorld() const {
  std::lock_guard lock(mutex_);
  const std::size_t busy = missions_.size() + fleets_.size() + queue_.size() + in_flight_.size();
  if (busy == 0) return Status::success();
  return make_error(ErrorCode::kInvalidArgument, "terrain.dem",
                    "a terrain change is refused while missions are active or requests are waiting (" +
                        std::to_string(missions_.size()) + " active, " + std::to_string(queue_.size()) + " queued, " +
                        std::to_string(in_flight_.size()) + " planning): their trajectories were checked on the "
                        "terrain in force; cancel them or let them finish, then reload");
}

Status Engine::replaceWorld(std::shared_ptr<WorldModel> world) {
  if (!world) return make_error(ErrorCode::kInvalidArgument, "terrain.dem", "no world model");
  if (Status free = canReplaceWorld(); !free.ok()) return free;
  // Under the lock that obstacle updates and new missions take: none is lost or planned on the
  // old terrain between the check and the swap.
  std::lock_guard lock(mutex_);
  if (!missions_.empty() || !fleets_.empty() || !queue_.empty() || !in_flight_.empty()) {
    return make_error(ErrorCode::kInvalidArgument, "terrain.dem", "a request arrived during the terrain change; retry");
  }
  world->adoptObstacles(*world_);
  world_ = std::move(world);
  return Status::success();
}

void Engine::status(const MissionRequestData& request, PlanState state, double planning_time_s) {
  PlanStatusData s;
  s.request_id = request.request_id;
  s.vehicle_id = request.vehicle_id;
  s.state = state;
  s.planning_time_s = planning_time_s;
  s.requester = request.requester;
  sink_.publishStatus(s);
}

void Engine::finish(const PlanStatusData& status) {
  {
    std::lock_guard lock(mutex_);
    registry_.finish(status);
  }
  sink_.publishStatus(status);
}

std::optional<PlanError> Engine::queueRefusal() const {
  if (stopping_) return PlanError{PlanErrorCode::kBusy, "", "the service is shutting down"};
  if (queue_.size() >= options_.max_queue) {
    return PlanError{PlanErrorCode::kBusy, "",
                     "the planning queue is full (" + std::to_string(options_.max_queue) + " requests); retry later"};
  }
  return std::nullopt;
}

std::optional<PlanError> Engine::enqueue(std::unique_ptr<Job> job, const Validator& validate) {
  std::lock_guard lock(mutex_);
  std::optional<PlanError> problem = validate(options_);
  if (!problem) problem = queueRefusal();
  if (!problem) queue_.push_back(std::move(job));
  return problem;
}

std::optional<PlanError> Engine::submit(MissionRequestData request) {
  std::optional<PlanError> problem;
  std::optional<PlanStatusData> stored;
  {
    std::lock_guard lock(mutex_);
    if (registry_.inFlight(request.vehicle_id, request.request_id)) {
      problem = PlanError{PlanErrorCode::kDuplicateRequest, "request_id",
                          "request_id '" + request.request_id + "' is already queued or being planned for vehicle '" +
                              request.vehicle_id + "': a request id names one plan; use a new id"};
    } else if (!(stored = registry_.finished(request.vehicle_id, request.request_id))) {
      problem = checkMissionAdmission(request, *world_, options_);
      if (!problem) problem = queueRefusal();
      if (!problem) {
        if (Status recorded = sink_.recordAccepted(request); !recorded.ok()) {
          problem = PlanError{PlanErrorCode::kJournalUnavailable, "service.state_dir",
                              "refused: the state journal cannot record the request (" + recorded.error().message +
                                  "); nothing was planned, retry when the journal can write"};
        }
      }
      if (!problem) {
        registry_.begin(request.vehicle_id, request.request_id);
        auto job = std::make_unique<Job>();
        job->request = request;
        queue_.push_back(std::move(job));
      }
    }
  }
  if (stored) {
    // A finished request's id again: its stored answer, addressed to the new requester; no new plan.
    spdlog::info("event=duplicate_request request={} vehicle={} answered=stored state={}", request.request_id,
                 request.vehicle_id, to_string(stored->state));
    stored->requester = request.requester;
    sink_.publishStatus(*stored);
    return std::nullopt;
  }
  if (problem) {
    throttle_.warn("request_rejected:" + request.vehicle_id + ":" + std::string(to_string(problem->code)) + ":" +
                       problem->field,
                   fmt::format("event=request_rejected request={} vehicle={} code={} field={} message=\"{}\"",
                               request.request_id, request.vehicle_id, to_string(problem->code), problem->field,
                               problem->message));
    sink_.publishStatus(PlanStatusData::failed(request, *problem, 0.0));
    return problem;
  }
  spdlog::info("event=request_accepted request={} vehicle={} points={}", request.request_id, request.vehicle_id,
               request.points.size());
  status(request, PlanState::kAccepted);
  work_cv_.notify_one();
  return std::nullopt;
}

bool Engine::cancel(const CancelRequestData& request) {
  std::vector<MissionRequestData> cancelled;
  std::vector<std::shared_ptr<Mission>> ended;
  std::vector<std::string> retracted;
  bool matched = false;
  std::optional<Error> unrecorded;  // the journal could not record the cancel
  // A refused cancel is answered to the canceller under the identity it gave.
  auto refuse = [&](const PlanError& error) {
    MissionRequestData identity;
    identity.request_id = request.request_id;
    identity.vehicle_id = request.vehicle_id;
    identity.requester = request.requester;
    sink_.publishStatus(PlanStatusData::failed(identity, error, 0.0));
    return false;
  };
  {
    std::lock_guard lock(mutex_);
    // A cancel names a vehicle, a request, or both; a fleet job's request is empty: never matches.
    auto matches = [&](const MissionRequestData& r) {
      return !r.vehicle_id.empty() && (request.vehicle_id.empty() || r.vehicle_id == request.vehicle_id) &&
             (request.request_id.empty() || r.request_id == request.request_id);
    };
    // Write-ahead: a cancel the journal cannot record is refused before anything changes (a
    // mission cancelled without its record would fly again after a restart).
    const bool matches_any =
        std::any_of(queue_.begin(), queue_.end(), [&](const auto& job) { return matches(job->request); }) ||
        std::any_of(in_flight_.begin(), in_flight_.end(), [&](const Job* job) { return matches(job->request); }) ||
        std::any_of(missions_.begin(), missions_.end(), [&](const auto& entry) { return matches(entry.second->request); });
    if (matches_any) {
      if (Status recorded = sink_.recordCancel(request); !recorded.ok()) unrecorded = recorded.error();
    }
    for (auto it = queue_.begin(); !unrecorded && it != queue_.end();) {
      if (matches((*it)->request)) {
        if ((*it)->resume) retracted.push_back((*it)->request.vehicle_id);  // its trajectory was republished
        cancelled.push_back((*it)->request);
        it = queue_.erase(it);
      } else {
        ++it;
      }
    }
    for (Job* job : in_flight_) {
      if (!unrecorded && matches(job->request)) {
        job->cancel->store(true);  // its worker answers with the cancelled status
        matched = true;
      }
    }
    for (auto it = missions_.begin(); !unrecorded && it != missions_.end();) {
      if (matches(it->second->request)) {
        ended.push_back(it->second);
        it = missions_.erase(it);
      } else {
        ++it;
      }
    }
  }
  if (unrecorded) {
    const PlanError error{PlanErrorCode::kJournalUnavailable, "service.state_dir",
                          "cancel refused: the state journal cannot record it (" + unrecorded->message +
                              "); the mission goes on, retry when the journal can write"};
    spdlog::warn("event=cancel_rejected vehicle={} request={} code={} message=\"{}\"", request.vehicle_id,
                 request.request_id, to_string(error.code), error.message);
    return refuse(error);
  }
  // Mission locks are never taken under the engine lock (the replanning loop holds a mission's
  // lock while it plans).
  for (const std::shared_ptr<Mission>& mission : ended) {
    mission->cancel->store(true);
    {
      std::lock_guard mission_lock(mission->mutex);
      mission->ended = true;
    }
    cancelled.push_back(mission->request);
    sink_.retractTrajectory(mission->request.vehicle_id);
  }
  for (const std::string& vehicle : retracted) sink_.retractTrajectory(vehicle);
  for (const MissionRequestData& r : cancelled) finish(cancelledStatus(r, "cancelled on request"));
  if (!cancelled.empty() || matched) {
    spdlog::info("event=cancel vehicle={} request={} cancelled={}", request.vehicle_id, request.request_id,
                 cancelled.size() + (matched ? 1 : 0));
    return true;
  }
  // Nothing to cancel: say so to the canceller (a finished request keeps its stored result).
  const std::string what = request.request_id.empty() ? "no request" : "no request '" + request.request_id + "'";
  const std::string whose = request.vehicle_id.empty() ? "" : " of vehicle '" + request.vehicle_id + "'";
  const PlanError error{PlanErrorCode::kInvalidArgument, request.request_id.empty() ? "vehicle_id" : "request_id",
                        "cancel refused: " + what + whose + " is queued, being planned or flying"};
  throttle_.warn("cancel_unknown:" + request.vehicle_id + ":" + request.request_id,
                 fmt::format("event=cancel_rejected vehicle={} request={} message=\"{}\"", request.vehicle_id,
                             request.request_id, error.message));
  return refuse(error);
}

std::optional<PlanError> Engine::updateObstacle(const ObstacleUpdateData& update) {
  const std::shared_ptr<WorldModel> world = this->world();
  std::optional<PlanError> problem;
  if (!update.remove) {
    problem = validateObstacleUpdate(update);
    if (!problem) problem = checkObstacleBounds(update, world->terrain(), options().obstacles);
  }
  if (!problem) problem = checkObstacleOrder(update, *world, options().obstacles);
  if (problem) {
    throttle_.warn("obstacle_rejected:" + std::to_string(update.obstacle.id) + ":" + problem->field,
                   fmt::format("event=obstacle_rejected id={} code={} field={} message=\"{}\"", update.obstacle.id,
                               to_string(problem->code), problem->field, problem->message));
    return problem;
  }
  {
    std::lock_guard lock(mutex_);  // the world in force (a reload may be replacing it)
    sink_.recordObstacle(update);
    world_->apply(update);
    replan_wake_ = true;
  }
  spdlog::debug("event=obstacle_update id={} remove={} motion={}", update.obstacle.id, update.remove,
                to_string(update.motionKind()));
  replan_cv_.notify_one();
  return std::nullopt;
}

std::optional<PlanError> Engine::updateNoFlyZone(const NoFlyZoneData& zone) {
  if (zone.remove) {
    {
      std::lock_guard lock(mutex_);  // the world in force (a reload may be replacing it)
      sink_.recordNoFlyZone(zone);
      world_->removeNoFlyZone(zone.zone_id);
      replan_wake_ = true;
    }
    spdlog::info("event=nofly_zone zone={} remove=true", zone.zone_id);
    replan_cv_.notify_one();
    return std::nullopt;
  }
  // Checked outside the engine's lock (planning workers and the replanning loop take it): the
  // work is O(n log n) in the ring's vertices, which the conversion bounded first
  // (kMaxNoFlyZoneVertices), a few milliseconds at the bound.
  const auto started = std::chrono::steady_clock::now();
  std::shared_ptr<WorldModel> checked_on = world();
  auto refuse = [&](const PlanError& problem) {
    throttle_.warn("nofly_rejected:" + zone.zone_id + ":" + problem.field,
                   fmt::format("event=nofly_rejected zone={} field={} message=\"{}\"", zone.zone_id, problem.field,
                               problem.message));
    return problem;
  };
  for (;;) {
    auto checked = placeNoFlyZone(zone, checked_on->terrain());
    if (!checked.ok()) return refuse(toPlanError(checked.error()));
    std::lock_guard lock(mutex_);
    if (world_ != checked_on) {  // a reload changed the terrain meanwhile: check on the new one
      checked_on = world_;
      continue;
    }
    // Every published zone is copied into each world on each change: their vertices together are
    // bounded too, so no update costs more than that.
    const std::size_t vertices = checked->ring_m.size() + world_->publishedNoFlyVertices(zone.zone_id);
    if (vertices > kMaxPublishedNoFlyVertices) {
      return refuse(PlanError{PlanErrorCode::kInvalidArgument, "ring",
                              "zone '" + zone.zone_id + "': the published zones in force would have " +
                                  std::to_string(vertices) + " vertices together, more than the " +
                                  std::to_string(kMaxPublishedNoFlyVertices) + " they may have; lift some first"});
    }
    sink_.recordNoFlyZone(zone);
    world_->upsertNoFlyZone(std::move(*checked));
    replan_wake_ = true;
    break;
  }
  spdlog::info("event=nofly_zone zone={} remove=false vertices={} check_s={:.4f}", zone.zone_id, zone.ring.size(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  replan_cv_.notify_one();
  return std::nullopt;
}

TrajectoryData Engine::trajectoryOf(const Mission& mission) const {
  const MissionPipeline pipeline(mission.world_model, options().pipeline);
  return pipeline.sample(mission.plan,
                         TrajectoryIdentity{mission.request.vehicle_id, mission.plan_id,
                                            mission.revision_base + mission.plan.flight->revision(), mission.request.request_id});
}

std::vector<TrajectoryData> Engine::currentTrajectories() const {
  std::vector<std::shared_ptr<Mission>> missions;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [vehicle, mission] : missions_) missions.push_back(mission);
  }
  std::vector<TrajectoryData> out;
  for (const std::shared_ptr<Mission>& mission : missions) {
    std::lock_guard mission_lock(mission->mutex);
    if (mission->ended) continue;
    const bool as_recovered = mission->recovered && mission->plan.flight->revision() == 0;
    out.push_back(as_recovered ? *mission->recovered : trajectoryOf(*mission));
  }
  return out;
}

void Engine::plan(Job& job) {
  if (job.fleet_replan) {
    replanFleetJob(job);
    return;
  }
  if (job.fleet) {
    planFleetJob(job);
    return;
  }
  if (job.resume) {
    planResumed(job);
    return;
  }
  const auto started = std::chrono::steady_clock::now();
  const MissionRequestData& r = job.request;
  if (job.cancel->load()) {
    finish(cancelledStatus(r, "cancelled before planning"));
    return;
  }
  status(r, PlanState::kPlanning);
  const EngineOptions options = this->options();
  const std::shared_ptr<WorldModel> world_model = world();
  PlanError error;
  std::shared_ptr<Mission> mission;
  // The memory guard, on the planner thread with the options in force now (a reload may have
  // changed the thread count, and with it each thread's share).
  if (auto too_large = checkRequestSize(r, *world_model, options)) {
    error = *too_large;
  } else {
    const MissionPipeline pipeline(world_model, options.pipeline);
    TerminationCondition stop;
    stop.withCancelFlag(job.cancel);
    // The collision worlds change in place when an obstacle or a zone arrives: a plan that ran
    // while one did may have found its path in one world and checked it in the next (the path then
    // "is not a valid motion"). Such a failure is no answer about the request: it is planned again
    // on the world as it is now, a bounded number of times. A plan that succeeded across a change
    // is checked by the next replanning cycle (changes_checked below).
    std::uint64_t changes_planned = world_model->version();  // the world the plan sees
    auto planned = pipeline.plan(PipelineRequest{r, std::nullopt, std::nullopt}, static_cast<double>(clock_()) * 1e-9,
                                 stop);
    for (int retry = 1; retry <= kPlansOnAChangingWorld - 1 && !planned.ok() &&
                        planned.error().code != PlanErrorCode::kCancelled && world_model->version() != changes_planned;
         ++retry) {
      spdlog::info("event=plan_retried request={} vehicle={} attempt={} reason=world_changed code={} field={}",
                   r.request_id, r.vehicle_id, retry + 1, to_string(planned.error().code), planned.error().field);
      changes_planned = world_model->version();
      planned = pipeline.plan(PipelineRequest{r, std::nullopt, std::nullopt}, static_cast<double>(clock_()) * 1e-9, stop);
    }
    if (planned.ok()) {
      mission = std::make_shared<Mission>();
      mission->request = r;
      mission->world_model = world_model;
      mission->plan = std::move(planned.value());
      mission->cancel = job.cancel;
      mission->changes_checked = changes_planned;
      logPlanned(r, mission->plan);
    } else {
      error = planned.error();
    }
  }
  const double planning_s = secondsSince(started);
  if (!mission) {
    if (error.code == PlanErrorCode::kCancelled) {
      // Where it stopped (e.g. "stopped while checking the trajectory") tells which stage heard it.
      error.message = "cancelled during planning" + (error.message.empty() ? "" : ": " + error.message);
      spdlog::info("event=plan_cancelled request={} vehicle={} field={} message=\"{}\" time_s={:.3f}", r.request_id,
                   r.vehicle_id, error.field, error.message, planning_s);
      finish(PlanStatusData::failed(r, error, planning_s));
      return;
    }
    const PlanStatusData s = PlanStatusData::failed(r, error, planning_s);
    throttle_.warn("plan_failed:" + r.vehicle_id + ":" + std::string(to_string(error.code)) + ":" + error.field,
                   fmt::format("event=plan_failed request={} vehicle={} code={} stage={} field={} message=\"{}\" "
                               "time_s={:.3f}",
                               r.request_id, r.vehicle_id, to_string(error.code), to_string(error.stage), error.field,
                               error.message, planning_s));
    finish(s);
    return;
  }
  // Registered and published under the mission's lock, so the replanning loop cannot publish
  // revision 1 before revision 0 is out. Registered under the engine's lock only when no cancel
  // or stop came first: after stop() began, a plan is answered cancelled, never succeeded; and
  // only once the journal recorded it (under the same lock, so no cancel comes between).
  std::unique_lock mission_lock(mission->mutex);
  TrajectoryData data = trajectoryOf(*mission);  // its plan id is given below
  std::shared_ptr<Mission> replaced;
  bool registered = false;
  std::optional<Error> unrecorded;
  {
    std::lock_guard lock(mutex_);
    if (!job.cancel->load() && !stopping_) {
      mission->plan_id = r.vehicle_id + "-" + (plan_id_tag_.empty() ? "" : plan_id_tag_ + "-") + std::to_string(++plan_counter_);
      data.plan_id = mission->plan_id;
      if (Status recorded = sink_.recordTrajectory(data); !recorded.ok()) {
        unrecorded = recorded.error();
      } else {
        if (auto it = missions_.find(r.vehicle_id); it != missions_.end()) replaced = it->second;
        missions_[r.vehicle_id] = mission;
        registered = true;
      }
    }
  }
  if (unrecorded) {
    // Nothing is published that the journal did not store: the vehicle's mission in force, if
    // any, flies on as it was.
    mission_lock.unlock();
    const PlanError error{PlanErrorCode::kJournalUnavailable, "service.state_dir",
                          "refused: the state journal cannot record the trajectory (" + unrecorded->message +
                              "); nothing was published, retry when the journal can write"};
    spdlog::warn("event=plan_not_journaled request={} vehicle={} plan={} message=\"{}\" time_s={:.3f}", r.request_id,
                 r.vehicle_id, data.plan_id, unrecorded->message, planning_s);
    finish(PlanStatusData::failed(r, error, planning_s));
    return;
  }
  if (!registered) {
    mission_lock.unlock();
    spdlog::info("event=plan_cancelled request={} vehicle={} time_s={:.3f}", r.request_id, r.vehicle_id, planning_s);
    finish(cancelledStatus(r, "cancelled during planning"));
    return;
  }
  if (replaced) {  // its replanning stops
    replaced->cancel->store(true);
    std::lock_guard old_lock(replaced->mutex);
    replaced->ended = true;
  }
  sink_.publishTrajectory(data);
  mission_lock.unlock();
  spdlog::info("event=plan_succeeded request={} vehicle={} plan={} duration_s={:.1f} samples={} time_s={:.3f}",
               r.request_id, r.vehicle_id, data.plan_id, mission->plan.flight->route().built.trajectory.duration_s(),
               data.samples.size(), planning_s);
  PlanStatusData succeeded;
  succeeded.request_id = r.request_id;
  succeeded.vehicle_id = r.vehicle_id;
  succeeded.state = PlanState::kSucceeded;
  succeeded.planning_time_s = planning_s;
  succeeded.requester = r.requester;
  for (const std::string& note : mission->plan.notes) {
    succeeded.message += (succeeded.message.empty() ? "" : "; ") + note;  // e.g. a fired wall-clock cap
  }
  finish(succeeded);
}

std::unique_ptr<Engine::Job> Engine::takeJobLocked() {
  if (queue_.empty()) return nullptr;
  std::unique_ptr<Job> job = std::move(queue_.front());
  queue_.pop_front();
  in_flight_.push_back(job.get());
  return job;
}

void Engine::planTaken(std::unique_ptr<Job> job) {
  plan(*job);
  std::lock_guard lock(mutex_);
  std::erase(in_flight_, job.get());
}

bool Engine::planNext() {
  std::unique_ptr<Job> job;
  {
    std::lock_guard lock(mutex_);
    job = takeJobLocked();
  }
  if (!job) return false;
  planTaken(std::move(job));
  return true;
}

std::size_t Engine::activeMissions() const {
  std::lock_guard lock(mutex_);
  return missions_.size();
}

std::size_t Engine::queueLength() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

ServiceStatusData Engine::status(const std::string& service_id) const {
  ServiceStatusData s;
  s.service_id = service_id;
  s.stamp_utc_ns = clock_();
  s.terrain_loaded = true;
  std::shared_ptr<WorldModel> world_model;
  {
    std::lock_guard lock(mutex_);
    s.vehicles = static_cast<std::uint32_t>(missions_.size());
    s.queue_length = static_cast<std::uint32_t>(queue_.size());
    world_model = world_;
  }
  s.terrain_name = world_model->terrainName();
  s.obstacles = static_cast<std::uint32_t>(world_model->obstacleCount());
  s.replans = static_cast<std::uint32_t>(replans_.load());
  s.audits = static_cast<std::uint32_t>(audit_counters_->audits.load());
  s.audit_failures = static_cast<std::uint32_t>(audit_counters_->failures.load());
  return s;
}

}  // namespace skyroute
