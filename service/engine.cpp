#include "service/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>


namespace skyroute {

struct Engine::Job {
  MissionRequestData request;                // a mission (request.vehicle_id set), or
  std::optional<FleetRequestData> fleet;     // a fleet (request left empty)
  std::shared_ptr<std::atomic<bool>> cancel = std::make_shared<std::atomic<bool>>(false);
};

struct Engine::Mission {
  MissionRequestData request;
  std::string plan_id;
  MissionPlan plan;                          // order, points and the flight being replanned
  std::shared_ptr<std::atomic<bool>> cancel;
  std::mutex mutex;                          // the flight and `ended`
  bool ended = false;                        // cancelled or replaced: no more revisions
};

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

Result<std::unique_ptr<Engine>> Engine::create(std::shared_ptr<WorldModel> world, const EngineOptions& options,
                                               EngineSink& sink, Clock clock) {
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "no world model");
  if (options.planning_threads < 1) {
    return make_error(ErrorCode::kInvalidArgument, "planning.threads", "must be at least 1");
  }
  if (auto bad = validatePipelineOptions(options.pipeline)) {
    return make_error(ErrorCode::kInvalidArgument, bad->field, bad->message);
  }
  if (!clock) clock = utcNowNs;
  return std::unique_ptr<Engine>(new Engine(std::move(world), options, sink, std::move(clock)));
}

Engine::Engine(std::shared_ptr<WorldModel> world, const EngineOptions& options, EngineSink& sink, Clock clock)
    : world_(std::move(world)), sink_(sink), clock_(std::move(clock)), options_(options) {}

Engine::~Engine() { stop(); }

void Engine::setOptions(const EngineOptions& options) {
  std::lock_guard lock(mutex_);
  options_ = options;
}

EngineOptions Engine::options() const {
  std::lock_guard lock(mutex_);
  return options_;
}

void Engine::status(const MissionRequestData& request, PlanState state, double planning_time_s,
                    std::string message) {
  PlanStatusData s;
  s.request_id = request.request_id;
  s.vehicle_id = request.vehicle_id;
  s.state = state;
  s.planning_time_s = planning_time_s;
  s.message = std::move(message);
  sink_.publishStatus(s);
}

std::optional<PlanError> Engine::enqueue(std::unique_ptr<Job> job, const Validator& validate) {
  std::lock_guard lock(mutex_);
  std::optional<PlanError> problem = validate(options_);
  if (!problem && stopping_) problem = PlanError{PlanErrorCode::kBusy, "", "the service is shutting down"};
  if (!problem && queue_.size() >= options_.max_queue) {
    problem = PlanError{PlanErrorCode::kBusy, "",
                        "the planning queue is full (" + std::to_string(options_.max_queue) + " requests); retry later"};
  }
  if (!problem) queue_.push_back(std::move(job));
  return problem;
}

std::optional<PlanError> Engine::submit(MissionRequestData request) {
  auto job = std::make_unique<Job>();
  job->request = request;
  const std::optional<PlanError> problem = enqueue(std::move(job), [&](const EngineOptions& o) {
    if (auto bad = validateMissionRequest(request, o.pipeline.bounds)) return bad;
    return request.planner.empty() ? std::nullopt : findRoutePlanner(request.planner, nullptr);
  });
  if (problem) {
    spdlog::warn("event=request_rejected request={} vehicle={} code={} field={} message=\"{}\"", request.request_id,
                 request.vehicle_id, to_string(problem->code), problem->field, problem->message);
    sink_.publishStatus(PlanStatusData::failed(request, *problem, 0.0));
    return problem;
  }
  spdlog::info("event=request_accepted request={} vehicle={} points={}", request.request_id, request.vehicle_id,
               request.points.size());
  status(request, PlanState::kAccepted);
  work_cv_.notify_one();
  return std::nullopt;
}

