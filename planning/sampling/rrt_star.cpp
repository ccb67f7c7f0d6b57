#include "planning/sampling/rrt_star.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

// nanoflann 1.4 copies a bounding box GCC cannot prove initialised (it is, before use).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop

namespace skyroute {

double rrtStarRewireRadius(std::size_t n, int dimension, double free_volume, double rewire_factor) {
  if (n < 2) return std::numeric_limits<double>::infinity();
  const double d = dimension;
  // Volume of the unit d-ball: pi^(d/2) / Gamma(d/2 + 1).
  const double unit_ball = std::pow(std::numbers::pi, d / 2.0) / std::tgamma(d / 2.0 + 1.0);
  const double gamma_min = 2.0 * std::pow(1.0 + 1.0 / d, 1.0 / d) * std::pow(free_volume / unit_ball, 1.0 / d);
  const double nd = static_cast<double>(n);
  return rewire_factor * gamma_min * std::pow(std::log(nd) / nd, 1.0 / d);
}

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::uint32_t kNoParent = std::numeric_limits<std::uint32_t>::max();

struct Node {
  Eigen::Vector3d p;
  double cost = 0.0;  // path length from the start through the tree
  std::uint32_t parent = kNoParent;
  std::vector<std::uint32_t> children;
};

// nanoflann's view of the tree's node positions.
struct NodeCloud {
  const std::vector<Node>* nodes = nullptr;
  std::size_t kdtree_get_point_count() const { return nodes->size(); }
  double kdtree_get_pt(std::size_t idx, std::size_t dim) const { return (*nodes)[idx].p[static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexDynamicAdaptor<nanoflann::L2_Simple_Adaptor<double, NodeCloud>,
                                                          NodeCloud, 3, std::size_t>;

// Uniform doubles from the generator with a fixed recipe (53 random bits), so results do not depend
// on the standard library's distribution implementation.
class Sampler {
 public:
  explicit Sampler(std::uint64_t seed) : rng_(seed) {}
  double uniform01() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }
  Eigen::Vector3d inBox(const Eigen::AlignedBox3d& box) {
    const double x = uniform(box.min().x(), box.max().x());
    const double y = uniform(box.min().y(), box.max().y());
    const double z = uniform(box.min().z(), box.max().z());
    return {x, y, z};
  }
  Eigen::Vector3d inUnitBall() {
    for (;;) {
      const Eigen::Vector3d v(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
      if (v.squaredNorm() <= 1.0) return v;
    }
  }

 private:
  std::mt19937_64 rng_;
};

// The informed set of a path of length c_best: points x with |x - start| + |x - goal| <= c_best,
// a prolate spheroid with foci start and goal.
class InformedSet {
 public:
  InformedSet(const Eigen::Vector3d& start, const Eigen::Vector3d& goal) : start_(start), goal_(goal) {
    centre_ = 0.5 * (start + goal);
    c_min_ = (goal - start).norm();
    // Rotation taking the x axis to the start -> goal direction.
    const Eigen::Vector3d axis = c_min_ > 0 ? Eigen::Vector3d((goal - start) / c_min_) : Eigen::Vector3d::UnitX();
    rotation_ = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), axis).toRotationMatrix();
  }
  double cMin() const { return c_min_; }
  bool contains(const Eigen::Vector3d& x, double c_best) const {
    return (x - start_).norm() + (x - goal_).norm() <= c_best;
  }
  double volume(double c_best) const {
    const double a = 0.5 * c_best;
    const double b = 0.5 * std::sqrt(std::max(0.0, c_best * c_best - c_min_ * c_min_));
    return 4.0 / 3.0 * std::numbers::pi * a * b * b;
  }
  // Uniform in the spheroid (the caller rejects points outside the sampling box).
  Eigen::Vector3d sample(Sampler& s, double c_best) const {
    const double a = 0.5 * c_best;
    const double b = 0.5 * std::sqrt(std::max(0.0, c_best * c_best - c_min_ * c_min_));
    const Eigen::Vector3d u = s.inUnitBall();
    return centre_ + rotation_ * Eigen::Vector3d(a * u.x(), b * u.y(), b * u.z());
  }

 private:
  Eigen::Vector3d start_, goal_, centre_;
  double c_min_ = 0.0;
  Eigen::Matrix3d rotation_;
};

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

std::string describe(const Eigen::Vector3d& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + ")";
}

// One planning run: the tree, its k-d index and the best solution so far.
class Search {
 public:
  Search(const MotionValidator& validator, const RrtStarOptions& options, const Eigen::AlignedBox3d& bounds,
         const Eigen::Vector3d& start, const Eigen::Vector3d& goal, double max_step)
      : validator_(validator),
        options_(options),
        bounds_(bounds),
        goal_(goal),
        max_step_(max_step),
        sampler_(options.seed),
        informed_(start, goal),
        cloud_{&nodes_},
        index_(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    box_volume_ = bounds.volume();
    guided_ = !options.guide_m.empty() && options.guide_bias > 0.0;
    addNode(start, kNoParent, 0.0);
  }

