#include "service/figure_layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace skyroute {
namespace {

constexpr double kRoundingSlack = 1e-9;  // so that 0.3 / 3 still counts as 0.1

// The pixel offset in [0, length_px] where `valueAt` (monotonic) reaches `target`.
double crossing(const std::function<double(double)>& valueAt, double length_px, double target) {
  double lo = 0.0;
  double hi = length_px;
  const bool increasing = valueAt(hi) >= valueAt(lo);
  for (int i = 0; i < 40 && hi - lo > 0.01; ++i) {
    const double mid = 0.5 * (lo + hi);
    if ((valueAt(mid) < target) == increasing) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

int decimalsFor(double step) {
  return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - kRoundingSlack)));
}

std::string formatDegrees(double value_deg, double step_deg, const char* positive, const char* negative) {
  char text[48];
  const int decimals = decimalsFor(step_deg);
  // A tick at zero is neither north nor south.
  const double magnitude = std::abs(value_deg) < 0.5 * step_deg ? 0.0 : std::abs(value_deg);
  std::snprintf(text, sizeof text, "%.*f\u00B0%s", decimals, magnitude,
                magnitude == 0.0 ? "" : (value_deg > 0 ? positive : negative));
  return text;
}

}  // namespace

double roundStepAtMost(double limit) {
  const double power = std::pow(10.0, std::floor(std::log10(limit)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * power <= limit * (1.0 + kRoundingSlack)) return m * power;
  }
  return power / 2.0;
}

double roundStepAtLeast(double limit) {
  const double power = std::pow(10.0, std::floor(std::log10(limit)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= limit * (1.0 - kRoundingSlack)) return m * power;
  }
  return 10.0 * power;
}

std::vector<double> roundTicks(double lo, double hi, int wanted) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  double step = roundStepAtLeast((hi - lo) / std::max(1, wanted));
  for (int attempt = 0; attempt < 4; ++attempt) {
    ticks.clear();
    for (double k = std::ceil(lo / step - kRoundingSlack); k * step <= hi + step * kRoundingSlack; k += 1.0) {
      ticks.push_back(k * step + 0.0);  // + 0.0: no "-0" label
      if (ticks.size() > 1000) break;  // never, for a step from the span
    }
    if (ticks.size() >= 2) break;
    step = roundStepAtMost(step * 0.99);
  }
  return ticks;
}

Eigen::AlignedBox2d cropAround(const Eigen::AlignedBox2d& content, const Eigen::AlignedBox2d& limits,
                               double margin_fraction, double min_margin_m) {
  if (content.isEmpty()) return limits;
  const double margin = std::max(min_margin_m, margin_fraction * content.sizes().maxCoeff());
  Eigen::AlignedBox2d grown(content.min() - Eigen::Vector2d::Constant(margin),
                            content.max() + Eigen::Vector2d::Constant(margin));
  const Eigen::AlignedBox2d clipped = grown.intersection(limits);
  return clipped.isEmpty() || clipped.volume() <= 0.0 ? limits : clipped;
}

MapViewport::MapViewport(const Eigen::AlignedBox2d& box_m, int long_side_px) : box_m_(box_m) {
  const Eigen::Vector2d size = box_m.isEmpty() ? Eigen::Vector2d(1.0, 1.0) : box_m.sizes();
  const double longest = std::max({size.x(), size.y(), 1e-6});
  metres_per_px_ = longest / std::max(1, long_side_px);
  width_px_ = std::max(1, static_cast<int>(std::lround(size.x() / metres_per_px_)));
  height_px_ = std::max(1, static_cast<int>(std::lround(size.y() / metres_per_px_)));
}

Eigen::Vector2d MapViewport::toPixel(const Eigen::Vector2d& en_m) const {
  return {(en_m.x() - box_m_.min().x()) / metres_per_px_, (box_m_.max().y() - en_m.y()) / metres_per_px_};
}

Eigen::Vector2d MapViewport::toEastNorth(const Eigen::Vector2d& px) const {
  return {box_m_.min().x() + px.x() * metres_per_px_, box_m_.max().y() - px.y() * metres_per_px_};
}

GeoTicks geoTicks(const MapViewport& viewport, const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& toLonLat,
                  int wanted_per_edge) {
  // Round values between an edge's two ends, each placed where the edge reaches it.
  auto edgeTicks = [wanted_per_edge](const std::function<double(double)>& valueAt, double length_px,
                                     std::string (*format)(double, double)) {
    const double lo = std::min(valueAt(0.0), valueAt(length_px));
    const double hi = std::max(valueAt(0.0), valueAt(length_px));
    const std::vector<double> values = roundTicks(lo, hi, wanted_per_edge);
    const double step = values.size() >= 2 ? values[1] - values[0] : 1.0;
    std::vector<FrameTick> ticks;
    for (double v : values) ticks.push_back({crossing(valueAt, length_px, v), v, format(v, step)});
    return ticks;
  };
  const double width = viewport.widthPx();
  const double height = viewport.heightPx();
  GeoTicks ticks;
  ticks.longitudes = edgeTicks([&](double x) { return toLonLat({x, height}).x(); }, width, &formatLongitude);
  ticks.latitudes = edgeTicks([&](double y) { return toLonLat({0.0, y}).y(); }, height, &formatLatitude);
  return ticks;
}

std::string formatLatitude(double lat_deg, double step_deg) { return formatDegrees(lat_deg, step_deg, "N", "S"); }
std::string formatLongitude(double lon_deg, double step_deg) { return formatDegrees(lon_deg, step_deg, "E", "W"); }

std::string formatDistance(double metres) {
  char text[32];
  if (metres >= 1000.0) {
    std::snprintf(text, sizeof text, "%g km", metres / 1000.0);
  } else {
    std::snprintf(text, sizeof text, "%g m", metres);
  }
  return text;
}

}  // namespace skyroute
