// HAB-PP (Heterogeneous-Ants-Based Path Planner, Lee 2017) and Improved HAB-PP (Lee 2019, seed
// 004: HAB-PP plus an RRT* species sharing the pheromone field). An any-angle global planner on a
// GridLayer: ants of several species walk from the start to the goal by roulette-wheel selection
// with the modified transition probability of eq. (1); arrived paths are pruned, crossed over,
// ranked by eq. (2) in a list of N_R paths, and laid down as pheromone by eqs. (3) and (4) with the
// interpolation of Fig. 3. The planner stops when the ranked list stops changing.
//
// Points are cell centres (integer coordinates); a path is a polyline of cell centres whose every
// segment passes GridLayer::lineOfSight.
//
// Where seed 004 defers a detail to the earlier paper [19], which we do not have, we chose; every
// such choice is marked "Choice:" below and in the hab_pp*.cpp files and has a test in
// tests/planning/colony/hab_pp_test.cpp.
#pragma once

#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include "planning/core/result.hpp"
#include "planning/core/termination.hpp"
#include "terrain/grid_layer.hpp"

namespace skyroute {

// Parameters, named as in Table 2 and section 5. Defaults are the paper's values (section 5) with
// the RRT* species off (N_RA = 0, the original HAB-PP); HabPpParameters::improved() turns it on.
struct HabPpParameters {
  // Colony (section 5). Species, Choice (Table 1 names them, [19] defines them):
  //   SA  simple ant: moves one cell, to one of its 8 neighbours (a 3x3 sight window).
  //   GA  general ant: moves to a point on the border of a window of radius general_radius.
  //   FA  far-sighted ant: the same with far_sighted_radius.
  //   SGA, SFA: GA and FA with the dynamic sight expansion principle (see sightRadius()).
  int simple_ants = 100;             // N_SA
  int general_ants = 30;             // N_GA
  int far_sighted_ants = 30;         // N_FA
  int sight_general_ants = 5;        // N_SGA
  int sight_far_sighted_ants = 5;    // N_SFA
  int rrt_ants = 0;                  // N_RA: RRT* trees growing one node per ant step (section 4)
  int crossover_paths = 5;           // N_P: best ranked paths crossed with each new arrival
  int ranked_paths = 30;             // N_R: size of the ranked list L_R

  double alpha = 2.0;                // pheromone exponent of eq. (1)
  double beta = 1.0;                 // visibility exponent of eq. (1)
  double gamma = 1.0;                // angle-change exponent of eq. (1)
  double rho = 0.1;                  // evaporation of eq. (3), in (0, 1)
  double k_mix = 0.8;                // weight of goal closeness against obstacle clearance in the MVF
  double d0_cells = 2.0;             // clearance (cells) beyond which obstacles no longer lower the MVF
  double w_length = 1.0 / 3.0;       // w_L of eq. (2)
  double w_angle = 1.0 / 3.0;        // w_A of eq. (2)
  double w_points = 1.0 / 3.0;       // w_P of eq. (2)
  double rrt_step_cells = 30.0;      // s_RRT: longest extension of the RRT* species, in cells
  double rrt_near_radius_cells = 30.0;  // r_RRT: RRT* choose-parent and rewire radius, in cells