  // Takes over a seed tree's nodes after the root (parents come first, so each one's parent is
  // in the tree already), then connects the cheapest node near the goal whose motion to it is
  // valid: a seed that reaches the goal's neighbourhood is a solution before any sample.
  void seedFrom(const RrtTree& seed, RrtStarResult& result, Clock::time_point t0) {
    nodes_.reserve(seed.size());
    for (std::size_t i = 1; i < seed.size(); ++i) addNode(seed.positions_m[i], seed.parents[i], seed.costs_m[i]);
    std::vector<std::pair<std::size_t, double>> near;
    nearWithin(goal_, max_step_, near);
    std::vector<std::pair<double, std::uint32_t>> by_cost;
    for (const auto& [idx, d2] : near) {
      by_cost.emplace_back(nodes_[idx].cost + std::sqrt(d2), static_cast<std::uint32_t>(idx));
    }
    std::sort(by_cost.begin(), by_cost.end());
    for (const auto& [c_cost, c] : by_cost) {
      if ((nodes_[c].p - goal_).norm() == 0.0 || motionValid(nodes_[c].p, goal_)) {
        goal_parents_.push_back(c);
        break;
      }
    }
    updateBestSolution(result, t0);
  }

  // The tree as data, parents before children (rewiring may have given a node a younger parent).
  void exportTree(RrtTree& out) const {
    out.positions_m.clear();
    out.parents.clear();
    out.costs_m.clear();
    std::vector<std::uint32_t> new_index(nodes_.size(), kNoParent);
    std::vector<std::uint32_t> order{0};
    new_index[0] = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
      for (std::uint32_t c : nodes_[order[k]].children) {
        new_index[c] = static_cast<std::uint32_t>(order.size());
        order.push_back(c);
      }
    }
    out.positions_m.reserve(order.size());
    out.parents.reserve(order.size());
    out.costs_m.reserve(order.size());
    for (std::uint32_t v : order) {
      out.positions_m.push_back(nodes_[v].p);
      out.parents.push_back(nodes_[v].parent == kNoParent ? kRrtTreeNoParent : new_index[nodes_[v].parent]);
      out.costs_m.push_back(nodes_[v].cost);
    }
  }