namespace {

FleetStatusData fleetStatus(const std::string& request_id, PlanState state) {
  FleetStatusData s;
  s.request_id = request_id;
  s.state = state;
  return s;
}

FleetStatusData fleetFailed(const std::string& request_id, const PlanError& error) {
  FleetStatusData s = fleetStatus(request_id, error.code == PlanErrorCode::kCancelled ? PlanState::kCancelled
                                                                                         : PlanState::kFailed);
  s.error_code = error.code;
  s.field = error.field;
  s.message = error.describe();
  return s;
}

}  // namespace

std::optional<PlanError> Engine::submitFleet(FleetRequestData request) {
  auto job = std::make_unique<Job>();
  job->fleet = request;
  const std::optional<PlanError> problem = enqueue(
      std::move(job), [&](const EngineOptions& o) { return validateFleetRequest(request, o.pipeline.fleet); });
  if (problem) {
    spdlog::warn("event=fleet_rejected request={} code={} field={} message=\"{}\"", request.request_id,
                 to_string(problem->code), problem->field, problem->message);
    sink_.publishFleetStatus(fleetFailed(request.request_id, *problem));
    return problem;
  }
  spdlog::info("event=fleet_accepted request={} vehicles={} tasks={}", request.request_id, request.vehicle_ids.size(),
               request.tasks.size());
  sink_.publishFleetStatus(fleetStatus(request.request_id, PlanState::kAccepted));
  work_cv_.notify_one();
  return std::nullopt;
}

