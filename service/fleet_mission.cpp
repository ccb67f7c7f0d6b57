#include "service/fleet_mission.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include <spdlog/spdlog.h>

#include "planning/fleet/fleet_planner.hpp"
#include "service/fleet_vehicle_route.hpp"
#include "service/mission_point_check.hpp"
#include "service/request_footprint.hpp"
#include "service/text_bounds.hpp"
#include "service/trajectory_data.hpp"
#include "terrain/grid_from_terrain.hpp"

namespace skyroute {

namespace {

std::string indexed(const char* name, std::size_t i) { return indexedField(name, i); }

PlanError fail(PlanErrorCode code, std::string field, std::string message) {
  return PlanError{code, std::move(field), std::move(message)};
}

std::optional<PlanError> checkPoint(const MissionPointData& p, const std::string& field) {
  if (p.frame == MissionPointData::Frame::kWgs84) {
    if (!std::isfinite(p.geo.lat_deg) || std::abs(p.geo.lat_deg) > 90.0)
      return fail(PlanErrorCode::kInvalidArgument, field + ".lat_deg", "must be a latitude in [-90, 90]");
    if (!std::isfinite(p.geo.lon_deg) || std::abs(p.geo.lon_deg) > 180.0)
      return fail(PlanErrorCode::kInvalidArgument, field + ".lon_deg", "must be a longitude in [-180, 180]");
    if (!std::isfinite(p.geo.alt_amsl_m))
      return fail(PlanErrorCode::kInvalidArgument, field + ".alt_amsl_m", "is not a finite number");
  } else if (!p.enu_m.allFinite()) {
    return fail(PlanErrorCode::kInvalidArgument, field + ".enu_m", "is not a finite position");
  }
  return std::nullopt;
}

// GMTPA names items "vehicle <id>" / "task <id>" (optionally with a suffix); the ids are the
// request's field names, so the reply names "begins[i]" or "tasks[j]".
std::string requestField(const std::string& field) {
  std::string rest = field;
  for (const char* prefix : {"vehicle ", "task "}) {
    if (rest.rfind(prefix, 0) == 0) rest = rest.substr(std::string(prefix).size());
  }
  if (const auto space = rest.find(' '); space != std::string::npos) rest = rest.substr(0, space);
  return rest;
}

}  // namespace

namespace {

// Bound of |dp/dtau| over tau in [0, 1] for one axis: the derivative (degree 6) in Bernstein form;
// a polynomial lies within the hull of its Bernstein coefficients.
double derivativeBoundTau(const Polynomial7& p) {
  constexpr int kDegree = Polynomial7::kDegree - 1;
  const auto& c = p.coefficients();
  double power[kDegree + 1];
  for (int m = 0; m <= kDegree; ++m) power[m] = (m + 1) * c[static_cast<std::size_t>(m + 1)];
  auto binomial = [](int n, int k) {
    double b = 1.0;
    for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
    return b;
  };
  double bound = 0.0;
  for (int i = 0; i <= kDegree; ++i) {
    double b = 0.0;
    for (int m = 0; m <= i; ++m) b += binomial(i, m) / binomial(kDegree, m) * power[m];
    bound = std::max(bound, std::abs(b));
  }
  return bound;
}

double segmentSpeedBound(const Segment& segment) {
  if (!(segment.duration_s > 0.0)) return 0.0;
  double sum = 0.0;
  for (const Polynomial7& axis : segment.axes) {
    const double b = derivativeBoundTau(axis);
    sum += b * b;
  }
  return std::sqrt(sum) / segment.duration_s;
}

// The largest of `bounds` (one per segment) over the segments overlapping [from_s, to_s].
double boundOver(const Trajectory& t, const std::vector<double>& bounds, double from_s, double to_s) {
  const double lo = std::max(from_s, 0.0);
  const double hi = std::min(to_s, t.duration_s());
  if (t.empty() || hi < lo) return 0.0;  // holding still before the start or after the end
  const std::vector<double>& knots = t.knotTimes();
  const auto after = std::upper_bound(knots.begin(), knots.end(), lo);
  // One segment earlier than needed when lo sits on a knot: a larger bound is still a bound.
  std::size_t s = after == knots.begin() ? 0 : static_cast<std::size_t>(after - knots.begin()) - 1;
  if (s > 0) --s;
  double bound = 0.0;
  for (; s < bounds.size() && knots[s] <= hi; ++s) bound = std::max(bound, bounds[s]);
  return bound;
}

// Positions sampled once per vehicle on its own clock; a delay of whole samples is an index shift.
class SeparationChecker {
 public:
  SeparationChecker(const std::vector<Trajectory>& flown, const SeparationCheckOptions& options)
      : flown_(flown), o_(options), samples_(flown.size()), bounds_(flown.size()), shift_(flown.size(), 0),
        offset_s_(flown.size(), 0.0) {
    for (std::size_t i = 0; i < flown.size(); ++i) {
      const double duration = flown[i].duration_s();
      const long n = static_cast<long>(std::ceil(duration / o_.sample_dt_s)) + 1;
      samples_[i].reserve(static_cast<std::size_t>(n));
      for (long k = 0; k < n; ++k) {
        samples_[i].push_back(flown[i].evaluate(std::min(k * o_.sample_dt_s, duration), Derivative::kPosition));
      }
      for (const Segment& segment : flown[i].segments()) bounds_[i].push_back(segmentSpeedBound(segment));
    }
  }

