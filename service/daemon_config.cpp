#include "service/daemon_config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <variant>
#include <vector>

#include <toml++/toml.h>

#include "service/known_keys.hpp"
#include "service/planner_registry.hpp"
#include "service/text_bounds.hpp"
#include "service/toml_precheck.hpp"

namespace skyroute {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One configuration key: where it lives, what it means, and the field it sets.
struct Key {
  const char* section;
  const char* name;
  const char* doc;  // meaning and unit
  std::variant<double*, std::int64_t*, bool*, std::string*> target;
  double min = -kInf;  // numbers only
  double max = kInf;
  std::vector<std::string> choices = {};  // strings only (empty = any)
  double scale = 1.0;  // the field holds value * scale (a key in seconds for a field in milliseconds)
};

// Integer and enum fields are kept in these while parsing, then copied to their typed homes.
struct IntegerShadow {
  std::int64_t domain, seed, threads, max_queue, max_points, leg_max_iterations, order_cells, grid_cells,
      grid_window_segments, max_attempts, replan_leg_iterations, max_stored_results, max_samples, fleet_vehicles,
      fleet_tasks, max_obstacles;
  std::string mission_point_mode;
  std::int64_t tree_reuse_nodes;
  std::int64_t reorder_threads;
  std::string vehicle_model;
  std::string time_allocation;
};

IntegerShadow shadowOf(const DaemonConfig& c) {
  const PipelineOptions& p = c.engine.pipeline;
  return IntegerShadow{c.domain,
                       static_cast<std::int64_t>(p.seed),
                       c.engine.planning_threads,
                       static_cast<std::int64_t>(c.engine.max_queue),
                       static_cast<std::int64_t>(p.bounds.max_points),
                       static_cast<std::int64_t>(p.budget.leg_max_iterations),
                       p.order.max_cells_per_axis,
                       p.grid_legs.max_cells_per_axis,
                       p.grid_legs.output_window_segments,
                       p.replan.max_attempts,
                       static_cast<std::int64_t>(p.replan.replan_leg_max_iterations),
                       static_cast<std::int64_t>(c.engine.max_stored_results),
                       static_cast<std::int64_t>(p.bounds.trajectory.max_samples),
                       static_cast<std::int64_t>(p.fleet.max_vehicles),
                       static_cast<std::int64_t>(p.fleet.max_tasks),
                       static_cast<std::int64_t>(c.engine.obstacles.max_obstacles),
                       std::string(to_string(p.replan.route.trajectory.fixed_waypoint_mode)),
                       static_cast<std::int64_t>(p.replan.route.tree_reuse.max_nodes),
                       static_cast<std::int64_t>(p.reorder.repair_threads),
                       std::string(to_string(p.vehicle.model)),
                       std::string(to_string(p.replan.route.trajectory.time_allocation.method))};
}

void applyShadow(const IntegerShadow& s, DaemonConfig& c) {
  PipelineOptions& p = c.engine.pipeline;
  c.domain = static_cast<int>(s.domain);
  p.seed = static_cast<std::uint64_t>(s.seed);
  c.engine.planning_threads = static_cast<int>(s.threads);
  c.engine.max_queue = static_cast<std::size_t>(s.max_queue);
  p.bounds.max_points = static_cast<std::size_t>(s.max_points);
  p.budget.leg_max_iterations = static_cast<std::uint64_t>(s.leg_max_iterations);
  p.order.max_cells_per_axis = static_cast<int>(s.order_cells);
  p.grid_legs.max_cells_per_axis = static_cast<int>(s.grid_cells);
  p.grid_legs.output_window_segments = static_cast<int>(s.grid_window_segments);
  p.replan.max_attempts = static_cast<int>(s.max_attempts);
  p.replan.replan_leg_max_iterations = static_cast<std::uint64_t>(s.replan_leg_iterations);
  c.engine.max_stored_results = static_cast<std::size_t>(s.max_stored_results);
  p.bounds.trajectory.max_samples = static_cast<std::size_t>(s.max_samples);
  p.fleet.max_vehicles = static_cast<std::size_t>(s.fleet_vehicles);
  p.fleet.max_tasks = static_cast<std::size_t>(s.fleet_tasks);
  c.engine.obstacles.max_obstacles = static_cast<std::size_t>(s.max_obstacles);
  p.replan.route.tree_reuse.max_nodes = static_cast<std::size_t>(s.tree_reuse_nodes);
  p.reorder.repair_threads = static_cast<int>(s.reorder_threads);
  // The key's choices are the parser's names.
  p.replan.route.trajectory.fixed_waypoint_mode =
      parseFixedWaypointMode(s.mission_point_mode).value_or(p.replan.route.trajectory.fixed_waypoint_mode);
  p.vehicle.model = parseVehicleModel(s.vehicle_model).value_or(p.vehicle.model);
  for (const TimeAllocationMethod method : {TimeAllocationMethod::kTrapezoidal, TimeAllocationMethod::kConstantSpeed}) {
    if (s.time_allocation == to_string(method)) p.replan.route.trajectory.time_allocation.method = method;
  }
}

std::vector<std::string> plannerChoices() {
  std::vector<std::string> names;
  for (const RoutePlannerInfo& p : routePlanners()) names.emplace_back(p.name);
  return names;
}

std::vector<Key> keysOf(DaemonConfig& c, IntegerShadow& s) {
  PipelineOptions& p = c.engine.pipeline;
  EngineOptions& e = c.engine;
  VehicleLimitBounds& b = p.bounds.limits;
  return {
      {"terrain", "dem", "DEM raster path (any GDAL raster); \"\" = the embedded default terrain", &c.dem_path},
      {"terrain", "nofly", "GeoJSON file of no-fly zones (docs/nofly.md); \"\" = none", &c.nofly_path},
      {"terrain", "vehicle_radius_m", "every vehicle's bounding sphere, metres", &c.world.vehicle_radius_m, 0.01, 1000},
      {"terrain", "terrain_margin_m", "horizontal distance kept from the ground, metres", &c.world.terrain_margin_m, 0, 1000},
      {"terrain", "constant_velocity_horizon_s",
       "how far ahead an obstacle with a constant velocity and no end of validity is predicted, seconds",
       &c.world.constant_velocity_horizon_s, 1, 86400},
      {"dds", "domain", "DDS domain id", &s.domain, 0, 232},
      {"dds", "service_id", "this daemon's key in the ServiceStatus heartbeat", &c.service_id},
      {"dds", "heartbeat_period_s", "ServiceStatus period, seconds", &c.heartbeat_period_s, 0.05, 3600},
      {"dds", "flush_timeout_s",
       "on stop, the deadline after the signal for the engine's stop and the readers' acknowledgements, seconds",
       &c.flush_timeout_s, 0, 10},
      {"dds", "startup_probe_s",
       "before serving, listen this long for another daemon with this service_id (then refuse to start); 0 serves at once, seconds",
       &c.startup_probe_s, 0, 10},
      {"dds", "primary_strength",
       "ownership strength of a primary's trajectory, status and heartbeat writers: readers take the strongest live "
       "writer's samples; must be above standby_strength",
       &c.primary_strength, 0, 2147483647},
      {"dds", "standby_strength", "ownership strength of a standby's writers (below primary_strength)",
       &c.standby_strength, 0, 2147483647},
      {"dds", "liveliness_lease_s",
       "liveliness lease of the trajectory, status and heartbeat writers: this long after a daemon dies, readers take "
       "the standby's samples instead, seconds",
       &c.liveliness_lease_s, 0.05, 60},
      {"service", "role",
       "primary, or standby: a hot standby on the primary's domain and service_id that plans every request too and "
       "whose samples ground stations take when the primary dies (docs/dds.md)",
       &c.role, -kInf, kInf, {"primary", "standby"}},
      {"service", "state_dir",
       "folder of the state journal (journal.sqlite, docs/journal.md): accepted missions, current trajectories, "
       "obstacles and no-fly zones survive a crash and a restart; \"\" = kept in memory only",
       &c.state_dir},
      {"service", "shard_group",
       "daemons on one domain with the same non-empty shard group split the vehicles between them, each with its own "
       "dds.service_id (docs/dds.md \"Shards\"); not with role standby; \"\" = not sharded: this daemon plans every request",
       &c.shard_group},
      {"security", "dir",
       "DDS Security: the folder of this daemon's identity, certificates and signed permissions (scripts/make-pki.sh "
       "makes DIR/daemon; docs/dds.md); \"\" = unsecured",
       &c.security_dir},
      {"ros2", "enabled",
       "mirror each vehicle's current trajectory on ROS 2 topics rt/skyroute/<vehicle>/path (nav_msgs/Path) and "
       "/origin (geographic_msgs/GeoPoint); docs/interop.md",
       &c.ros2_enabled},
      {"planning", "default_planner", "route planner used when a request names none (skyroute planners lists them)",
       &p.default_planner, -kInf, kInf, plannerChoices()},
      {"planning", "seed", "seed of every plan (a run is reproducible from it)", &s.seed, 0, 9.0e18},
      {"planning", "leg_max_iterations", "search iterations per leg (RRT*; 0 = none, then leg_time_cap_s alone)",
       &s.leg_max_iterations, 0, 1e9},
      {"planning", "leg_time_cap_s",
       "wall-clock cap of one leg's search, seconds (0 = none); when it fires the status says so and the plan is "
       "no longer reproducible from the seed",
       &p.budget.leg_time_cap_s, 0, 3600},
      {"planning", "memory_budget_mb",
       "memory the planning threads share; a request whose estimate exceeds one thread's share is refused with "
       "ERROR_TOO_LARGE (0 = no guard), MiB",
       &e.memory_budget_mb, 0, 1e6},
      {"planning", "max_stored_results", "finished requests remembered to answer a repeated request_id",
       &s.max_stored_results, 0, 1000000},
      {"planning", "threads", "requests planned at once (skyrouted)", &s.threads, 1, 64},
      {"planning", "max_queue", "requests waiting beyond this are refused with ERROR_BUSY (skyrouted)", &s.max_queue, 1,
       100000},
      {"planning", "max_points", "largest number of mission points in one request", &s.max_points, 1, 1000},
      {"planning", "sample_dt_s", "spacing of the trajectory samples, seconds", &p.sample_dt_s, 0.001, 10},
      {"planning", "corridor_margin_m", "RRT* samples within this distance of a leg's bounding box first (then wider), metres",
       &p.replan.route.corridor_margin_m, 0, 1e6},
      {"planning", "lospo_spacing_m",
       "rrtstar-lospo: spacing of the vertices LOSPO inserts along each leg's RRT* path before it joins the farthest "
       "visible ones (smaller: a shorter path for more checks); not the trajectory's extra waypoints, metres",
       &p.replan.route.lospo.spacing_m, 1, 10000},
      {"planning", "order_grid_max_cells", "cells per axis of the MMD*L ordering grid at most", &s.order_cells, 8, 2000},
      {"planning", "order_band_margin_m", "the ordering grid's flight band reaches this far above the highest point, metres",
       &p.order.band_margin_m, 0, 10000},
      {"planning", "grid_max_cells", "cells per axis of the grid planners' flight-band grid at most (hab-pp, hab-pp-rrt)",
       &s.grid_cells, 8, 4000},
      {"planning", "grid_band_margin_m",
       "the grid planners' band reaches this far above a leg's higher end, metres (hab-pp, hab-pp-rrt)",
       &p.grid_legs.band_margin_m, 0, 10000},
      {"planning", "mission_point_mode",
       "at a mission point the trajectory must pass exactly: pass = fly through, slowed to the speed the corner "
       "allows, and come to rest there only where passing cannot be made to fly (a turn no rounding fits, or a "
       "limit no repair meets; the plan's status names the point); stop = come to rest at every point",
       &s.mission_point_mode, -kInf, kInf, {"pass", "stop"}},
      {"planning", "time_allocation",
       "times of the trajectory's segments: trapezoidal = a speed profile per segment that accelerates and brakes "
       "at a share of the acceleration limit, cruises at v_ref and slows before sharp turns; constant_speed = "
       "seed 003's equation 3, each segment's length over v_ref",
       &s.time_allocation, -kInf, kInf, {"trapezoidal", "constant_speed"}},
      {"planning", "grid_window_segments",
       "the grid planners' output re-planned in windows of this many segments (0 = off; hab-pp, hab-pp-rrt)",
       &s.grid_window_segments, 0, 1000},
      {"planning", "rrt_tree_reuse",
       "rrtstar-lospo replans: keep the RRT* tree of the leg being flown and grow it again from the takeover "
       "point (what that point still reaches through motions clear of the updated obstacles is kept; the kept "
       "nodes count against replanning.leg_max_iterations, of which at least a quarter is still sampled) instead "
       "of a new tree; docs/benchmarks.md compares replan latency and length with and without",
       &p.replan.rrt_tree_reuse},
      {"planning", "rrt_tree_reuse_max_nodes",
       "with rrt_tree_reuse: RRT* nodes kept per vehicle at most (the cheapest from the root), and re-rooted at "
       "most per replan (one motion check each)",
       &s.tree_reuse_nodes, 1, 1000000},
      {"vehicle", "model",
       "vehicle model of the requests that leave it to the service (VehicleLimits.model DEFAULT, no \"model\" in a "
       "mission file): multirotor (may hover), or fixed_wing (never under its minimum airspeed, banks at most "
       "max_bank_deg, climbs and descends at most at its path angles, never stops; docs/dds.md)",
       &s.vehicle_model, -kInf, kInf, {"multirotor", "fixed_wing"}},
      {"vehicle", "stall_speed_mps",
       "fixed wing: stall speed of the requests that give 0; 0 = none (such a request is refused naming "
       "limits.stall_speed_mps), m/s",
       &p.vehicle.stall_speed_mps, 0, 1000},
      {"vehicle", "stall_margin", "fixed wing: minimum airspeed = stall speed x this, for the requests that give 0",
       &p.vehicle.stall_margin, 1, 3},
      {"vehicle", "max_bank_deg",
       "fixed wing: largest bank angle, for the requests that give 0 (turn radius V^2 / (g tan(bank)), load factor "
       "1 / cos(bank)), degrees",
       &p.vehicle.max_bank_deg, 1, 79},
      {"vehicle", "max_climb_angle_deg",
       "fixed wing: largest flight path angle above the horizontal, for the requests that give 0, degrees",
       &p.vehicle.max_climb_angle_deg, 1, 60},
      {"vehicle", "max_descent_angle_deg",
       "fixed wing: largest flight path angle below the horizontal, for the requests that give 0, degrees",
       &p.vehicle.max_descent_angle_deg, 1, 60},
      {"replanning", "enabled", "replan active missions when obstacles will meet them (skyrouted)", &c.engine.replanning},
      {"replanning", "period_s", "replanning cycle t_ref, seconds", &p.replan.period_s, 0.01, 10},
      {"replanning", "horizon_s", "how far ahead conflicts are looked for, seconds", &p.replan.horizon_s, 1, 3600},
      {"replanning", "margin_m", "extra room kept from moving obstacles when replanning, metres", &p.replan.margin_m,
       0, 10000},
      {"replanning", "window_s", "a moving obstacle blocks the stretch it covers in this long, seconds",
       &p.replan.window_s, 0, 3600},
      {"replanning", "max_attempts", "candidates tried per replan", &s.max_attempts, 1, 100},
      {"replanning", "reorder",
       "re-order a flying mission's points left when the obstacles change (MMD*L searches repaired, open TSP from the "
       "vehicle; missions whose order MMD*L chose)",
       &p.reorder.enabled},
      {"replanning", "reorder_sweep_s",
       "re-ordering: an obstacle covers the order grid's cells its track crosses this long ahead, seconds",
       &p.reorder.sweep_s, 0, 3600},
      {"replanning", "reorder_threads",
       "re-ordering: threads of one repair of the MMD*L searches, the replanning loop's included (the goals' maps are "
       "repaired apart; same results)",
       &s.reorder_threads, 1, 16},
      {"replanning", "leg_max_iterations", "RRT* iterations per leg when replanning (0 = planning.leg_max_iterations)",
       &s.replan_leg_iterations, 0, 1e9},
      {"replanning", "budget_s",
       "wall-clock budget of one replan (the first candidate is always finished), seconds",
       &p.replan.replan_budget_ms, 0, 60, {}, 1e3},
      {"audit", "step_s",
       "the audit every trajectory passes before it is published checks its samples this far apart (docs/dds.md), "
       "seconds",
       &p.audit.step_s, 0.001, 1},
      {"audit", "tolerance_m",
       "the audit lets a sample come this much nearer than the clearance, the ceiling, a no-fly zone or an obstacle "
       "allow, metres",
       &p.audit.tolerance_m, 0, 5},
      {"audit", "limit_tolerance", "the audit lets a sample exceed a vehicle limit by this share of it",
       &p.audit.limit_tolerance, 0, 0.5},
      {"bounds", "min_speed_mps", "a request's v_ref_mps and max_speed_mps at least, m/s", &b.min_speed_mps, 0.01, 1000},
      {"bounds", "max_speed_mps", "any speed limit of a request at most, m/s", &b.max_speed_mps, 0.01, 1000},
      {"bounds", "min_vertical_speed_mps", "a request's max_climb_rate_mps and max_descent_rate_mps at least, m/s",
       &b.min_vertical_speed_mps, 0.001, 1000},
      {"bounds", "min_accel_mps2", "a request's max_accel_mps2 at least, m/s^2", &b.min_accel_mps2, 0.001, 1000},
      {"bounds", "max_accel_mps2", "a request's max_accel_mps2 at most, m/s^2", &b.max_accel_mps2, 0.001, 1000},
      {"bounds", "max_turn_radius_m", "a request's min_turn_radius_m at most, metres", &b.max_turn_radius_m, 0, 1e6},
      {"bounds", "max_clearance_m", "a request's min_clearance_agl_m at most, metres", &b.max_clearance_m, 0, 1e5},
      {"bounds", "max_ceiling_amsl_m", "a request's ceiling_amsl_m at most, metres", &b.max_ceiling_amsl_m, 0, 1e5},
      {"bounds", "max_trajectory_duration_s",
       "longest trajectory the service makes; a longer one is refused with ERROR_TOO_LARGE before sampling, seconds",
       &p.bounds.trajectory.max_duration_s, 1, 1e6},
      {"bounds", "max_trajectory_samples",
       "most samples in one published trajectory; more is refused with ERROR_TOO_LARGE before sampling",
       &s.max_samples, 10, 10000000},
      {"bounds", "max_fleet_vehicles", "vehicles in one fleet request at most", &s.fleet_vehicles, 1, 1000},
      {"bounds", "max_fleet_tasks", "tasks in one fleet request at most", &s.fleet_tasks, 1, 10000},
      {"fleet", "replan",
       "keep flying fleets clear of obstacles: replan the vehicles an obstacle will meet, re-offer tasks no vehicle "
       "can reach (docs/dds.md)",
       &p.fleet_replan.enabled},
      {"fleet", "replan_budget_s", "wall-clock budget of one fleet replan on a planning worker, seconds",
       &p.fleet_replan.budget_s, 0.01, 60},
      {"fleet", "replan_margin_m", "room a fleet vehicle keeps from every obstacle beyond its radius, metres",
       &p.fleet_replan.margin_m, 0, 10000},
      {"obstacles", "max_speed_mps", "an obstacle's speed at most, m/s", &e.obstacles.max_speed_mps, 0, 10000},
      {"obstacles", "extent_factor",
       "an obstacle's size at most, and its position at most this far outside the DEM, in DEM longer sides",
       &e.obstacles.extent_factor, 0.01, 100},
      {"obstacles", "max_active", "obstacles in force at most; an update for a new obstacle beyond them is refused",
       &s.max_obstacles, 1, 1e6},
      {"log", "level", "log level", &c.log_level, -kInf, kInf, {"trace", "debug", "info", "warn", "error"}},
      {"log", "format", "text, or json (one object per line)", &c.log_format, -kInf, kInf, {"text", "json"}},
      {"log", "repeat_window_s",
       "a warning repeated for the same vehicle or input and reason is logged once per window, then with its count, "
       "seconds",
       &e.log_repeat_window_s, 0.1, 3600},
  };
}

std::string keyName(const Key& k) { return std::string(k.section) + "." + k.name; }

Status setKey(const Key& key, const toml::node& node) {
  const std::string name = keyName(key);
  auto range = [&](double v) -> Status {
    if (!std::isfinite(v) || v < key.min || v > key.max) {
      std::ostringstream m;
      m << "is " << v << ", outside [" << key.min << ", " << key.max << "]";
      return make_error(ErrorCode::kInvalidArgument, name, m.str());
    }
    return Status::success();
  };
  if (auto* d = std::get_if<double*>(&key.target)) {
    std::optional<double> v = node.is_integer() ? std::optional<double>(static_cast<double>(*node.value<std::int64_t>()))
                                                : node.value<double>();
    if (!node.is_number() || !v) return make_error(ErrorCode::kInvalidArgument, name, "must be a number");
    if (Status s = range(*v); !s.ok()) return s;
    **d = *v * key.scale;
  } else if (auto* i = std::get_if<std::int64_t*>(&key.target)) {
    if (!node.is_integer()) return make_error(ErrorCode::kInvalidArgument, name, "must be an integer");
    const std::int64_t v = *node.value<std::int64_t>();
    if (Status s = range(static_cast<double>(v)); !s.ok()) return s;
    **i = v;
  } else if (auto* b = std::get_if<bool*>(&key.target)) {
    if (!node.is_boolean()) return make_error(ErrorCode::kInvalidArgument, name, "must be true or false");
    **b = *node.value<bool>();
  } else if (auto* str = std::get_if<std::string*>(&key.target)) {
    if (!node.is_string()) return make_error(ErrorCode::kInvalidArgument, name, "must be a string");
    const std::string v = *node.value<std::string>();
    if (!key.choices.empty() && std::find(key.choices.begin(), key.choices.end(), v) == key.choices.end()) {
      std::string known;
      for (const auto& c : key.choices) known += (known.empty() ? "" : ", ") + c;
      return make_error(ErrorCode::kInvalidArgument, name, "'" + v + "' is not one of " + known);
    }
    **str = v;
  }
  return Status::success();
}

}  // namespace

