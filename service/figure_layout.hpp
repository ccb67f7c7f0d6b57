// The arithmetic of a map figure, apart from drawing it: which part of the terrain is shown, how
// many metres a pixel covers, where the latitude/longitude ticks fall and how long the scale bar
// is. Kept free of Cairo so tests can check it against the local frame directly.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace skyroute {

// The largest 1, 2 or 5 times a power of ten that is at most `limit` (> 0).
double roundStepAtMost(double limit);
// The smallest 1, 2 or 5 times a power of ten that is at least `limit` (> 0).
double roundStepAtLeast(double limit);
// Multiples of a round step inside [lo, hi], about `wanted` of them (at least 2 when the span allows).
std::vector<double> roundTicks(double lo, double hi, int wanted);

// What is drawn, grown by a margin on every side (a fraction of the larger extent, at least
// min_margin_m) and clipped to `limits`. An empty `content` gives `limits`.
Eigen::AlignedBox2d cropAround(const Eigen::AlignedBox2d& content, const Eigen::AlignedBox2d& limits,
                               double margin_fraction, double min_margin_m);

// North-up pixel mapping of an east/north box into an image whose longer side is long_side_px.
class MapViewport {
 public:
  MapViewport(const Eigen::AlignedBox2d& box_m, int long_side_px);
  int widthPx() const { return width_px_; }
  int heightPx() const { return height_px_; }
  double metresPerPixel() const { return metres_per_px_; }
  const Eigen::AlignedBox2d& box() const { return box_m_; }
  // Pixel (x right, y down; pixel centres at +0.5) of an east/north point, and back.
  Eigen::Vector2d toPixel(const Eigen::Vector2d& en_m) const;
  Eigen::Vector2d toEastNorth(const Eigen::Vector2d& px) const;

 private:
  Eigen::AlignedBox2d box_m_;
  int width_px_ = 1;
  int height_px_ = 1;
  double metres_per_px_ = 1.0;
};

// A labelled mark on the figure's frame at pixel offset `at_px` along its edge.
struct FrameTick {
  double at_px = 0.0;
  double value = 0.0;
  std::string label;
};

// Round longitudes along the bottom edge and latitudes along the left edge. `toLonLat` maps a
// pixel to (longitude, latitude) in degrees; each tick's position is found where the edge crosses
// the tick's value, to a hundredth of a pixel.
struct GeoTicks {
  std::vector<FrameTick> longitudes;  // along the bottom edge, at_px = x
  std::vector<FrameTick> latitudes;   // along the left edge, at_px = y
};
GeoTicks geoTicks(const MapViewport& viewport, const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& toLonLat,
                  int wanted_per_edge);

// "44.05°N", "72.1°W": as many decimals as the step needs.
std::string formatLatitude(double lat_deg, double step_deg);
std::string formatLongitude(double lon_deg, double step_deg);
// "500 m", "2 km".
std::string formatDistance(double metres);

}  // namespace skyroute