  // Choices for what the seed leaves to [19] (all in cells, radians or iterations):
  int general_radius = 2;            // GA sight window radius (Chebyshev), cells
  int far_sighted_radius = 4;        // FA sight window radius, cells
  int sight_max_radius = 12;         // largest window the dynamic sight expansion may open, cells
  double pheromone_min = 0.05;       // lower limit of the cumulative pheromone (Table 1), keeps exploring
  double pheromone_max = 1.0;        // upper limit (Table 1, "normalized pheromone trail value")
  double angle_factor_floor = 0.05;  // xi never drops below this, so a U-turn stays possible
  double angle_eval_epsilon_rad = 0.1;  // added to f_A in eq. (2) so a straight path does not divide by 0
  int stable_iterations = 60;        // L_R unchanged this many iterations stops the plan (see planHabPp)
  int max_ant_steps = 0;             // an ant that walked this many steps restarts; 0: 2 * (width + height)
  int crossover_points = 2;          // crossings used per pair of paths in the path crossover
  // An RRT* tree starts over from its root after this many nodes past its first path, so it keeps
  // bringing fresh paths; 0 (default): never, the tree keeps growing and rewiring as in Table 3, so
  // its path keeps improving and its branches, which the ants join, keep getting shorter.
  int rrt_nodes_after_solution = 0;
  // Near set of the RRT* species, Choice: Table 3's Near(x_new, V) is the nodes within r_RRT, of
  // which only the k = ceil(2e ln(n + 1)) nearest are kept (n nodes; the k-nearest RRT* of Karaman
  // and Frazzoli), so choose-parent and rewire stay O(log n) while a tree fills a large map (on the
  // 160x170 apartment map a tree grows to ~17 000 nodes before a first path, and r_RRT = 30 holds
  // ~1 800 of them: the trees cost 3x the 170 ants per iteration; with the cap ~1.2x).
  // false: all nodes within r_RRT.
  bool rrt_near_nearest = true;
  // Draws of x_rand per RRT* step, Choice: a draw that cannot grow the tree (the sample or the
  // steered point is already a node) is redrawn, up to this many draws in all.
  int rrt_draws_per_step = 8;
  // Samples that land on a node of the tree (option, default 0): rejected by one lookup and drawn
  // again without counting towards rrt_draws_per_step, up to this many times per step. Once the
  // ranked routes hold most of the pheromone (~96 % of the wheel on office) and the tree covers
  // them, nearly every draw lands on a node and the tree grows about one node in four steps; with
  // 64 such redraws about one per step, mostly through the floor part of the wheel. Measured (30
  // runs): office length +9.4 % -> +5.8 % against Theta*, Boston +2.1 % -> +1.8 %, but office's
  // total time goes from -22 % to +6 % against HAB-PP (the plan runs ~120 iterations longer).
  int rrt_node_redraws = 0;
  // One tree for the species, Choice: the N_RA RRT* ants grow one tree together, each adding one
  // node per ant step (section 4: the species grows its tree "one node at a time" in step with the
  // ants), as the other species share one pheromone field. One tree of 5n nodes reaches across a
  // map long before the first of five trees of n nodes does. false: each RRT* ant grows its own.
  bool rrt_shared_tree = true;
  // Root of the tree, DEPARTURE from Table 3 (V <- {x_start}): the tree grows from the goal, and a
  // path it finds (when it reaches the start) is handed over reversed. Together with
  // rrt_ants_join_tree this makes the species meet the ants half way. false: rooted at the start.
  bool rrt_tree_from_goal = true;
  // Ants finish along the tree, DEPARTURE from section 4 (which shares paths only through the
  // pheromone field and the ranked list): while the ranked list holds fewer than N_R paths, an ant
  // that steps onto a tree node, or next to one in sight, completes its path along the tree's
  // branch to the goal; the path is pruned and ranked like any arrival. Needs rrt_tree_from_goal.
  // Why: on maze-like maps (Moving AI 8room: one-cell doors) a tree from the start needs ~12 500
  // nodes to reach the goal, several times what the ants need, so the species as published never
  // brings the first path there (docs/benchmarks/habpp.md measures both).
  bool rrt_ants_join_tree = true;
  // The species rests once the ranked list holds N_R paths (option, default off): section 4 gives
  // the trees fast first paths and leaves optimising them to the ants, and a tree step costs as
  // much as tens of ant steps, so resting makes the plan faster (office -34 % total time against
  // -20 %) but the trees no longer improve the routes (Boston +3.5 % length against +2.1 %).
  bool rrt_rest_when_full = false;
  // Sampling of the RRT* species, Choice: x_rand by roulette wheel over the free cells with weight
  // tau^alpha * eta^beta (the cell terms of eq. (1)), so a tree from the start keeps the colony's
  // pull towards the goal after the initial pheromone (tau = eta) has evaporated. false (default):
  // weight tau^alpha alone, as section 4 says; a tree from the goal gains nothing from the pull.
  bool rrt_sample_visibility = false;
  // Stopping rule of Improved HAB-PP, Choice: in an iteration in which only RRT* paths arrived, the
  // ranked list counts as changed only when its top N_P paths (the crossover parents, which steer
  // the colony) changed. Section 4 gives the RRT* species fast first paths and leaves optimising to
  // the ants; a growing tree keeps bringing slightly shorter paths that enter low in the list and
  // would otherwise keep restarting the count.
  // false: every change counts, as for the ants. No effect without RRT* ants.
  bool rrt_stop_top_paths = true;
  // Passes of vertex relocation in the arrival pruning (see habpp::tightenPath); 0: greedy pruning only.
  int tighten_passes = 64;
  // Output stage (planning/colony/hab_pp_output.hpp): the best ranked path is made taut in a corridor of
  // this many cells around its route once the colony stops; -1: the stage is off (the output is
  // the best ranked path as it is), 0: greedy shortcut and vertex relaxation only.
  int output_corridor_cells = 2;
  // Output stage, Choice: the corridor is the union of the corridors of this many top ranked paths
  // (1: the best ranked path's alone). The ranked list under eq. (2), with the paper's equal
  // weights, puts fewer points and less turning above length, so the shortest route the colony
  // holds is often not the first; the union lets the stage take it (see tautPath).
  int output_ranked_routes = 30;
  // Output stage, Choice: the corridor also holds the shortest path the RRT* species brought
  // (pruned as on arrival), which eq. (2) may have kept out of the ranked list for its number of
  // points. false: the ranked routes only.
  bool output_tree_route = true;
  // Output stage, Choice: local search by windowed re-planning after the corridor step
  // (habpp::replanWindows): windows of output_window_segments path segments (or of at least
  // output_window_cells path length), re-planned by Theta* in the box around them grown by
  // output_window_margin_cells. Where the colony went round the wrong side of an obstacle within a
  // few turns it takes the other side: with 3 segments, Boston +1.9 % -> +0.5 % against Theta*,
  // office +8.8 % -> +6.2 %, apartment +20.6 % -> +14.4 % (docs/benchmarks/habpp.md). A door
  // sequence across many rooms stays the colony's choice: windows long enough to change it (120
  // cells of path on office) make the step Theta* on the path's bounding box, so output_window_cells
  // is 0 by default. Both 0: off.
  int output_window_segments = 3;
  double output_window_cells = 0.0;
  int output_window_margin_cells = 8;
  // Goal closeness in the visibility field eta (see GridFields::visibility): false, the straight-line
  // distance to the goal; true, the shortest 8-connected grid distance around the obstacles.
  bool geodesic_visibility = false;