Result<DaemonConfig> parseDaemonConfig(const std::string& toml_text, const std::string& source_name,
                                       DaemonConfig defaults) {
  if (auto refused = findTomlHazard(toml_text, source_name)) return *refused;
  toml::table document;
  try {
    document = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream m;
    m << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column << ": " << e.description();
    return make_error(ErrorCode::kParseError, source_name, m.str());
  }
  DaemonConfig config = std::move(defaults);
  IntegerShadow shadow = shadowOf(config);
  const std::vector<Key> keys = keysOf(config, shadow);
  for (const auto& [section_name, section_node] : document) {
    // An empty name (TOML allows "" and '') is named as written, so the error still names a field.
    const std::string section = section_name.str().empty() ? "\"\"" : std::string(section_name.str());
    const toml::table* table = section_node.as_table();
    KnownKeys sections;
    for (const Key& k : keys)
      if (std::find(sections.begin(), sections.end(), k.section) == sections.end()) sections.push_back(k.section);
    if (std::find(sections.begin(), sections.end(), section) == sections.end()) {
      const auto close = closestKnownKey(section, sections);
      std::string known;
      for (std::string_view s : sections) known += (known.empty() ? "" : ", ") + std::string(s);
      return make_error(ErrorCode::kInvalidArgument, section,
                        "unknown section [" + section + "] (" +
                            (close ? "did you mean [" + std::string(*close) + "]?; " : std::string()) + "known: " +
                            known + ")");
    }
    if (!table) return make_error(ErrorCode::kInvalidArgument, section, "must be a table [" + section + "]");
    for (const auto& [key_name, node] : *table) {
      const std::string name = key_name.str().empty() ? "\"\"" : std::string(key_name.str());
      auto key = std::find_if(keys.begin(), keys.end(),
                              [&](const Key& k) { return section == k.section && name == k.name; });
      if (key == keys.end()) {
        KnownKeys names;
        for (const Key& k : keys)
          if (section == k.section) names.push_back(k.name);
        const auto close = closestKnownKey(name, names);
        return make_error(ErrorCode::kInvalidArgument, section + "." + name,
                          "unknown key (" + (close ? "did you mean " + std::string(*close) + "?; " : std::string()) +
                              "skyrouted --print-config lists every key)");
      }
      if (Status s = setKey(*key, node); !s.ok()) return s.error();
    }
  }
  applyShadow(shadow, config);
  const VehicleLimitBounds& b = config.engine.pipeline.bounds.limits;
  if (b.min_speed_mps > b.max_speed_mps) {
    return make_error(ErrorCode::kInvalidArgument, "bounds.min_speed_mps", "is above bounds.max_speed_mps");
  }
  if (b.min_accel_mps2 > b.max_accel_mps2) {
    return make_error(ErrorCode::kInvalidArgument, "bounds.min_accel_mps2", "is above bounds.max_accel_mps2");
  }
  if (b.min_vertical_speed_mps > b.max_speed_mps) {
    return make_error(ErrorCode::kInvalidArgument, "bounds.min_vertical_speed_mps", "is above bounds.max_speed_mps");
  }
  if (auto bad = validatePipelineOptions(config.engine.pipeline)) {
    return make_error(ErrorCode::kInvalidArgument, bad->field, bad->message);
  }
  if (Status s = validateDaemonConfig(config); !s.ok()) return s.error();
  return config;
}