  void run(const TerminationCondition& stop, const TerminationCondition* outer, RrtStarResult& result,
           Clock::time_point t0) {
    std::vector<std::pair<std::size_t, double>> near;
    std::vector<std::uint32_t> candidates;
    std::vector<std::pair<double, std::uint32_t>> by_cost;
    while (true) {
      result.stop_reason = stop.reason(result.iterations);
      if (result.stop_reason == TerminationCondition::Reason::kNone && outer) {
        result.stop_reason = outer->reason(result.iterations);
      }
      if (result.stop_reason != TerminationCondition::Reason::kNone) break;
      if (options_.max_nodes != 0 && nodes_.size() >= options_.max_nodes) {
        result.node_budget_reached = true;
        break;
      }
      ++result.iterations;

      const Eigen::Vector3d x_rand = sample();
      const std::uint32_t nearest = nearestNode(x_rand);
      Eigen::Vector3d x_new = x_rand;
      const Eigen::Vector3d to_rand = x_rand - nodes_[nearest].p;
      const double d_rand = to_rand.norm();
      if (d_rand < 1e-9) continue;
      if (d_rand > max_step_) x_new = nodes_[nearest].p + to_rand * (max_step_ / d_rand);
      if (!validator_.isStateValid(x_new)) continue;
      if (!motionValid(nodes_[nearest].p, x_new)) continue;

      // ChooseBestParent: cheapest neighbour (by cost through it) with a valid motion; the nearest
      // node is known valid, so candidates costlier than it need no check.
      if (options_.k_nearest) {
        nearestK(x_new, rewireK(), near);
      } else {
        nearWithin(x_new, std::min(max_step_, rewireRadius()), near);
      }
      candidates.clear();
      for (const auto& [idx, d2] : near) candidates.push_back(static_cast<std::uint32_t>(idx));
      if (std::find(candidates.begin(), candidates.end(), nearest) == candidates.end()) candidates.push_back(nearest);
      by_cost.clear();
      for (std::uint32_t c : candidates) by_cost.emplace_back(nodes_[c].cost + (nodes_[c].p - x_new).norm(), c);
      std::sort(by_cost.begin(), by_cost.end());
      std::uint32_t parent = nearest;
      double cost = nodes_[nearest].cost + (nodes_[nearest].p - x_new).norm();
      for (const auto& [c_cost, c] : by_cost) {
        if (c == nearest) break;
        if (motionValid(nodes_[c].p, x_new)) {
          parent = c;
          cost = c_cost;
          break;
        }
      }
      const std::uint32_t added = addNode(x_new, parent, cost);

      // Rewire: neighbours reached more cheaply through the new node take it as their parent.
      // With skip_hopeless_checks, a neighbour that even then cannot lie on a path shorter than
      // the best one (its cost plus the straight line to the goal is no shorter) is skipped: no
      // path through it or its subtree can beat the best, so the motion check would buy nothing.
      const double hopeless_m = options_.skip_hopeless_checks ? best_cost_ : std::numeric_limits<double>::infinity();
      std::sort(candidates.begin(), candidates.end());
      for (std::uint32_t c : candidates) {
        if (c == parent) continue;
        const double through_new = cost + (nodes_[c].p - x_new).norm();
        if (through_new >= nodes_[c].cost - 1e-9) continue;
        if (through_new + (nodes_[c].p - goal_).norm() >= hopeless_m) continue;
        if (motionValid(x_new, nodes_[c].p)) reparent(c, added, through_new);
      }

      // Goal connection (with skip_hopeless_checks only when it would beat the best path so far).
      const double d_goal = (x_new - goal_).norm();
      if (d_goal <= max_step_ && cost + d_goal < hopeless_m - 1e-9 && (d_goal == 0.0 || motionValid(x_new, goal_))) {
        goal_parents_.push_back(added);
      }
      updateBestSolution(result, t0);
    }
  }

  void fillResult(RrtStarResult& result, bool allow_approximate) const {
    result.tree_size = nodes_.size();
    if (best_goal_parent_ != kNoParent) {
      result.path_m = pathTo(best_goal_parent_);
      if ((result.path_m.back() - goal_).norm() > 0.0) result.path_m.push_back(goal_);
      result.length_m = polylineLength(result.path_m);
      result.distance_to_goal_m = 0.0;
      result.status = PlannerStatus::kSolved;
      return;
    }
    if (allow_approximate) {
      std::uint32_t closest = 0;
      double best = (nodes_[0].p - goal_).norm();
      for (std::uint32_t i = 1; i < nodes_.size(); ++i) {
        const double d = (nodes_[i].p - goal_).norm();
        if (d < best) best = d, closest = i;
      }
      if (closest != 0) {
        result.path_m = pathTo(closest);
        result.length_m = polylineLength(result.path_m);
        result.distance_to_goal_m = best;
        result.status = PlannerStatus::kApproximate;
        return;
      }
    }
    result.distance_to_goal_m = (nodes_[0].p - goal_).norm();
    switch (result.stop_reason) {
      case TerminationCondition::Reason::kDeadline: result.status = PlannerStatus::kTimeout; break;
      case TerminationCondition::Reason::kCancelled: result.status = PlannerStatus::kCancelled; break;
      default: result.status = PlannerStatus::kBudgetExhausted; break;
    }
  }

  std::uint64_t motionChecks() const { return motion_checks_; }

  // k-nearest RRT*: k = ceil(rewire_factor * e * (1 + 1/d) * log n), n the nodes that count for the
  // radius (the informed set's once a path exists, as rewireRadius()).
  std::size_t rewireK() const {
    const double n = static_cast<double>(informedActive() ? informed_nodes_ + 1 : nodes_.size() + 1);
    const double k_rrt = options_.rewire_factor * std::numbers::e * (1.0 + 1.0 / 3.0);
    return static_cast<std::size_t>(std::ceil(k_rrt * std::log(std::max(n, 2.0))));
  }