void Engine::planFleetJob(Job& job) {
  const FleetRequestData& r = *job.fleet;
  if (job.cancel->load()) {
    sink_.publishFleetStatus(fleetFailed(r.request_id, PlanError{PlanErrorCode::kCancelled, "", "cancelled before planning"}));
    return;
  }
  sink_.publishFleetStatus(fleetStatus(r.request_id, PlanState::kPlanning));
  const MissionPipeline pipeline(world_, options().pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  const FleetPlanOutput out = pipeline.planFleet(r, clock_(), stop);
  if (!out.ok()) {
    spdlog::warn("event=fleet_failed request={} code={} field={} message=\"{}\" time_s={:.3f}", r.request_id,
                 to_string(out.status.error_code), out.status.field, out.status.message, out.status.planning_time_s);
    sink_.publishFleetStatus(out.status);
    return;
  }
  // A vehicle's own mission ends: the fleet's trajectory replaces it (and is not replanned).
  std::vector<std::shared_ptr<Mission>> replaced;
  {
    std::lock_guard lock(mutex_);
    for (const std::string& vehicle : r.vehicle_ids) {
      if (auto it = missions_.find(vehicle); it != missions_.end()) {
        replaced.push_back(it->second);
        missions_.erase(it);
      }
    }
  }
  for (const std::shared_ptr<Mission>& m : replaced) {
    m->cancel->store(true);
    std::lock_guard old_lock(m->mutex);
    m->ended = true;
  }
  for (const TrajectoryData& t : out.trajectories) sink_.publishTrajectory(t);
  spdlog::info("event=fleet_succeeded request={} vehicles={} makespan_steps={} makespan_s={:.1f} separation_m={:.0f} "
               "repairs={} time_s={:.3f}",
               r.request_id, r.vehicle_ids.size(), out.status.makespan_steps, out.status.makespan_s,
               out.status.achieved_separation_m, out.status.separation_repairs, out.status.planning_time_s);
  sink_.publishFleetStatus(out.status);
}

bool Engine::cancel(const CancelRequestData& request) {
  std::vector<MissionRequestData> cancelled;
  std::shared_ptr<Mission> ended;
  bool matched = false;
  {
    std::lock_guard lock(mutex_);
    auto matches = [&](const MissionRequestData& r) {  // a fleet job's request is empty: never matches
      return !r.vehicle_id.empty() && r.vehicle_id == request.vehicle_id &&
             (request.request_id.empty() || r.request_id == request.request_id);
    };
    for (auto it = queue_.begin(); it != queue_.end();) {
      if (matches((*it)->request)) {
        cancelled.push_back((*it)->request);
        it = queue_.erase(it);
      } else {
        ++it;
      }
    }
    for (Job* job : in_flight_) {
      if (matches(job->request)) {
        job->cancel->store(true);  // its worker answers with the cancelled status
        matched = true;
      }
    }
    if (auto it = missions_.find(request.vehicle_id); it != missions_.end() && matches(it->second->request)) {
      ended = it->second;
      missions_.erase(it);
    }
  }
  // Mission locks are never taken under the engine lock (the replanning loop holds a mission's
  // lock while it plans).
  if (ended) {
    ended->cancel->store(true);
    {
      std::lock_guard mission_lock(ended->mutex);
      ended->ended = true;
    }
    cancelled.push_back(ended->request);
    sink_.retractTrajectory(request.vehicle_id);
  }
  for (const MissionRequestData& r : cancelled) {
    PlanStatusData s = PlanStatusData::failed(r, PlanError{PlanErrorCode::kCancelled, "", "cancelled on request"}, 0.0);
    s.state = PlanState::kCancelled;
    sink_.publishStatus(s);
  }
  if (!cancelled.empty() || matched) {
    spdlog::info("event=cancel vehicle={} request={} cancelled={}", request.vehicle_id, request.request_id,
                 cancelled.size() + (matched ? 1 : 0));
  }
  return matched || !cancelled.empty();
}

std::optional<PlanError> Engine::updateObstacle(const ObstacleUpdateData& update) {
  if (!update.remove) {
    if (auto problem = validateObstacleUpdate(update)) {
      spdlog::warn("event=obstacle_rejected id={} field={} message=\"{}\"", update.obstacle.id, problem->field,
                   problem->message);
      return problem;
    }
  }
  world_->apply(update);
  spdlog::debug("event=obstacle_update id={} remove={} motion={}", update.obstacle.id, update.remove,
                to_string(update.motionKind()));
  {
    std::lock_guard lock(mutex_);
    replan_wake_ = true;
  }
  replan_cv_.notify_one();
  return std::nullopt;
}

Result<TrajectoryData, PlanError> Engine::trajectoryOf(const Mission& mission) const {
  const MissionPipeline pipeline(world_, options().pipeline);
  return pipeline.sample(mission.plan, TrajectoryIdentity{mission.request.vehicle_id, mission.plan_id,
                                                          mission.plan.flight->revision(), mission.request.request_id});
}

void Engine::plan(Job& job) {
  if (job.fleet) {
    planFleetJob(job);
    return;
  }
  const auto started = std::chrono::steady_clock::now();
  const MissionRequestData& r = job.request;
  if (job.cancel->load()) {
    PlanStatusData s = PlanStatusData::failed(r, PlanError{PlanErrorCode::kCancelled, "", "cancelled before planning"}, 0.0);
    s.state = PlanState::kCancelled;
    sink_.publishStatus(s);
    return;
  }
  status(r, PlanState::kPlanning);
  const MissionPipeline pipeline(world_, options().pipeline);
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  const double now_s = static_cast<double>(clock_()) * 1e-9;
  auto planned = pipeline.plan(PipelineRequest{r, std::nullopt, std::nullopt}, now_s, stop);
  std::shared_ptr<Mission> mission;
  PlanError error;
  if (planned.ok()) {
    mission = std::make_shared<Mission>();
    mission->request = r;
    mission->plan = std::move(planned.value());
    mission->cancel = job.cancel;
    const OrderedMission& m = mission->plan.mission;
    if (!m.ordering.fallback_reason.empty()) {
      spdlog::info("event=order_fallback request={} reason=\"{}\"", r.request_id, m.ordering.fallback_reason);
    }
    spdlog::info("event=order request={} method={} cost_m={:.0f} expansions={} time_ms={:.1f} planner={}",
                 r.request_id, m.ordering.method, m.ordering.cost_m, m.ordering.expansions, m.ordering.time_ms,
                 m.planner->name);
    for (const std::string& note : mission->plan.notes) {
      spdlog::warn("event=budget_capped request={} vehicle={} note=\"{}\"", r.request_id, r.vehicle_id, note);
    }
  } else {
    error = planned.error();
  }
  const double planning_s = secondsSince(started);
  if (mission && job.cancel->load()) {
    mission.reset();
    error = PlanError{PlanErrorCode::kCancelled, "", "cancelled during planning"};
  }
  if (!mission) {
    if (error.code == PlanErrorCode::kCancelled && job.cancel->load()) error.message = "cancelled during planning";
    PlanStatusData s = PlanStatusData::failed(r, error, planning_s);
    if (error.code == PlanErrorCode::kCancelled) s.state = PlanState::kCancelled;
    spdlog::warn("event=plan_failed request={} vehicle={} code={} stage={} field={} message=\"{}\" time_s={:.3f}",
                 r.request_id, r.vehicle_id, to_string(error.code), to_string(error.stage), error.field, error.message,
                 planning_s);
    sink_.publishStatus(s);
    return;
  }
  // Registered and published under the mission's lock, so the replanning loop cannot publish
  // revision 1 before revision 0 is out.
  std::unique_lock mission_lock(mission->mutex);
  std::shared_ptr<Mission> replaced;
  {
    std::lock_guard lock(mutex_);
    mission->plan_id = r.vehicle_id + "-" + std::to_string(++plan_counter_);
    if (auto it = missions_.find(r.vehicle_id); it != missions_.end()) replaced = it->second;
    missions_[r.vehicle_id] = mission;
  }
  if (replaced) {  // its replanning stops
    replaced->cancel->store(true);
    std::lock_guard old_lock(replaced->mutex);
    replaced->ended = true;
  }
  auto data = trajectoryOf(*mission);
  if (!data.ok()) {
    mission->ended = true;
    mission_lock.unlock();
    {
      std::lock_guard lock(mutex_);
      if (auto it = missions_.find(r.vehicle_id); it != missions_.end() && it->second == mission) missions_.erase(it);
    }
    sink_.publishStatus(PlanStatusData::failed(r, data.error(), planning_s));
    return;
  }
  sink_.publishTrajectory(*data);
  mission_lock.unlock();
  std::string notes;
  for (const std::string& note : mission->plan.notes) notes += (notes.empty() ? "" : "; ") + note;
  spdlog::info("event=plan_succeeded request={} vehicle={} plan={} duration_s={:.1f} samples={} time_s={:.3f}",
               r.request_id, r.vehicle_id, data->plan_id, mission->plan.flight->route().built.trajectory.duration_s(),
               data->samples.size(), planning_s);
  status(r, PlanState::kSucceeded, planning_s, notes);
}

bool Engine::planNext() {
  std::unique_ptr<Job> job;
  {
    std::lock_guard lock(mutex_);
    if (queue_.empty()) return false;
    job = std::move(queue_.front());
    queue_.pop_front();
    in_flight_.push_back(job.get());
  }
  plan(*job);
  std::lock_guard lock(mutex_);
  std::erase(in_flight_, job.get());
  return true;
}

std::size_t Engine::replanCycle() {
  const double now_s = static_cast<double>(clock_()) * 1e-9;
  world_->expire(now_s);
  std::vector<std::shared_ptr<Mission>> missions;
  {
    std::lock_guard lock(mutex_);
    if (!options_.replanning) return 0;
    for (const auto& [vehicle, mission] : missions_) missions.push_back(mission);
  }
  std::size_t published = 0;
  for (const std::shared_ptr<Mission>& mission : missions) {
    if (stopping_) break;
    std::unique_lock mission_lock(mission->mutex);
    if (mission->ended) continue;
    if (mission->plan.flight->finished(now_s)) {
      mission->ended = true;
      mission_lock.unlock();
      std::lock_guard lock(mutex_);
      if (auto it = missions_.find(mission->request.vehicle_id); it != missions_.end() && it->second == mission) {
        missions_.erase(it);
        spdlog::info("event=mission_completed request={} vehicle={} plan={}", mission->request.request_id,
                     mission->request.vehicle_id, mission->plan_id);
      }
      continue;
    }
    const ReplanStep step = mission->plan.flight->step(now_s);
    if (step.replanned) {
      auto data = trajectoryOf(*mission);
      if (!data.ok()) {
        spdlog::warn("event=replan_failed request={} vehicle={} field={} message=\"{}\"", mission->request.request_id,
                     mission->request.vehicle_id, data.error().field, data.error().message);
        continue;
      }
      sink_.publishTrajectory(*data);
      mission_lock.unlock();
      ++replans_;
      ++published;
      spdlog::info("event=replanned request={} vehicle={} plan={} revision={} latency_ms={:.1f}",
                   mission->request.request_id, mission->request.vehicle_id, mission->plan_id, data->revision,
                   step.latency_ms);
      status(mission->request, PlanState::kReplanned, step.latency_ms * 1e-3);
    } else if (step.failure) {
      spdlog::warn("event=replan_failed request={} vehicle={} field={} message=\"{}\"", mission->request.request_id,
                   mission->request.vehicle_id, step.failure->field, step.failure->message);
    }
  }
  return published;
}

void Engine::workerLoop() {
  for (;;) {
    std::unique_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      work_cv_.wait(lock, [&] { return stopping_.load() || !queue_.empty(); });
      if (stopping_) return;
      job = std::move(queue_.front());
      queue_.pop_front();
      in_flight_.push_back(job.get());
    }
    plan(*job);
    std::lock_guard lock(mutex_);
    std::erase(in_flight_, job.get());
  }
}