std::int32_t ownershipStrength(const DaemonConfig& config) {
  return static_cast<std::int32_t>(config.role == "standby" ? config.standby_strength : config.primary_strength);
}

Status validateDaemonConfig(const DaemonConfig& config) {
  // The strings first (text_bounds.hpp): the service id names the daemon on the wire and in logs.
  if (auto e = checkId(config.service_id, "dds.service_id")) return *e;
  // The group travels in the daemon's USER_DATA (";shard_group=..."): an id holds no ';' or '='.
  if (auto e = checkOptionalId(config.shard_group, "service.shard_group")) return *e;
  for (const auto& [path, key] : {std::pair{&config.dem_path, "terrain.dem"}, std::pair{&config.nofly_path, "terrain.nofly"},
                                  std::pair{&config.state_dir, "service.state_dir"},
                                  std::pair{&config.security_dir, "security.dir"}}) {
    // A path is the operator's: any byte a file name may hold, within the free-text length.
    if (path->size() > kMaxFreeTextBytes)
      return make_error(ErrorCode::kInvalidArgument, key,
                        std::string(key) + " has " + std::to_string(path->size()) + " bytes, more than the limit of " +
                            std::to_string(kMaxFreeTextBytes));
  }
  if (config.role != "primary" && config.role != "standby") {
    return make_error(ErrorCode::kInvalidArgument, "service.role", "'" + config.role + "' is not one of primary, standby");
  }
  if (!config.shard_group.empty() && config.role == "standby") {
    return make_error(ErrorCode::kInvalidArgument, "service.shard_group",
                      "'" + config.shard_group + "' with service.role standby: a shard has no hot standby (its vehicles "
                      "move to the other shards when it dies); run shards as primaries");
  }
  if (config.primary_strength <= config.standby_strength) {
    return make_error(ErrorCode::kInvalidArgument, "dds.primary_strength",
                      "is " + std::to_string(config.primary_strength) + ", not above dds.standby_strength (" +
                          std::to_string(config.standby_strength) + "): ground stations would not prefer the primary");
  }
  return Status::success();
}