  // Delay of vehicle i: whole samples use the cached positions, any other delay evaluates.
  void setDelay(std::size_t i, double delay_s) {
    shift_[i] = std::lround(delay_s / o_.sample_dt_s);
    offset_s_[i] = delay_s - static_cast<double>(shift_[i]) * o_.sample_dt_s;
  }
  void setShift(std::size_t i, long samples) {
    shift_[i] = samples;
    offset_s_[i] = 0.0;
  }
  long shift(std::size_t i) const { return shift_[i]; }
  double delay(std::size_t i) const { return static_cast<double>(shift_[i]) * o_.sample_dt_s + offset_s_[i]; }

  // The first mission time at which a and b are (or cannot be proven not to be) closer than the
  // separation; nullopt when proven clear at every instant. `closest` and `refinements` accumulate.
  std::optional<double> firstLoss(std::size_t a, std::size_t b, double& closest, std::size_t& refinements) const {
    const double dt = o_.sample_dt_s;
    const long last = std::max(horizon(a), horizon(b));  // after it both hold still
    double before = distanceAtSample(a, b, 0);
    closest = std::min(closest, before);
    if (before < o_.separation_m) return 0.0;
    for (long g = 1; g <= last; ++g) {
      const double here = distanceAtSample(a, b, g);
      closest = std::min(closest, here);
      if (here < o_.separation_m) return static_cast<double>(g) * dt;
      if (auto loss = lossBetween(a, b, static_cast<double>(g - 1) * dt, static_cast<double>(g) * dt, before, here,
                                  closest, refinements)) {
        return loss;
      }
      before = here;
    }
    return std::nullopt;
  }

 private:
  long horizon(std::size_t i) const {
    return shift_[i] + static_cast<long>(samples_[i].size()) + (offset_s_[i] != 0.0 ? 1 : 0);
  }

  Eigen::Vector3d positionAt(std::size_t i, double t_s) const {
    return flown_[i].evaluate(t_s - delay(i), Derivative::kPosition);  // clamped: holding before and after
  }
  Eigen::Vector3d positionAtSample(std::size_t i, long g) const {
    if (offset_s_[i] != 0.0) return positionAt(i, static_cast<double>(g) * o_.sample_dt_s);
    const long k = std::clamp(g - shift_[i], 0L, static_cast<long>(samples_[i].size()) - 1);
    return samples_[i][static_cast<std::size_t>(k)];
  }
  double distanceAtSample(std::size_t a, std::size_t b, long g) const {
    return (positionAtSample(a, g) - positionAtSample(b, g)).norm();
  }

