#include "trajectory/corner_rounding.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "planning/core/enum_names.hpp"

namespace skyroute {

std::string_view to_string(CornerMethod method) {
  constexpr EnumName<CornerMethod> kNames[] = {{CornerMethod::kFillet, "fillet"},
                                               {CornerMethod::kPassThrough, "pass-through"}};
  return enumName(kNames, method);
}

double deflectionAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& p, const Eigen::Vector3d& b) {
  const Eigen::Vector3d in = p - a;
  const Eigen::Vector3d out = b - p;
  if (in.norm() == 0.0 || out.norm() == 0.0) return 0.0;
  const Eigen::Vector3d u_in = in.normalized();
  const Eigen::Vector3d u_out = out.normalized();
  return std::atan2(u_in.cross(u_out).norm(), u_in.dot(u_out));
}

namespace {

constexpr double kNoTurnRad = 1e-9;

// Tangent point, arc points, tangent point of the fillet at p; {p} itself when p does not turn.
std::optional<std::vector<Eigen::Vector3d>> fillet(const Eigen::Vector3d& a, const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& b, double radius_m, double share_in,
                                                   double share_out, double arc_step_rad) {
  const double len_in = (p - a).norm();
  const double len_out = (b - p).norm();
  if (len_in == 0.0 || len_out == 0.0) return std::nullopt;
  const Eigen::Vector3d u_in = (p - a) / len_in;
  const Eigen::Vector3d u_out = (b - p) / len_out;
  const Eigen::Vector3d cross = u_in.cross(u_out);
  const double phi = std::atan2(cross.norm(), u_in.dot(u_out));
  if (phi < kNoTurnRad) return std::vector<Eigen::Vector3d>{p};
  // A reversal has no plane and an infinite tangent length.
  if (cross.norm() < 1e-9) return std::nullopt;
  const double d = radius_m * std::tan(0.5 * phi);
  if (!std::isfinite(d) || d > share_in * len_in || d > share_out * len_out) return std::nullopt;
  const Eigen::Vector3d n = cross.normalized();  // the arc's axis: normal of the legs' plane
  const Eigen::Vector3d t_in = p - d * u_in;
  const Eigen::Vector3d t_out = p + d * u_out;
  const Eigen::Vector3d centre = t_in + radius_m * n.cross(u_in);  // n x u_in points into the turn
  const int pieces = std::max(2, static_cast<int>(std::ceil(phi / arc_step_rad - 1e-9)));
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<std::size_t>(pieces) + 1);
  points.push_back(t_in);
  for (int k = 1; k < pieces; ++k)
    points.push_back(centre + Eigen::AngleAxisd(phi * k / pieces, n) * (t_in - centre));
  points.push_back(t_out);
  return points;
}

}  // namespace

std::optional<CornerGeometry> roundCorner(CornerMethod method, const Eigen::Vector3d& a, const Eigen::Vector3d& p,
                                          const Eigen::Vector3d& b, double radius_m, double share_in,
                                          double share_out, const CornerRoundingOptions& options) {
  if (!(radius_m > 0.0) || !std::isfinite(radius_m)) return std::nullopt;
  const double phi = deflectionAngle(a, p, b);
  if (phi < kNoTurnRad) return std::nullopt;
  const double step = std::clamp(options.arc_step_deg, 0.5, 90.0) * std::numbers::pi / 180.0;
  CornerGeometry out;
  out.radius_m = radius_m;
  out.deflection_rad = phi;

  if (method == CornerMethod::kFillet) {
    auto points = fillet(a, p, b, radius_m, share_in, share_out, step);
    if (!points) return std::nullopt;
    out.points = std::move(*points);
    return out;
  }

  // Pass-through. The bisector of the turn; for a reversal any direction across the leg works:
  // prefer a horizontal one so the detour stays at the leg's altitude.
  const Eigen::Vector3d u_in = (p - a).normalized();
  const Eigen::Vector3d u_out = (b - p).normalized();
  Eigen::Vector3d h = u_in + u_out;
  if (h.norm() < 1e-9) {
    h = u_in.cross(Eigen::Vector3d::UnitZ());
    if (h.norm() < 1e-6) h = u_in.cross(Eigen::Vector3d::UnitX());
  }
  h.normalize();
  // L: the fillets at Q1 and Q2 need R tan(phi_i / 2) of the straight through P, plus the straight
  // share. The corners at Q1, Q2 depend on L (a fixed point; it converges when the legs are
  // long against R, and L outgrowing a leg means it does not fit).
  const double straight = 1.0 + std::max(0.0, options.pass_through_straight_share);
  const double len_in = (p - a).norm();
  const double len_out = (b - p).norm();
  double length = radius_m * std::tan(0.25 * phi) * straight;
  bool converged = false;
  for (int iteration = 0; iteration < 60; ++iteration) {
    if (!(length < len_in) || !(length < len_out)) return std::nullopt;
    const double phi1 = deflectionAngle(a, p - length * h, p);
    const double phi2 = deflectionAngle(p, p + length * h, b);
    const double need = radius_m * std::max(std::tan(0.5 * phi1), std::tan(0.5 * phi2)) * straight;
    if (!std::isfinite(need)) return std::nullopt;
    const bool close = std::abs(need - length) <= 1e-9 * std::max(1.0, length);
    length = std::max(need, 1e-6);
    if (close) {
      converged = true;
      break;
    }
  }
  if (!converged || !(length < len_in) || !(length < len_out)) return std::nullopt;
  const Eigen::Vector3d q1 = p - length * h;
  const Eigen::Vector3d q2 = p + length * h;
  // Each fillet may use the whole straight towards P (the straight share is already in L).
  auto first = fillet(a, q1, p, radius_m, share_in, 1.0, step);
  auto second = fillet(p, q2, b, radius_m, 1.0, share_out, step);
  if (!first || !second) return std::nullopt;
  out.points = std::move(*first);
  out.kept_point = out.points.size();
  out.points.push_back(p);
  out.points.insert(out.points.end(), second->begin(), second->end());
  return out;
}

double largestFittingRadius(CornerMethod method, const Eigen::Vector3d& a, const Eigen::Vector3d& p,
                            const Eigen::Vector3d& b, double upper_m, double share_in, double share_out,
                            const CornerRoundingOptions& options) {
  if (!(upper_m > 0.0)) return 0.0;
  const double phi = deflectionAngle(a, p, b);
  if (phi < kNoTurnRad) return 0.0;
  if (method == CornerMethod::kFillet) {
    const double room = std::min(share_in * (p - a).norm(), share_out * (b - p).norm());
    const double radius = room / std::tan(0.5 * phi);
    if (!std::isfinite(radius) || radius <= 0.0) return 0.0;
    // Closed form, then the largest radius the fillet itself accepts (rounding at the boundary).
    double r = std::min(upper_m, radius);
    for (int k = 0; k < 8 && !roundCorner(method, a, p, b, r, share_in, share_out, options); ++k) r *= 1.0 - 1e-9;
    return roundCorner(method, a, p, b, r, share_in, share_out, options) ? r : 0.0;
  }
  if (roundCorner(method, a, p, b, upper_m, share_in, share_out, options)) return upper_m;
  // Everything in the construction scales with R except the legs: bisect on the fit.
  double lo = 0.0;
  double hi = upper_m;
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (roundCorner(method, a, p, b, mid, share_in, share_out, options))
      lo = mid;
    else
      hi = mid;
  }
  return lo > 0.0 && roundCorner(method, a, p, b, lo, share_in, share_out, options) ? lo : 0.0;
}

}  // namespace skyroute