Result<DaemonConfig> loadDaemonConfig(const std::string& path, DaemonConfig defaults) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kFileNotFound, path, "cannot read the configuration file " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return parseDaemonConfig(text.str(), path, std::move(defaults));
}

namespace {

// A TOML basic string that parses back to `text` (toml++'s own formatter picks a literal string
// for some texts with quotes, which its parser then refuses: found by the config fuzzer).
std::string tomlBasicString(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (c == '\n') {
      quoted += "\\n";
    } else if (c == '\t') {
      quoted += "\\t";
    } else if (byte < 0x20 || byte == 0x7F) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04X", byte);
      quoted += escape;
    } else {
      quoted += c;
    }
  }
  return quoted + "\"";
}

}  // namespace

std::string describeDaemonConfig(const DaemonConfig& config) {
  DaemonConfig copy = config;
  IntegerShadow shadow = shadowOf(copy);
  const std::vector<Key> keys = keysOf(copy, shadow);
  std::ostringstream out;
  out << "# skyrouted configuration (TOML). Every key is optional; shown with its current value.\n";
  std::string section;
  for (const Key& k : keys) {
    if (section != k.section) {
      section = k.section;
      out << "\n[" << section << "]\n";
    }
    out << "# " << k.doc << "\n" << k.name << " = ";
    if (auto* d = std::get_if<double*>(&k.target)) {
      std::ostringstream v;
      v << **d / k.scale;
      std::string text = v.str();
      if (text.find_first_of(".e") == std::string::npos && text.find("inf") == std::string::npos) text += ".0";
      out << text;
    } else if (auto* i = std::get_if<std::int64_t*>(&k.target)) {
      out << **i;
    } else if (auto* b = std::get_if<bool*>(&k.target)) {
      out << (**b ? "true" : "false");
    } else if (auto* s = std::get_if<std::string*>(&k.target)) {
      out << tomlBasicString(**s);
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace skyroute