  // The improved planner of seed 004: the same colony plus N_RA = 5 RRT* ants (one tree from the
  // goal that the ants may join, see above).
  static HabPpParameters improved() {
    HabPpParameters p;
    p.rrt_ants = 5;
    return p;
  }
  // Section 4 as published: five trees from the start, sharing paths only through the pheromone
  // field and the ranked list, growing in every iteration.
  static HabPpParameters improvedAsPublished() {
    HabPpParameters p = improved();
    p.rrt_shared_tree = false;
    p.rrt_tree_from_goal = false;
    p.rrt_ants_join_tree = false;
    p.rrt_rest_when_full = false;
    return p;
  }
  int totalAnts() const {
    return simple_ants + general_ants + far_sighted_ants + sight_general_ants + sight_far_sighted_ants;
  }
  // An error naming the first parameter out of range.
  Status validate() const;
};

enum class HabPpStatus {
  kConverged,            // the ranked list stopped changing: path is the best ranked path
  kStoppedWithPath,      // the termination condition stopped it after a path was found (best so far)
  kStoppedWithoutPath,   // the termination condition stopped it before any path reached the goal
  kInvalidStart,         // start outside the grid or blocked
  kInvalidGoal,          // goal outside the grid or blocked
  kUnreachable,          // no chain of free cells joins start and goal (checked before the search)
  kInvalidParameters,    // HabPpParameters::validate failed (message in HabPpResult::message)
};

std::string_view to_string(HabPpStatus status);
inline bool hasPath(HabPpStatus s) { return s == HabPpStatus::kConverged || s == HabPpStatus::kStoppedWithPath; }

struct HabPpResult {
  HabPpStatus status = HabPpStatus::kStoppedWithoutPath;
  std::string message;               // why it failed, naming the field, when it did
  std::vector<GridCell> path;        // best ranked path after the output stage, start first, any-angle segments
  double length_cells = 0.0;         // Euclidean length of path, in cell edges
  double ranked_length_cells = 0.0;  // length of the best ranked path before the output stage
  double angle_change_rad = 0.0;     // sum of turning angles of path
  double first_path_time_s = -1.0;   // time until the first path entered the ranked list; -1 if none
  double total_time_s = 0.0;
  // The same two times in processor time of this process (std::clock), which other processes on a
  // shared machine do not inflate; the benchmark reports these.
  double first_path_cpu_s = -1.0;
  double total_cpu_s = 0.0;
  std::uint64_t iterations = 0;      // n_I
  std::uint64_t first_path_iteration = 0;
  bool first_path_by_rrt = false;    // an RRT* tree brought a path in the first path's iteration
  bool first_path_by_join = false;   // an ant that joined a tree brought a path in that iteration
  std::uint64_t ant_arrivals = 0;    // paths brought by the ants (joined ones included)
  std::uint64_t joined_arrivals = 0;  // of those, paths an ant completed along a tree
  std::uint64_t rrt_arrivals = 0;    // paths brought by the RRT* species
  std::uint64_t rrt_steps = 0;       // nodes the RRT* ants tried to add (one per RRT* ant per iteration until they rest)
  std::uint64_t crossover_children = 0;  // valid paths made by the path crossover
  TerminationCondition::Reason stop_reason = TerminationCondition::Reason::kNone;
};

// The planner's entry point: HAB-PP when params.rrt_ants == 0, Improved HAB-PP otherwise.
// Same grid, endpoints, parameters and seed give the same result (time aside).
HabPpResult planHabPp(const GridLayer& grid, GridCell start, GridCell goal, const HabPpParameters& params,
                      std::uint64_t seed, const TerminationCondition& stop = {});

// ---- Building blocks, exposed for the tests and for the RRT* species -----------------------------
namespace habpp {

using Rng = std::mt19937_64;
using Path = std::vector<GridCell>;

// Cells whose closed square the segment a-b touches, in order from a to b, each once (the cells
// GridLayer::lineOfSight examines). Used for the pheromone interpolation of Fig. 3 and crossover.
std::vector<GridCell> segmentCells(GridCell a, GridCell b);

// Fields precomputed once per plan (the grid does not change during a plan).
class GridFields {
 public:
  GridFields(const GridLayer& grid, GridCell goal, const HabPpParameters& params);
  const GridLayer& grid() const { return *grid_; }
  GridCell goal() const { return goal_; }
  // Modified visibility field (Table 1, MVF), in (0, 1]. Choice: eta_j = k_mix * closeness_j +
  // (1 - k_mix) * clearance_j, closeness_j = 1 - |j - g| / (largest |c - g| over the grid),
  // clearance_j = min(1, distance from j to the nearest blocked cell / d_0); floored at 1e-3.
  double visibility(GridCell c) const { return visibility_[grid_->index(c)]; }
  // True when every cell of the (2r+1)^2 window around c is inside the grid and free (O(1)).
  bool windowFree(GridCell c, int r) const;
  // Line of sight from c to each point of the border of its window of radius r (2 to
  // kMaxCachedRadius), one bit per point in candidates()' order (rows -r and +r by x, then columns
  // -r and +r by y); a point outside the grid or blocked has bit 0. Computed once per cell and
  // radius and cached: the ants stand on the same cells again and again, so candidates() reads a
  // mask instead of repeating lineOfSight. The cache makes GridFields unsafe to share between
  // threads (each plan builds its own).
  static constexpr int kMaxCachedRadius = 4;
  std::uint32_t borderSight(GridCell c, int r) const;