  // Over [t0, t1] with distances d0, d1 at its ends: the distance changes at most at the relative
  // speed v (both vehicles' bounds there), so it is at least (d0 + d1 - v (t1 - t0)) / 2 inside.
  std::optional<double> lossBetween(std::size_t a, std::size_t b, double t0, double t1, double d0, double d1,
                                    double& closest, std::size_t& refinements) const {
    const double v = boundOver(flown_[a], bounds_[a], t0 - delay(a), t1 - delay(a)) +
                     boundOver(flown_[b], bounds_[b], t0 - delay(b), t1 - delay(b));
    if (0.5 * (d0 + d1 - v * (t1 - t0)) >= o_.separation_m) return std::nullopt;
    const double mid = 0.5 * (t0 + t1);
    if (t1 - t0 <= o_.min_interval_s) return mid;  // not provable at this resolution: too close
    const double dm = (positionAt(a, mid) - positionAt(b, mid)).norm();
    ++refinements;
    closest = std::min(closest, dm);
    if (dm < o_.separation_m) return mid;
    if (auto loss = lossBetween(a, b, t0, mid, d0, dm, closest, refinements)) return loss;
    return lossBetween(a, b, mid, t1, dm, d1, closest, refinements);
  }

  const std::vector<Trajectory>& flown_;
  SeparationCheckOptions o_;
  std::vector<std::vector<Eigen::Vector3d>> samples_;
  std::vector<std::vector<double>> bounds_;  // per vehicle, per segment: speed bound (m/s)
  std::vector<long> shift_;                  // per vehicle: delay in whole samples
  std::vector<double> offset_s_;             // per vehicle: the rest of the delay (0 when whole)
};

}  // namespace

double speedBoundMps(const Trajectory& trajectory, double from_s, double to_s) {
  std::vector<double> bounds;
  for (const Segment& segment : trajectory.segments()) bounds.push_back(segmentSpeedBound(segment));
  return boundOver(trajectory, bounds, from_s, to_s);
}

SeparationVerdict checkFleetSeparation(const std::vector<Trajectory>& flown, const std::vector<double>& delays_s,
                                       const SeparationCheckOptions& options) {
  SeparationVerdict verdict;
  SeparationChecker checker(flown, options);
  for (std::size_t i = 0; i < flown.size() && i < delays_s.size(); ++i) checker.setDelay(i, delays_s[i]);
  for (std::size_t b = 1; b < flown.size(); ++b) {
    for (std::size_t a = 0; a < b; ++a) {
      const auto loss = checker.firstLoss(a, b, verdict.closest_m, verdict.refinements);
      if (loss && verdict.clear) {
        verdict.clear = false;
        verdict.vehicle_a = a;
        verdict.vehicle_b = b;
        verdict.time_s = *loss;
      }
    }
  }
  return verdict;
}

SeparationRepair repairFleetSeparation(const std::vector<Trajectory>& flown, const SeparationCheckOptions& options,
                                       double delay_step_s, double max_delay_s, const TerminationCondition& stop) {
  SeparationRepair out;
  SeparationChecker checker(flown, options);
  const long step_samples = std::max(1L, std::lround(delay_step_s / options.sample_dt_s));
  const long max_shift = std::lround(max_delay_s / options.sample_dt_s);
  std::size_t refinements = 0;
  for (std::size_t i = 1; i < flown.size(); ++i) {
    while (true) {
      bool lost = false;
      for (std::size_t k = 0; k < i && !lost; ++k) {
        double closest = std::numeric_limits<double>::infinity();
        lost = checker.firstLoss(i, k, closest, refinements).has_value();
      }
      if (!lost) break;
      if (stop.shouldStop()) {
        out.stopped = true;
        return out;
      }
      checker.setShift(i, checker.shift(i) + step_samples);
      if (checker.shift(i) > max_shift) {
        out.failed_vehicle = i;
        return out;
      }
    }
    if (checker.shift(i) > 0) ++out.repaired;
  }
  // The final schedule, every pair once more: the least distance met (all pairs proven clear).
  for (std::size_t b = 1; b < flown.size(); ++b) {
    for (std::size_t a = 0; a < b; ++a) checker.firstLoss(a, b, out.closest_m, refinements);
  }
  for (std::size_t i = 0; i < flown.size(); ++i) out.delays_s.push_back(checker.delay(i));
  return out;
}

Eigen::Vector3d FleetPlanOutput::positionAt(std::size_t i, double t_s) const {
  const double local = t_s - delays_s[i];
  if (local <= 0.0) return flown[i].evaluate(0.0, Derivative::kPosition);
  if (local >= flown[i].duration_s()) return flown[i].evaluate(flown[i].duration_s(), Derivative::kPosition);
  return flown[i].evaluate(local, Derivative::kPosition);
}

std::optional<PlanError> validateFleetRequest(const FleetRequestData& r, const FleetMissionOptions& options) {
  if (auto e = checkId(r.request_id, "request_id", kMaxRequestIdChars)) return toPlanError(*e);
  if (auto e = checkName(r.planner, "planner")) return toPlanError(*e);
  if (r.vehicle_ids.empty()) return fail(PlanErrorCode::kEmptyMission, "vehicle_ids", "no vehicles given");
  if (r.vehicle_ids.size() > options.max_vehicles) {
    return fail(PlanErrorCode::kMissionTooLarge, "vehicle_ids",
                std::to_string(r.vehicle_ids.size()) + " vehicles, at most " + std::to_string(options.max_vehicles));
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < r.vehicle_ids.size(); ++i) {
    if (auto e = checkId(r.vehicle_ids[i], indexed("vehicle_ids", i))) return toPlanError(*e);
    if (!seen.insert(r.vehicle_ids[i]).second) {
      return fail(PlanErrorCode::kInvalidArgument, indexed("vehicle_ids", i), "duplicate vehicle id '" + r.vehicle_ids[i] + "'");
    }
  }
  if (r.begins.size() != r.vehicle_ids.size()) {
    return fail(PlanErrorCode::kInvalidArgument, "begins",
                "has " + std::to_string(r.begins.size()) + " points for " + std::to_string(r.vehicle_ids.size()) + " vehicles");
  }
  if (r.ends.size() != r.vehicle_ids.size()) {
    return fail(PlanErrorCode::kInvalidArgument, "ends",
                "has " + std::to_string(r.ends.size()) + " points for " + std::to_string(r.vehicle_ids.size()) + " vehicles");
  }
  if (r.tasks.empty()) return fail(PlanErrorCode::kEmptyMission, "tasks", "no tasks given");
  if (r.tasks.size() > options.max_tasks) {
    return fail(PlanErrorCode::kMissionTooLarge, "tasks",
                std::to_string(r.tasks.size()) + " tasks, at most " + std::to_string(options.max_tasks));
  }
  for (std::size_t i = 0; i < r.begins.size(); ++i) {
    if (auto e = checkPoint(r.begins[i], indexed("begins", i))) return e;
    if (auto e = checkPoint(r.ends[i], indexed("ends", i))) return e;
  }
  for (std::size_t j = 0; j < r.tasks.size(); ++j) {
    if (auto e = checkPoint(r.tasks[j], indexed("tasks", j))) return e;
  }
  if (auto e = checkVehicleLimits(r.limits, options.limit_bounds)) return e;
  if (r.limits.model.value_or(options.default_model) == VehicleModel::kFixedWing) {
    return fail(PlanErrorCode::kInvalidArgument, "limits.model",
                std::string(r.limits.model ? "is fixed_wing" : "is left to the service's vehicle.model, fixed_wing") +
                    ": fleets fly multirotors only (their plans wait in place and stop at the depots, which a fixed "
                    "wing cannot); give limits.model multirotor, or plan each fixed wing as a mission");
  }
  if (!r.planner.empty() && r.planner != kFleetPlannerGreedy) {
    return fail(PlanErrorCode::kUnknownPlanner, "planner",
                "'" + r.planner + "' is not a fleet planner (\"\" or \"" + kFleetPlannerGreedy + "\")");
  }
  return std::nullopt;
}

namespace {

// The route points in ENU, each checked against the world, into out; the highest one's height.
Result<double, PlanError> placeRoutePoints(const FleetRequestData& r, const CollisionWorld& world,
                                           const LocalFrame& frame, FleetPlanOutput& out) {
  double top_m = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < r.vehicle_ids.size(); ++i) {
    // Each point is checked as a mission's are, so its error quotes it as the user wrote it.
    if (auto bad = checkMissionPoint(world, r.begins[i], indexed("begins", i))) return *bad;
    if (auto bad = checkMissionPoint(world, r.ends[i], indexed("ends", i))) return *bad;
    out.begins_m.push_back(r.begins[i].toEnu(frame));
    out.ends_m.push_back(r.ends[i].toEnu(frame));
    top_m = std::max({top_m, out.begins_m[i].z(), out.ends_m[i].z()});
  }
  for (std::size_t j = 0; j < r.tasks.size(); ++j) {
    if (auto bad = checkMissionPoint(world, r.tasks[j], indexed("tasks", j))) return *bad;
    out.tasks_m.push_back(r.tasks[j].toEnu(frame));
    top_m = std::max(top_m, out.tasks_m[j].z());
  }
  return top_m;
}

// The flight band's grid (as the HAB-PP legs build theirs), just above the highest route point.
Result<GridLayer, PlanError> buildFlightBand(const WorldModel& world_model, const CollisionWorld& world,
                                             const FleetMissionOptions& o, double top_m,
                                             const TerminationCondition& stop, FleetPlanOutput& out) {
  const Heightfield& terrain = world_model.terrain();
  const CollisionWorldOptions& wo = world.options();
  out.cell_size_m = std::max(terrain.dem().resolutionM().minCoeff(),
                             1.0001 * terrain.boundsEn().sizes().maxCoeff() / o.max_cells_per_axis);
  out.cruise_altitude_m = std::min(wo.ceiling_m - 1.0, top_m + o.band_margin_m);
  TerrainGridOptions go;
  go.cell_size_m = out.cell_size_m;
  go.flight_ceiling_m = out.cruise_altitude_m;
  go.min_clearance_m = wo.min_clearance_m + wo.vehicle_radius_m;
  go.cancel = stop.cancelFlag();
  go.no_fly_zones = world.noFlyZones();
  go.zone_margin_m = wo.vehicle_radius_m;
  for (const auto* points : {&out.begins_m, &out.ends_m, &out.tasks_m})
    for (const Eigen::Vector3d& p : *points) go.keep_free_m.push_back(p.head<2>());
  auto grid = buildTerrainGrid(terrain, go);
  if (!grid.ok()) return toPlanError(grid.error());
  return std::move(*grid);
}

// Depots must already be apart: a held vehicle cannot be moved by a delay.
std::optional<PlanError> checkDepotSeparation(const FleetPlanOutput& out, double separation_m) {
  const std::string apart = "closer than the minimum separation (" + std::to_string(static_cast<int>(separation_m)) + " m) to ";
  for (std::size_t i = 0; i < out.begins_m.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      if ((out.begins_m[i] - out.begins_m[k]).norm() < separation_m)
        return fail(PlanErrorCode::kInvalidArgument, indexed("begins", i), apart + indexed("begins", k));
      if ((out.ends_m[i] - out.ends_m[k]).norm() < separation_m)
        return fail(PlanErrorCode::kInvalidArgument, indexed("ends", i), apart + indexed("ends", k));
    }
  }
  return std::nullopt;
}

