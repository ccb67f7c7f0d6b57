// Corner rounding: the geometry that widens a polyline's corner to a given turn radius, so the
// spline through it can be flown by a vehicle with a minimum turn radius (a fixed wing). Stretching
// time never widens a turn; only a different path does.
// - Fillet: the corner P between neighbours A and B, turning by phi, is replaced by the circular
//   arc of radius R tangent to both legs: tangent points at d = R tan(phi / 2) from P along each
//   leg, and arc points in between, in the plane of the two legs (3D), at most arc_step apart in
//   angle. The corner point itself is cut.
// - Pass-through: for a point that must be flown over exactly (a mission point), the vehicle
//   crosses P on a straight line along the turn's bisector h = (u_in + u_out) / |.|: approach
//   and departure points Q1 = P - L h and Q2 = P + L h are inserted and the two smaller corners
//   there (about phi / 2 each) are filleted; P stays a vertex with no turn at it.
// Pure geometry: no collision checks (the caller validates what it adopts).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace skyroute {

struct CornerRoundingOptions {
  // First fillet radius = radius_factor * the vehicle's min turn radius: the spline through the arc
  // points dips a little under the arc's radius where the straight joins the arc.
  double radius_factor = 1.3;
  // When a fillet collides, smaller radii are tried, down to the min turn radius, in this many steps.
  int radius_attempts = 4;
  // Largest angle (degrees) between consecutive arc points; smaller follows the arc more closely.
  double arc_step_deg = 15.0;
  // Pass-through: the straight line through the fixed point extends this share of the fillets'
  // tangent length beyond each of them, so the vehicle is straight and level in heading at P.
  double pass_through_straight_share = 0.25;
};

enum class CornerMethod { kFillet, kPassThrough };
std::string_view to_string(CornerMethod method);

// The replacement of corner P: these points go where P was, in order (a fillet: tangent point,
// arc points, tangent point; a pass-through: fillet at Q1, P, fillet at Q2).
struct CornerGeometry {
  std::vector<Eigen::Vector3d> points;
  std::size_t kept_point = static_cast<std::size_t>(-1);  // index of P in points (pass-through), else -1
  double radius_m = 0.0;
  double deflection_rad = 0.0;  // the corner's turn at P
};

// Turn angle at p between the legs a->p and p->b, in [0, pi].
double deflectionAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& p, const Eigen::Vector3d& b);

// The rounded corner with the given radius, or nullopt when it does not fit: each tangent length
// may use at most share_in of the leg a->p (share_out of p->b), so the neighbours' corners keep
// room for theirs. A (near) reversal cannot be filleted; nullopt for a corner that does not turn.
std::optional<CornerGeometry> roundCorner(CornerMethod method, const Eigen::Vector3d& a, const Eigen::Vector3d& p,
                                          const Eigen::Vector3d& b, double radius_m, double share_in,
                                          double share_out, const CornerRoundingOptions& options = {});

// Largest radius in [0, upper_m] for which roundCorner fits (0 when none does).
double largestFittingRadius(CornerMethod method, const Eigen::Vector3d& a, const Eigen::Vector3d& p,
                            const Eigen::Vector3d& b, double upper_m, double share_in, double share_out,
                            const CornerRoundingOptions& options = {});

}  // namespace skyroute