  // Karaman and Frazzoli's radius for the space where samples are drawn now. Once a path exists
  // that is the informed set (when smaller than the box), and only the nodes inside it count, as
  // in OMPL's InformedRRTstar with pruning: the formula assumes n uniform samples over the volume,
  // and with the box's volume and all nodes the samples packed into a thin spheroid would give
  // near sets of thousands of nodes (each one sorted and many checked per iteration).
  double rewireRadius() const {
    if (!informedActive()) return rrtStarRewireRadius(nodes_.size() + 1, 3, box_volume_, options_.rewire_factor);
    return rrtStarRewireRadius(informed_nodes_ + 1, 3, std::min(box_volume_, informed_.volume(best_cost_)),
                               options_.rewire_factor);
  }

 private:
  bool motionValid(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    ++motion_checks_;
    return validator_.isMotionValid(a, b);
  }

  std::uint32_t addNode(const Eigen::Vector3d& p, std::uint32_t parent, double cost) {
    const auto id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(Node{p, cost, parent, {}});
    pruned_.push_back(0);
    if (parent != kNoParent) nodes_[parent].children.push_back(id);
    if (informedActive() && informed_.contains(p, best_cost_)) ++informed_nodes_;
    index_.addPoints(id, id);
    return id;
  }

  void reparent(std::uint32_t node, std::uint32_t new_parent, double new_cost) {
    auto& siblings = nodes_[nodes_[node].parent].children;
    siblings.erase(std::find(siblings.begin(), siblings.end(), node));
    nodes_[new_parent].children.push_back(node);
    nodes_[node].parent = new_parent;
    const double delta = new_cost - nodes_[node].cost;
    // Every descendant's cost drops by the same amount.
    std::vector<std::uint32_t> stack{node};
    while (!stack.empty()) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      nodes_[v].cost += delta;
      for (std::uint32_t c : nodes_[v].children) stack.push_back(c);
    }
  }

  // Samples come from the informed set (and the radius follows its volume) once a path exists.
  bool informedActive() const {
    return options_.informed_sampling && best_cost_ < std::numeric_limits<double>::infinity();
  }