// GMTPA on the flight band: which vehicle does which tasks, and their collision-free grid paths.
Result<FleetPlan, PlanError> allocateTasks(const GridLayer& grid, const FleetPlanOutput& out,
                                           const TerminationCondition& stop) {
  FleetProblem problem;
  for (std::size_t i = 0; i < out.begins_m.size(); ++i) {
    const auto cell = grid.cellAt(out.begins_m[i].head<2>());
    if (!cell) return fail(PlanErrorCode::kOutsideMap, indexed("begins", i), "is off the flight-band grid");
    problem.vehicles.push_back({indexed("begins", i), *cell, 0});
  }
  for (std::size_t j = 0; j < out.tasks_m.size(); ++j) {
    const auto cell = grid.cellAt(out.tasks_m[j].head<2>());
    if (!cell) return fail(PlanErrorCode::kOutsideMap, indexed("tasks", j), "is off the flight-band grid");
    problem.tasks.push_back({indexed("tasks", j), *cell});
  }
  auto plan = planFleet(grid, problem, FleetPlannerOptions{}, stop);
  if (!plan.ok()) {
    PlanError e = toPlanError(plan.error());
    e.field = requestField(plan.error().field);
    e.message = plan.error().message + " (on the " + std::to_string(static_cast<int>(out.cell_size_m)) +
                " m flight-band grid under " + std::to_string(static_cast<int>(out.cruise_altitude_m)) + " m)";
    return e;
  }
  return std::move(*plan);
}

