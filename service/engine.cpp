#include "service/engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "service/trajectory_data.hpp"

namespace skyroute {

struct Engine::Job {
  MissionRequestData request;                // a mission (request.vehicle_id set), or
  std::optional<FleetRequestData> fleet;     // a fleet (request left empty)
  std::shared_ptr<std::atomic<bool>> cancel = std::make_shared<std::atomic<bool>>(false);
};

struct Engine::Mission {
  MissionRequestData request;
  std::string plan_id;
  std::vector<int> order;                    // request point indices in visiting order
  std::vector<Eigen::Vector3d> ordered_m;    // the points in that order, ENU
  double sample_dt_s = 0.2;                  // of the published trajectories
  std::shared_ptr<std::atomic<bool>> cancel;
  std::mutex mutex;                          // the replanner and `ended`
  std::unique_ptr<FlightReplanner> replanner;
  bool ended = false;                        // cancelled or replaced: no more revisions
};

namespace {

double secondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Request point index -> the request's field name.
std::string pointName(int index, int count) {
  if (index == 0) return "begin";
  if (index == count - 1) return "end";
  return "points[" + std::to_string(index - 1) + "]";
}

// The trajectory stage names its limits after VehicleLimits; the request after the IDL.
std::string requestLimitField(const std::string& field) {
  if (field == "limits.max_climb_mps") return "limits.max_climb_rate_mps";
  if (field == "limits.max_descent_mps") return "limits.max_descent_rate_mps";
  return field;
}

// Route errors name ordered points ("points[k]") and legs ("legs[k]"); replies name the request's.
PlanError requestError(const Error& e, const std::vector<int>& order) {
  PlanError out = toPlanError(e);
  const int count = static_cast<int>(order.size());
  auto index = [&](const std::string& prefix) -> std::optional<int> {
    if (e.field.rfind(prefix, 0) != 0) return std::nullopt;
    try {
      const int k = std::stoi(e.field.substr(prefix.size()));
      if (k >= 0 && k < count) return k;
    } catch (const std::exception&) {
    }
    return std::nullopt;
  };
  if (auto k = index("points[")) {
    out.field = pointName(order[*k], count);
  } else if (auto leg = index("legs[")) {
    if (*leg + 1 < count) {
      out.message += " (the leg from " + pointName(order[*leg], count) + " to " + pointName(order[*leg + 1], count) + ")";
      out.field = pointName(order[*leg + 1], count);
    }
  }
  return out;
}

}  // namespace

Result<std::unique_ptr<Engine>> Engine::create(std::shared_ptr<WorldModel> world, const EngineOptions& options,
                                               EngineSink& sink, Clock clock) {
  if (!world) return make_error(ErrorCode::kInvalidArgument, "world", "no world model");
  if (options.planning_threads < 1) {
    return make_error(ErrorCode::kInvalidArgument, "planning_threads", "must be at least 1");
  }
  if (!(options.sample_dt_s > 0.0)) return make_error(ErrorCode::kInvalidArgument, "sample_dt_s", "must be positive");
  if (!(options.replan.period_s > 0.0)) return make_error(ErrorCode::kInvalidArgument, "replan.period_s", "must be positive");
  const auto& planners = options.bounds.planners;
  if (std::find(planners.begin(), planners.end(), options.default_planner) == planners.end()) {
    return make_error(ErrorCode::kInvalidArgument, "default_planner",
                      "'" + options.default_planner + "' is not one of the planners the engine knows");
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

void Engine::status(const MissionRequestData& request, PlanState state, double planning_time_s) {
  PlanStatusData s;
  s.request_id = request.request_id;
  s.vehicle_id = request.vehicle_id;
  s.state = state;
  s.planning_time_s = planning_time_s;
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
  const std::optional<PlanError> problem = enqueue(
      std::move(job), [&](const EngineOptions& o) { return validateMissionRequest(request, o.bounds); });
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
      std::move(job), [&](const EngineOptions& o) { return validateFleetRequest(request, o.fleet); });
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
  const EngineOptions options = this->options();
  FleetMissionOptions fleet = options.fleet;
  fleet.sample_dt_s = options.sample_dt_s;
  fleet.route.trajectory = options.replan.route.trajectory;
  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  const FleetPlanOutput out = planFleetMission(r, *world_, fleet, clock_(), stop);
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

std::shared_ptr<Engine::Mission> Engine::planMission(const Job& job, const EngineOptions& options, PlanError& error) {
  const MissionRequestData& r = job.request;
  const int count = static_cast<int>(r.points.size()) + 2;
  std::vector<Eigen::Vector3d> points;
  auto toEnu = [&](const MissionPointData& p) {
    return p.frame == MissionPointData::Frame::kWgs84 ? world_->frame().toEnu(p.geo) : p.enu_m;
  };
  points.push_back(toEnu(r.begin));
  for (const MissionPointData& p : r.points) points.push_back(toEnu(p));
  points.push_back(toEnu(r.end));

  const std::string planner = r.planner.empty() ? options.default_planner : r.planner;
  const std::optional<GridGlobalPlanner> grid_planner = parseGridGlobalPlanner(planner);
  if (planner != kDefaultPlanner && !grid_planner) {
    error = PlanError{PlanErrorCode::kUnknownPlanner, "planner", "planner '" + planner + "' is not available here"};
    return nullptr;
  }
  auto world = world_->worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
  if (!world.ok()) {
    error = PlanError{PlanErrorCode::kLimitsOutOfRange, world.error().field, world.error().message};
    return nullptr;
  }
  const VehicleLimits limits = toVehicleLimits(r.limits);
  if (Status ok = limits.validate(); !ok.ok()) {
    error = PlanError{PlanErrorCode::kLimitsOutOfRange, requestLimitField(ok.error().field), ok.error().message};
    return nullptr;
  }
  const double now_s = static_cast<double>(clock_()) * 1e-9;
  ObstacleSnapshot snapshot;
  snapshot.time_s = now_s;
  for (int i = 0; i < count; ++i) {
    if (Status ok = checkRoutePoint(**world, points[i], pointName(i, count), snapshot); !ok.ok()) {
      error = toPlanError(ok.error());
      return nullptr;
    }
  }

  TerminationCondition stop;
  stop.withCancelFlag(job.cancel);
  auto order = orderMissionPoints(world_->terrain(), points, r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m,
                                  r.fixed_order, options.order, stop);
  if (!order.ok()) {
    error = toPlanError(order.error());
    return nullptr;
  }
  if (!order->fallback_reason.empty()) {
    spdlog::info("event=order_fallback request={} reason=\"{}\"", r.request_id, order->fallback_reason);
  }
  auto mission = std::make_shared<Mission>();
  mission->request = r;
  mission->order = order->order;
  mission->cancel = job.cancel;
  mission->sample_dt_s = options.sample_dt_s;
  for (int index : mission->order) mission->ordered_m.push_back(points[index]);

  ReplanOptions replan = options.replan;
  replan.route.seed = options.seed;
  replan.cancel = job.cancel;
  Result<std::unique_ptr<FlightReplanner>> replanner = make_error(ErrorCode::kInternal, "planner", "not run");
  if (grid_planner) {
    // HAB-PP finds each leg's path on the flight band; the trajectory stage is the same.
    TerminationCondition leg_stop = TerminationCondition::after(
        std::chrono::nanoseconds(static_cast<std::int64_t>(options.grid_leg_budget_s * 1e9)));
    leg_stop.withCancelFlag(job.cancel);
    auto route = planGridRoutePaths(*world, mission->ordered_m, *grid_planner, options.grid_legs, options.seed,
                                    leg_stop, snapshot);
    if (route.ok()) {
      RouteOptions build = replan.route;
      build.trajectory_start_world_s = now_s;
      build.moving_check_horizon_s = replan.horizon_s;
      if (Status built = buildRouteTrajectory(*world, mission->ordered_m, limits, build, *route); !built.ok()) {
        replanner = built.error();
      } else {
        replanner = FlightReplanner::startWithRoute(*world, mission->ordered_m, limits, replan, now_s,
                                                    std::move(route.value()));
      }
    } else {
      replanner = route.error();
    }
  } else {
    replanner = FlightReplanner::start(*world, mission->ordered_m, limits, replan, now_s);
  }
  if (!replanner.ok()) {
    error = requestError(replanner.error(), mission->order);
    return nullptr;
  }
  mission->replanner = std::move(*replanner);
  spdlog::info("event=order request={} method={} cost_m={:.0f} expansions={} time_ms={:.1f} planner={}", r.request_id,
               order->method, order->cost_m, order->expansions, order->time_ms, planner);
  return mission;
}

TrajectoryData Engine::trajectoryOf(const Mission& mission) const {
  const FlightReplanner& replanner = *mission.replanner;
  const double start_s = replanner.trajectoryStartWorldS();
  TrajectoryIdentity identity{mission.request.vehicle_id, mission.plan_id, replanner.revision(),
                              mission.request.request_id};
  TrajectoryData data = toTrajectoryData(replanner.route().built.trajectory, world_->frame(), mission.sample_dt_s,
                                         static_cast<std::int64_t>(std::llround(start_s * 1e9)), identity);
  for (int index : mission.order) data.visiting_order.push_back(static_cast<std::uint32_t>(index));
  // The route's points: the first is where this revision starts (the begin point, or where the
  // vehicle takes the new trajectory over); the others are the points still to reach, copied
  // from the ordered points. A revision's first leg continues the leg it interrupted.
  const std::vector<Eigen::Vector3d> remaining = replanner.remainingPoints(start_s);
  std::vector<int> route_ids;
  for (const Eigen::Vector3d& p : remaining) {
    int id = mission.order.back();
    for (std::size_t k = 0; k < mission.ordered_m.size(); ++k) {
      if (mission.ordered_m[k] == p) id = mission.order[k];
    }
    route_ids.push_back(id);
  }
  int previous = mission.order.front();
  if (!route_ids.empty()) {
    const auto at = std::find(mission.order.begin(), mission.order.end(), route_ids.front());
    if (at != mission.order.begin() && at != mission.order.end()) previous = *(at - 1);
  }
  route_ids.insert(route_ids.begin(), previous);
  for (const RouteLeg& leg : replanner.route().legs) {
    if (leg.to_point >= route_ids.size()) break;
    data.legs.push_back(LegBoundaryData{static_cast<std::uint32_t>(route_ids[leg.from_point]),
                                        static_cast<std::uint32_t>(route_ids[leg.to_point]), leg.start_s, leg.end_s});
  }
  return data;
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
  const EngineOptions options = this->options();
  PlanError error;
  std::shared_ptr<Mission> mission = planMission(job, options, error);
  const double planning_s = secondsSince(started);
  if (mission && job.cancel->load()) {
    mission.reset();
    error = PlanError{PlanErrorCode::kCancelled, "", "cancelled during planning"};
  }
  if (!mission) {
    if (error.code == PlanErrorCode::kCancelled && job.cancel->load()) error.message = "cancelled during planning";
    PlanStatusData s = PlanStatusData::failed(r, error, planning_s);
    if (error.code == PlanErrorCode::kCancelled) s.state = PlanState::kCancelled;
    spdlog::warn("event=plan_failed request={} vehicle={} code={} field={} message=\"{}\" time_s={:.3f}", r.request_id,
                 r.vehicle_id, to_string(error.code), error.field, error.message, planning_s);
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
  const TrajectoryData data = trajectoryOf(*mission);
  sink_.publishTrajectory(data);
  mission_lock.unlock();
  spdlog::info("event=plan_succeeded request={} vehicle={} plan={} duration_s={:.1f} samples={} time_s={:.3f}",
               r.request_id, r.vehicle_id, data.plan_id, mission->replanner->route().built.trajectory.duration_s(),
               data.samples.size(), planning_s);
  status(r, PlanState::kSucceeded, planning_s);
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
    if (mission->replanner->finished(now_s)) {
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
    const ReplanStep step = mission->replanner->step(now_s);
    if (step.replanned) {
      const TrajectoryData data = trajectoryOf(*mission);
      sink_.publishTrajectory(data);
      mission_lock.unlock();
      ++replans_;
      ++published;
      spdlog::info("event=replanned request={} vehicle={} plan={} revision={} latency_ms={:.1f}",
                   mission->request.request_id, mission->request.vehicle_id, mission->plan_id, data.revision,
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
      period_s = options_.replan.period_s;
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