 private:
  const GridLayer* grid_;
  GridCell goal_;
  mutable std::vector<std::uint32_t> border_sight_;  // kMaxCachedRadius - 1 masks per cell
  mutable std::vector<std::uint8_t> border_known_;   // bit r - 2: that mask is computed
  std::vector<double> visibility_;
  std::vector<int> blocked_prefix_;  // summed-area table of blocked cells, (w+1) x (h+1)
};

// Dynamic sight expansion principle, Choice: an expanding ant's window grows from its base radius
// one ring at a time while the whole window stays free, up to max_radius. In open space the ant
// sees (and strides) far and walks straight; near obstacles it falls back to its base window.
int sightRadius(const GridFields& fields, GridCell at, int base_radius, bool expanding, int max_radius);

// Candidate set C of eq. (1), Choice: the points on the border of the window of radius r that are
// free, not yet visited by this ant (visited[cell index] != 0) and in line of sight; when none, the radius
// shrinks by one until some exist (radius 1 = the 8 neighbours). When the goal lies inside the
// window and is in sight, it is the only candidate. Empty: the ant is stuck.
std::vector<GridCell> candidates(const GridFields& fields, GridCell at, int radius,
                                 const std::vector<std::uint8_t>& visited);
// The same into a caller's buffer (cleared first), so the ants' steps allocate nothing.
void candidates(const GridFields& fields, GridCell at, int radius, const std::vector<std::uint8_t>& visited,
                std::vector<GridCell>& out);

// Angle-change factor xi of eq. (1), Choice: (1 + cos theta) / 2, theta the angle between the
// ant's heading and the step at -> to, floored at `floor`. No heading (zero vector): 1.
double angleFactor(double heading_x, double heading_y, GridCell at, GridCell to, double floor);

// Roulette-wheel selection: index i with probability weights[i] / sum. weights must not all be 0.
std::size_t rouletteSelect(const std::vector<double>& weights, Rng& rng);

// Path pruning, Choice: after each step, drop the previous point while the point before it sees
// the new one (string pulling); on arrival the whole path is pruned greedily (from each point jump
// to the farthest visible later point).
void pruneLastStep(const GridLayer& grid, Path& path);
Path prunePath(const GridLayer& grid, const Path& path);

// Path pruning on arrival, Choice (stronger than [19]'s, so lengths approach the any-angle
// optimum of the path's route): prunePath, then local string pulling by vertex relocation: each
// interior vertex moves to the neighbouring free cell centre (8-neighbourhood) that shortens its
// two segments most while both stay in sight, and a vertex whose neighbours see each other is
// dropped; passes repeat until one changes nothing (at most max_passes). Every change keeps all
// segments in sight and strictly shortens the path, so it ends; the vertices end next to the
// obstacle corners the path bends round, as Theta*'s do.
Path tightenPath(const GridLayer& grid, const Path& path, int max_passes);

// Path crossover, Choice: two paths cross where their interpolated cells (segmentCells) share a
// cell other than start and goal. At up to `max_points` such crossings (spread evenly over the
// crossings found) the heads and tails are swapped through the shared cell; children whose new
// segments fail the line-of-sight check are dropped; the rest are pruned.
std::vector<Path> crossover(const GridLayer& grid, const Path& a, const Path& b, int max_points);

// Eq. (2) over a list: f_L, f_A (+ epsilon), f_P of each path normalised by the best (smallest)
// value in the list, weighted. Returns one value in (0, 1] per path; larger is better.
std::vector<double> evaluate(const std::vector<Path>& paths, const HabPpParameters& params);

// Pheromone field tau (one value per cell), eqs. (3) and (4) with the Fig. 3 interpolation.
class PheromoneField {
 public:
  PheromoneField(const GridFields& fields, const HabPpParameters& params);  // tau <- eta (free cells)
  double at(GridCell c) const { return tau_[fields_->grid().index(c)]; }
  // tau_j <- clamp((1 - rho) tau_j + sum over ranked paths of rho * f_Eval(path) on every cell the
  // path's segments touch (each cell once per path), to [pheromone_min, pheromone_max].
  // Choice: the deposit of a path is rho * f_Eval, so a cell on a path of value 1 tends to the cap.
  void update(const std::vector<Path>& ranked, const std::vector<double>& evaluation);
  // The same with each path given as its touched cells' indices, each once (pathCells): the
  // colony keeps these for its ranked paths instead of re-walking every segment each iteration.
  void updateCells(const std::vector<std::vector<std::uint32_t>>& ranked_cells, const std::vector<double>& evaluation);
  // The indices of the cells the path's segments touch (Fig. 3), each once, in path order.
  std::vector<std::uint32_t> pathCells(const Path& path);
  // Roulette-wheel choice of a free cell with probability proportional to tau^alpha (the RRT*
  // species' sampling). Most cells sit at the floor pheromone_min, so the wheel has two parts: the
  // floor (every free cell, pheromone_min^alpha each: a uniform draw) and the excess
  // tau^alpha - pheromone_min^alpha of the cells above it, a cumulative table over those cells only,
  // rebuilt on the first draw after each update. One random number picks the part and the cell.
  GridCell sample(Rng& rng) const;
  // The same with weight tau^alpha * eta^beta (HabPpParameters::rrt_sample_visibility). The floor
  // part is a fixed cumulative table of pheromone_min^alpha * eta^beta over the free cells.
  GridCell sampleWithVisibility(Rng& rng) const;
  // Cells above the floor now (the rest hold exactly pheromone_min). Exposed for the tests.
  std::size_t activeCount() const { return active_.size(); }