// Each trajectory's size against the caps, before the separation check samples them all.
std::optional<PlanError> checkTrajectorySizes(const FleetRequestData& r, const FleetMissionOptions& o,
                                              const FleetPlanOutput& out) {
  for (std::size_t i = 0; i < out.flown.size(); ++i) {
    if (auto too_large = checkTrajectorySize(out.flown[i].duration_s(), o.sample_dt_s, o.trajectory_bounds)) {
      too_large->field = indexed("vehicle_ids", i);
      too_large->message = r.vehicle_ids[i] + ": " + too_large->message;
      return too_large;
    }
  }
  return std::nullopt;
}

// Separation over continuous time, repaired by delaying starts (see the header); the delays.
Result<SeparationRepair, PlanError> separateVehicles(const FleetRequestData& r, const FleetMissionOptions& o,
                                                     double separation_m, const TerminationCondition& stop,
                                                     FleetPlanOutput& out) {
  SeparationCheckOptions so;
  so.separation_m = separation_m;
  so.sample_dt_s = o.separation_dt_s;
  so.min_interval_s = o.separation_min_interval_s;
  SeparationRepair repair = repairFleetSeparation(out.flown, so, o.delay_step_s, o.max_delay_s, stop);
  if (repair.stopped) return fail(PlanErrorCode::kCancelled, "", "stopped during the separation repair");
  if (repair.failed_vehicle) {
    const std::size_t i = *repair.failed_vehicle;
    return fail(PlanErrorCode::kUnreachable, indexed("vehicle_ids", i),
                r.vehicle_ids[i] + " cannot keep " + std::to_string(static_cast<int>(separation_m)) +
                    " m from the vehicles before it within a delay of " + std::to_string(static_cast<int>(o.max_delay_s)) +
                    " s (its route passes too close to a point where another holds)");
  }
  out.status.separation_repairs = static_cast<std::uint32_t>(repair.repaired);
  out.status.achieved_separation_m = out.flown.size() > 1 ? repair.closest_m : 0.0;
  return repair;
}