void Engine::replanLoop() {
  auto next = std::chrono::steady_clock::now();
  while (!stopping_) {
    replanCycle();
    double period_s = 0.1;
    {
      std::lock_guard lock(mutex_);
      period_s = options_.pipeline.replan.period_s;
    }
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(period_s));
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // a long cycle: start the next at once rather than catch up
    std::unique_lock lock(mutex_);
    replan_cv_.wait_until(lock, next, [&] { return stopping_.load() || replan_wake_; });
    replan_wake_ = false;
  }
}

void Engine::start() {
  if (running_.exchange(true)) return;
  stopping_ = false;
  const int threads = options().planning_threads;
  for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { workerLoop(); });
  replanner_ = std::thread([this] { replanLoop(); });
  spdlog::info("event=engine_started planning_threads={}", threads);
}

void Engine::stop() {
  std::vector<MissionRequestData> dropped;
  std::vector<std::string> dropped_fleets;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !running_) return;
    stopping_ = true;
    for (Job* job : in_flight_) job->cancel->store(true);
    for (const auto& [vehicle, mission] : missions_) mission->cancel->store(true);
    for (const auto& job : queue_) {
      if (job->fleet) {
        dropped_fleets.push_back(job->fleet->request_id);
      } else {
        dropped.push_back(job->request);
      }
    }
    queue_.clear();
  }
  work_cv_.notify_all();
  replan_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
  if (replanner_.joinable()) replanner_.join();
  for (const MissionRequestData& r : dropped) {
    PlanStatusData s = PlanStatusData::failed(r, PlanError{PlanErrorCode::kCancelled, "", "the service stopped"}, 0.0);
    s.state = PlanState::kCancelled;
    sink_.publishStatus(s);
  }
  for (const std::string& id : dropped_fleets) {
    sink_.publishFleetStatus(fleetFailed(id, PlanError{PlanErrorCode::kCancelled, "", "the service stopped"}));
  }
  if (running_.exchange(false)) spdlog::info("event=engine_stopped");
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
  s.terrain_name = world_->terrainName();
  {
    std::lock_guard lock(mutex_);
    s.vehicles = static_cast<std::uint32_t>(missions_.size());
    s.queue_length = static_cast<std::uint32_t>(queue_.size());
  }
  s.replans = static_cast<std::uint32_t>(replans_.load());
  return s;
}

}  // namespace skyroute