 private:
  const GridFields* fields_;
  HabPpParameters params_;
  std::vector<double> tau_;
  std::vector<std::size_t> free_cells_;
  std::vector<std::uint32_t> stamp_;  // per-cell marker, so each path deposits once per cell
  std::uint32_t stamp_now_ = 0;
  // The update touches only the cells above the floor and the deposited ones (a cell at the floor
  // that gets nothing stays at the floor: (1 - rho) * min clamps back to min), with the same
  // arithmetic, in the same order per cell, as a pass over every cell.
  std::vector<std::uint32_t> active_;   // cells with tau > pheromone_min
  std::vector<std::uint8_t> in_active_;
  mutable std::vector<double> excess_cumulative_;   // running sum of the excess over excess_cells_
  mutable std::vector<std::uint32_t> excess_cells_;  // the active cells (all free), in active_ order
  // Which weighting the excess table holds; the update makes it stale.
  enum class ExcessTable : std::uint8_t { kStale, kPheromoneOnly, kWithEta };
  mutable ExcessTable excess_table_ = ExcessTable::kStale;
  std::vector<double> eta_beta_;             // eta^beta per cell (free cells), for sampleWithVisibility
  std::vector<double> floor_eta_cumulative_;  // running sum of eta^beta over free_cells_
  // sample() (with_eta false: the floor part is a uniform draw) and sampleWithVisibility() (true:
  // the floor part and the excess weighted by eta^beta).
  GridCell sampleWeighted(Rng& rng, bool with_eta) const;
  void nextStamp();
};

}  // namespace habpp
}  // namespace skyroute