  Eigen::Vector3d sample() {
    if (sampler_.uniform01() < options_.goal_bias) return goal_;
    const bool no_path = best_cost_ == std::numeric_limits<double>::infinity();
    if (no_path && guided_ && sampler_.uniform01() < options_.guide_bias) return guideSample();
    if (!options_.informed_sampling || no_path) {
      return sampler_.inBox(bounds_);
    }
    // Draw from whichever of box and spheroid is smaller and reject what lies outside the other.
    const bool from_spheroid = informed_.volume(best_cost_) < box_volume_;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      if (from_spheroid) {
        const Eigen::Vector3d x = informed_.sample(sampler_, best_cost_);
        if (bounds_.contains(x)) return x;
      } else {
        const Eigen::Vector3d x = sampler_.inBox(bounds_);
        if (informed_.contains(x, best_cost_)) return x;
      }
    }
    return sampler_.inBox(bounds_);
  }

  // Near a random guide point: horizontally within the radius, vertically from its height to the top.
  Eigen::Vector3d guideSample() {
    const auto& guide = options_.guide_m;
    const std::size_t k = std::min(guide.size() - 1, static_cast<std::size_t>(sampler_.uniform01() * guide.size()));
    const Eigen::Vector3d& g = guide[k];
    const double r = options_.guide_radius_m;
    const double x = g.x() + sampler_.uniform(-r, r);
    const double y = g.y() + sampler_.uniform(-r, r);
    const double z = sampler_.uniform(std::min(g.z(), bounds_.max().z()), bounds_.max().z());
    return {x, y, z};
  }

  std::uint32_t nearestNode(const Eigen::Vector3d& x) const {
    std::size_t idx = 0;
    double d2 = 0.0;
    nanoflann::KNNResultSet<double, std::size_t> result(1);
    result.init(&idx, &d2);
    index_.findNeighbors(result, x.data(), nanoflann::SearchParams());
    return static_cast<std::uint32_t>(idx);
  }

  void nearWithin(const Eigen::Vector3d& x, double radius, std::vector<std::pair<std::size_t, double>>& out) const {
    out.clear();
    nanoflann::RadiusResultSet<double, std::size_t> result(radius * radius, out);
    index_.findNeighbors(result, x.data(), nanoflann::SearchParams(32, 0.0f, false));
  }

  void nearestK(const Eigen::Vector3d& x, std::size_t k, std::vector<std::pair<std::size_t, double>>& out) const {
    k = std::min(k, nodes_.size());
    knn_idx_.resize(k);
    knn_d2_.resize(k);
    nanoflann::KNNResultSet<double, std::size_t> result(k);
    result.init(knn_idx_.data(), knn_d2_.data());
    index_.findNeighbors(result, x.data(), nanoflann::SearchParams());
    out.clear();
    for (std::size_t i = 0; i < result.size(); ++i) out.emplace_back(knn_idx_[i], knn_d2_[i]);
  }

  void updateBestSolution(RrtStarResult& result, Clock::time_point t0) {
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_parent = kNoParent;
    for (std::uint32_t g : goal_parents_) {
      const double c = nodes_[g].cost + (nodes_[g].p - goal_).norm();
      if (c < best) best = c, best_parent = g;
    }
    if (best_parent == kNoParent || best >= best_cost_ - 1e-9) return;
    if (best_goal_parent_ == kNoParent) {
      result.first_solution_s = std::chrono::duration<double>(Clock::now() - t0).count();
      result.first_solution_iteration = result.iterations;
    }
    best_goal_parent_ = best_parent;
    best_cost_ = best;
    ++result.solution_improvements;
    if (informedActive()) {
      informed_nodes_ = 0;
      for (std::uint32_t i = 0; i < nodes_.size(); ++i) {
        if (informed_.contains(nodes_[i].p, best_cost_)) {
          ++informed_nodes_;
        } else if (options_.prune_tree && !pruned_[i]) {
          pruned_[i] = 1;
          index_.removePoint(i);
        }
      }
    }
  }

  std::vector<Eigen::Vector3d> pathTo(std::uint32_t node) const {
    std::vector<Eigen::Vector3d> path;
    for (std::uint32_t v = node; v != kNoParent; v = nodes_[v].parent) path.push_back(nodes_[v].p);
    std::reverse(path.begin(), path.end());
    return path;
  }

  const MotionValidator& validator_;
  const RrtStarOptions& options_;
  Eigen::AlignedBox3d bounds_;
  Eigen::Vector3d goal_;
  double max_step_;
  double box_volume_ = 0.0;
  bool guided_ = false;  // guide points and a positive bias
  Sampler sampler_;
  InformedSet informed_;
  std::vector<Node> nodes_;
  NodeCloud cloud_;
  KdTree index_;
  std::vector<std::uint32_t> goal_parents_;
  std::uint32_t best_goal_parent_ = kNoParent;
  double best_cost_ = std::numeric_limits<double>::infinity();
  std::size_t informed_nodes_ = 0;  // nodes inside the informed set of best_cost_
  std::uint64_t motion_checks_ = 0;
  std::vector<char> pruned_;  // 1: removed from index_ (options.prune_tree)
  mutable std::vector<std::size_t> knn_idx_;  // scratch for nearestK
  mutable std::vector<double> knn_d2_;
};

}  // namespace

RrtStar::RrtStar(const MotionValidator& validator, RrtStarOptions options)
    : validator_(validator), options_(options) {}

Result<RrtStarResult> RrtStar::plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                                    const TerminationCondition& stop) const {
  return plan(start_m, goal_m, stop, nullptr);
}

Result<RrtStarResult> RrtStar::plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                                    const TerminationCondition& stop, const TerminationCondition& outer) const {
  return plan(start_m, goal_m, stop, &outer);
}

Result<RrtStarResult> RrtStar::plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                                    const TerminationCondition& stop, const TerminationCondition& outer,
                                    RrtTree* tree_out) const {
  return plan(start_m, goal_m, stop, &outer, nullptr, tree_out);
}

Result<RrtStarResult> RrtStar::planFromTree(const RrtTree& seed, const Eigen::Vector3d& goal_m,
                                            const TerminationCondition& stop, const TerminationCondition& outer,
                                            RrtTree* tree_out) const {
  if (seed.empty()) return make_error(ErrorCode::kInvalidArgument, "seed_tree", "has no root");
  if (auto bad = seed.layoutError()) return make_error(ErrorCode::kInvalidArgument, "seed_tree", *bad);
  return plan(seed.positions_m.front(), goal_m, stop, &outer, &seed, tree_out);
}