// Each vehicle's trajectory sampled from its delayed start, keeping its visiting order and legs.
void sampleDelayedTrajectories(const FleetRequestData& r, const LocalFrame& frame, const FleetMissionOptions& o,
                               std::int64_t start_utc_ns, const std::vector<double>& delays_s, FleetPlanOutput& out) {
  for (std::size_t i = 0; i < out.flown.size(); ++i) {
    const double delay_s = delays_s[i];
    out.delays_s.push_back(delay_s);
    out.status.allocation[i].delay_s = delay_s;
    out.status.makespan_s = std::max(out.status.makespan_s, delay_s + out.flown[i].duration_s());
    TrajectoryData& d = out.trajectories[i];
    TrajectoryIdentity id{r.vehicle_ids[i], r.request_id + "-" + r.vehicle_ids[i], 0, r.request_id};
    TrajectoryData sampled = toTrajectoryData(out.flown[i], frame, o.sample_dt_s,
                                              start_utc_ns + static_cast<std::int64_t>(std::llround(delay_s * 1e9)), id);
    sampled.visiting_order = std::move(d.visiting_order);
    sampled.legs = std::move(d.legs);
    d = std::move(sampled);
  }
}

// The planning proper; throws nothing, reports through `out.status` (error fields) or fills out.
std::optional<PlanError> planInto(const FleetRequestData& r, WorldModel& world_model, const FleetMissionOptions& o,
                                  std::int64_t start_utc_ns, const TerminationCondition& stop, FleetPlanOutput& out) {
  if (auto e = validateFleetRequest(r, o)) return e;
  if (!(o.separation_dt_s > 0.0) || !(o.delay_step_s > 0.0) || !(o.sample_dt_s > 0.0) || o.max_cells_per_axis < 4 ||
      !(o.min_separation_m >= 0.0) || !(o.separation_min_interval_s > 0.0)) {
    return fail(PlanErrorCode::kInternal, "options", "fleet options out of range");
  }
  auto world_r = world_model.worldFor(r.limits.min_clearance_agl_m, r.limits.ceiling_amsl_m);
  if (!world_r.ok()) return fail(PlanErrorCode::kLimitsOutOfRange, world_r.error().field, world_r.error().message);
  const std::shared_ptr<const CollisionWorld> world = *world_r;
  const LocalFrame& frame = world_model.frame();

  auto top_m = placeRoutePoints(r, *world, frame, out);
  if (!top_m.ok()) return top_m.error();
  auto grid = buildFlightBand(world_model, *world, o, *top_m, stop, out);
  if (!grid.ok()) return grid.error();
  const double separation_m = o.min_separation_m > 0.0 ? o.min_separation_m : out.cell_size_m;
  out.status.min_separation_m = separation_m;
  if (auto e = checkDepotSeparation(out, separation_m)) return e;
  auto plan = allocateTasks(*grid, out, stop);
  if (!plan.ok()) return plan.error();
  out.status.makespan_steps = plan->makespan();

  // Each vehicle's route in 3D through the trajectory stage.
  const FleetRouteContext context{r, *grid, world, out.cruise_altitude_m, toVehicleLimits(r.limits), o};
  for (std::size_t i = 0; i < r.vehicle_ids.size(); ++i) {
    if (stop.shouldStop()) return fail(PlanErrorCode::kCancelled, "", "stopped while building trajectories");
    if (auto e = addFleetVehicleRoute(context, i, plan->paths.vehicles[i], out)) return e;
  }
  if (auto e = checkTrajectorySizes(r, o, out)) return e;
  auto repair = separateVehicles(r, o, separation_m, stop, out);
  if (!repair.ok()) return repair.error();
  sampleDelayedTrajectories(r, frame, o, start_utc_ns, repair->delays_s, out);
  out.grid_paths = plan->paths.vehicles;
  out.grid = std::make_shared<const GridLayer>(std::move(*grid));
  return std::nullopt;
}

}  // namespace

FleetPlanOutput planFleetMission(const FleetRequestData& request, WorldModel& world, const FleetMissionOptions& options,
                                 std::int64_t start_utc_ns, const TerminationCondition& stop) {
  const auto started = std::chrono::steady_clock::now();
  FleetPlanOutput out;
  out.status.request_id = request.request_id;
  std::optional<PlanError> error = planInto(request, world, options, start_utc_ns, stop, out);
  out.status.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (error) {
    out.status.state = error->code == PlanErrorCode::kCancelled ? PlanState::kCancelled : PlanState::kFailed;
    out.status.error_code = error->code;
    out.status.field = error->field;
    out.status.message = error->describe();
    out.trajectories.clear();
  } else {
    out.status.state = PlanState::kSucceeded;
  }
  return out;
}

}  // namespace skyroute