Result<RrtStarResult> RrtStar::plan(const Eigen::Vector3d& start_m, const Eigen::Vector3d& goal_m,
                                    const TerminationCondition& stop, const TerminationCondition* outer,
                                    const RrtTree* seed, RrtTree* tree_out) const {
  const auto t0 = Clock::now();
  if (tree_out) *tree_out = RrtTree{};
  if (!finite(start_m)) return make_error(ErrorCode::kInvalidArgument, "start", "start is not finite: " + describe(start_m));
  if (!finite(goal_m)) return make_error(ErrorCode::kInvalidArgument, "goal", "goal is not finite: " + describe(goal_m));
  if (!(options_.goal_bias >= 0.0 && options_.goal_bias < 1.0)) {
    return make_error(ErrorCode::kInvalidArgument, "goal_bias", "goal_bias must be in [0, 1)");
  }
  if (!(options_.max_step_m >= 0.0) || !std::isfinite(options_.max_step_m)) {
    return make_error(ErrorCode::kInvalidArgument, "max_step_m", "max_step_m must be finite and >= 0 (0 = automatic)");
  }
  if (!(options_.rewire_factor > 1.0) || !std::isfinite(options_.rewire_factor)) {
    return make_error(ErrorCode::kInvalidArgument, "rewire_factor", "rewire_factor must be finite and > 1");
  }
  if (!(options_.guide_bias >= 0.0 && options_.guide_bias < 1.0)) {
    return make_error(ErrorCode::kInvalidArgument, "guide_bias", "guide_bias must be in [0, 1)");
  }
  if (!(options_.guide_radius_m >= 0.0) || !std::isfinite(options_.guide_radius_m)) {
    return make_error(ErrorCode::kInvalidArgument, "guide_radius_m", "guide_radius_m must be finite and >= 0");
  }
  for (const Eigen::Vector3d& g : options_.guide_m) {
    if (!finite(g)) return make_error(ErrorCode::kInvalidArgument, "guide_m", "a guide point is not finite: " + describe(g));
  }
  const Eigen::AlignedBox3d bounds = validator_.samplingBounds();
  if (bounds.isEmpty() || !bounds.min().allFinite() || !bounds.max().allFinite() || !(bounds.volume() > 0.0)) {
    return make_error(ErrorCode::kInvalidArgument, "sampling bounds",
                      "the validator's sampling box is empty, flat or not finite");
  }

  RrtStarResult result;
  result.tree_size = 0;
  auto finish = [&]() -> Result<RrtStarResult> {
    result.time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
  };
  if (!bounds.contains(start_m) || !validator_.isStateValid(start_m)) {
    result.status = PlannerStatus::kStartInvalid;
    return finish();
  }
  if (!bounds.contains(goal_m) || !validator_.isStateValid(goal_m)) {
    result.status = PlannerStatus::kGoalInvalid;
    return finish();
  }
  if (options_.try_direct_first) {
    ++result.motion_checks;
    if (validator_.isMotionValid(start_m, goal_m)) {
      result.status = PlannerStatus::kSolved;
      result.path_m = {start_m, goal_m};
      result.length_m = (goal_m - start_m).norm();
      result.tree_size = 2;
      result.solution_improvements = 1;
      result.first_solution_s = std::chrono::duration<double>(Clock::now() - t0).count();
      // A seed tree stays what is handed on, with the goal joined to its root.
      if (tree_out) *tree_out = seed ? *seed : RrtTree{{start_m}, {kRrtTreeNoParent}, {0.0}};
      if (tree_out) {
        tree_out->positions_m.push_back(goal_m);
        tree_out->parents.push_back(0);
        tree_out->costs_m.push_back(result.length_m);
      }
      return finish();
    }
  }

  const double max_step = options_.max_step_m > 0.0 ? options_.max_step_m : 0.2 * bounds.diagonal().norm();
  Search search(validator_, options_, bounds, start_m, goal_m, max_step);
  if (seed) {
    search.seedFrom(*seed, result, t0);
    result.seeded_nodes = seed->size();
  }
  search.run(stop, outer, result, t0);
  search.fillResult(result, options_.allow_approximate);
  if (tree_out) search.exportTree(*tree_out);
  result.motion_checks += search.motionChecks();
  return finish();
}

}  // namespace skyroute
