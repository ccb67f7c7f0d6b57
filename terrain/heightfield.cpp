#include "terrain/heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <mutex>

#include <ogr_spatialref.h>

namespace skyroute {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Longest piece of a segment treated as straight in pixel space (the ENU -> pixel map bends by
// far less than a millimetre over this length on any DEM tile).
constexpr double kMaxStraightPieceM = 2000.0;

// The DEM's footprint in ENU: the box inside its four edges (a cell's width in from where they
// bow) and the box around them.
struct Footprint {
  Eigen::AlignedBox2d inner;
  Eigen::AlignedBox2d outer;
};

// From pixel centres sampled along the four edges.
Result<Footprint> enuFootprint(const Dem& dem, OGRCoordinateTransformation& dem_to_wgs84, const LocalFrame& frame) {
  const int w = dem.width();
  const int h = dem.height();
  const int edge_samples = 64;
  std::vector<double> ex;
  std::vector<double> ny;
  std::vector<int> edge_of;  // 0 = first column, 1 = last column, 2 = first row, 3 = last row
  for (int k = 0; k <= edge_samples; ++k) {
    const double f = static_cast<double>(k) / edge_samples;
    const double col = f * (w - 1);
    const double row = f * (h - 1);
    const std::pair<Eigen::Vector2d, int> pts[4] = {{{0.0, row}, 0}, {{w - 1.0, row}, 1}, {{col, 0.0}, 2},
                                                    {{col, h - 1.0}, 3}};
    for (const auto& [px, edge] : pts) {
      const Eigen::Vector2d c = dem.pixelToCrs(px.x() + 0.5, px.y() + 0.5);
      ex.push_back(c.x());
      ny.push_back(c.y());
      edge_of.push_back(edge);
    }
  }
  if (!dem_to_wgs84.Transform(static_cast<int>(ex.size()), ex.data(), ny.data())) {
    return make_error(ErrorCode::kNoCrs, dem.path(), "edges cannot be transformed to WGS84");
  }
  frame.lonLatToEastNorth(ex.data(), ny.data(), ex.size());
  double mean_e[4] = {0, 0, 0, 0};
  double mean_n[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < ex.size(); ++i) {
    mean_e[edge_of[i]] += ex[i];
    mean_n[edge_of[i]] += ny[i];
  }
  // Which pixel edges face west, east, south, north.
  const bool cols_west_to_east = mean_e[0] < mean_e[1];
  const bool rows_north_to_south = mean_n[2] > mean_n[3];
  const int west = cols_west_to_east ? 0 : 1;
  const int east = cols_west_to_east ? 1 : 0;
  const int north = rows_north_to_south ? 2 : 3;
  const int south = rows_north_to_south ? 3 : 2;
  double e_min = -std::numeric_limits<double>::infinity();
  double e_max = std::numeric_limits<double>::infinity();
  double n_min = -std::numeric_limits<double>::infinity();
  double n_max = std::numeric_limits<double>::infinity();
  Eigen::AlignedBox2d outer;
  for (std::size_t i = 0; i < ex.size(); ++i) {
    outer.extend(Eigen::Vector2d(ex[i], ny[i]));
    if (edge_of[i] == west) e_min = std::max(e_min, ex[i]);
    if (edge_of[i] == east) e_max = std::min(e_max, ex[i]);
    if (edge_of[i] == south) n_min = std::max(n_min, ny[i]);
    if (edge_of[i] == north) n_max = std::min(n_max, ny[i]);
  }
  // The edges bow slightly between samples: keep a cell's width inside.
  const Eigen::Vector2d res = dem.resolutionM();
  Footprint footprint;
  footprint.inner = Eigen::AlignedBox2d(Eigen::Vector2d(e_min + res.x(), n_min + res.y()),
                                        Eigen::Vector2d(e_max - res.x(), n_max - res.y()));
  footprint.outer = outer;
  if (footprint.inner.isEmpty()) return make_error(ErrorCode::kInvalidArgument, dem.path(), "footprint is empty");
  return footprint;
}

}  // namespace

struct Heightfield::CrsTransforms {
  OGRSpatialReference dem_srs;
  OGRSpatialReference wgs84;
  std::unique_ptr<OGRCoordinateTransformation> dem_to_wgs84;
  std::unique_ptr<OGRCoordinateTransformation> wgs84_to_dem;
  std::mutex mutex;
};

Result<std::shared_ptr<const Heightfield>> Heightfield::build(std::shared_ptr<const Dem> dem,
                                                              std::optional<LocalFrame> frame) {
  if (!dem) return make_error(ErrorCode::kInvalidArgument, "dem", "is null");
  auto crs = std::make_shared<CrsTransforms>();
  if (crs->dem_srs.SetFromUserInput(dem->crsWkt().c_str()) != OGRERR_NONE) {
    return make_error(ErrorCode::kNoCrs, dem->path(), "CRS cannot be interpreted");
  }
  crs->dem_srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  crs->wgs84.SetWellKnownGeogCS("WGS84");
  crs->wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  crs->dem_to_wgs84.reset(OGRCreateCoordinateTransformation(&crs->dem_srs, &crs->wgs84));
  crs->wgs84_to_dem.reset(OGRCreateCoordinateTransformation(&crs->wgs84, &crs->dem_srs));
  if (!crs->dem_to_wgs84 || !crs->wgs84_to_dem) {
    return make_error(ErrorCode::kNoCrs, dem->path(), "CRS cannot be transformed to WGS84");
  }

  std::shared_ptr<Heightfield> hf(new Heightfield());
  hf->crs_ = crs;
  hf->dem_ = dem;
  hf->width_ = dem->width();
  hf->height_ = dem->height();
  hf->heights_ = dem->cells();
  hf->min_height_m_ = dem->minHeightM();
  hf->max_height_m_ = dem->maxHeightM();

  if (!frame) {
    Eigen::Vector2d c = dem->pixelToCrs(dem->width() / 2.0, dem->height() / 2.0);
    double x = c.x();
    double y = c.y();
    if (!crs->dem_to_wgs84->Transform(1, &x, &y)) {
      return make_error(ErrorCode::kNoCrs, dem->path(), "centre cannot be transformed to WGS84");
    }
    auto created = LocalFrame::create(y, x, 0.0);
    if (!created.ok()) return created.error();
    frame = created.value();
  }
  hf->frame_ = *frame;

  auto footprint = enuFootprint(*dem, *crs->dem_to_wgs84, hf->frame_);
  if (!footprint.ok()) return footprint.error();
  hf->bounds_en_ = footprint->inner;
  const Eigen::AlignedBox2d& outer = footprint->outer;
  const Eigen::Vector2d res = dem->resolutionM();
  const int w = dem->width();
  const int h = dem->height();

  // Lattice ENU -> pixel, exact at the nodes: every 8 cells of the finer axis, but never more nodes
  // than a quarter of the DEM's cells (a DEM has about a 64th; cells far longer than wide, from a
  // bad geotransform, would otherwise ask for billions of nodes).
  if (!outer.sizes().allFinite()) return make_error(ErrorCode::kInvalidArgument, dem->path(), "footprint is not finite");
  double step = std::max(1.0, 8.0 * std::min(res.x(), res.y()));
  const double max_nodes = std::max(static_cast<double>(w) * h / 4.0, 65536.0);
  auto nodes_along = [&](double extent_m) { return std::ceil((extent_m + step) / step) + 2.0; };
  while (nodes_along(outer.sizes().x()) * nodes_along(outer.sizes().y()) > max_nodes) step *= 2.0;
  hf->lattice_step_m_ = step;
  hf->lattice_origin_m_ = outer.min() - Eigen::Vector2d(step, step);
  hf->lattice_nx_ = static_cast<int>(std::ceil((outer.max().x() - hf->lattice_origin_m_.x()) / step)) + 2;
  hf->lattice_ny_ = static_cast<int>(std::ceil((outer.max().y() - hf->lattice_origin_m_.y()) / step)) + 2;
  const std::size_t nodes = static_cast<std::size_t>(hf->lattice_nx_) * hf->lattice_ny_;
  std::vector<double> lx(nodes);
  std::vector<double> ly(nodes);
  for (int j = 0; j < hf->lattice_ny_; ++j) {
    for (int i = 0; i < hf->lattice_nx_; ++i) {
      lx[j * hf->lattice_nx_ + i] = hf->lattice_origin_m_.x() + i * step;
      ly[j * hf->lattice_nx_ + i] = hf->lattice_origin_m_.y() + j * step;
    }
  }
  hf->frame_.eastNorthToLonLat(lx.data(), ly.data(), nodes);
  std::vector<int> ok(nodes, 0);
  crs->wgs84_to_dem->Transform(static_cast<int>(nodes), lx.data(), ly.data(), nullptr, ok.data());
  hf->lattice_pixels_.resize(nodes);
  for (std::size_t n = 0; n < nodes; ++n) {
    hf->lattice_pixels_[n] = ok[n] ? Eigen::Vector2d(dem->crsToPixel(lx[n], ly[n]) - Eigen::Vector2d(0.5, 0.5))
                                   : Eigen::Vector2d(kNaN, kNaN);
  }
  return std::shared_ptr<const Heightfield>(std::move(hf));
}

namespace {

// out[i] = the largest value(j) for j in [i - half, i + half] within [0, n), for every i in O(n):
// indices whose value can still be a maximum are kept in a queue of decreasing values.
template <class Value>
void slidingMax(int n, int half, const Value& value, std::vector<float>& out) {
  std::deque<int> candidates;
  int next = 0;
  for (int i = 0; i < n; ++i) {
    for (; next < n && next <= i + half; ++next) {
      while (!candidates.empty() && value(candidates.back()) <= value(next)) candidates.pop_back();
      candidates.push_back(next);
    }
    while (candidates.front() < i - half) candidates.pop_front();
    out[static_cast<std::size_t>(i)] = value(candidates.front());
  }
}

}  // namespace

std::shared_ptr<const Heightfield> Heightfield::dilated(double radius_m) const {
  std::shared_ptr<Heightfield> out(new Heightfield(*this));
  if (!(radius_m > 0.0)) return out;
  const Eigen::Vector2d res = dem_->resolutionM();
  // Offsets past the raster's own size never reach a cell.
  const int rx = static_cast<int>(std::min(width_ - 1.0, std::ceil(radius_m / res.x())));
  const int ry = static_cast<int>(std::min(height_ - 1.0, std::ceil(radius_m / res.y())));
  // The window: cells whose centre lies within the radius plus half a cell diagonal. Its offsets
  // at one dy are a single run -a..a of dx (and at one dx a run of dy), so each cell's maximum is
  // the largest of per-run maxima, and a sliding maximum gives those for a whole line at once: the
  // work is cells x runs, not cells x window (cells far narrower than the radius made that
  // millions of offsets per cell).
  const double reach_m = radius_m + 0.5 * res.norm();
  auto in_window = [&](int dx, int dy) { return std::hypot(dx * res.x(), dy * res.y()) <= reach_m; };
  // Unknown cells are +inf while taking maxima (no height is infinite) and NaN again at the end:
  // an unknown cell in reach makes the result unknown.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> source(heights_);
  for (float& v : source) v = std::isnan(v) ? kInf : v;
  std::vector<float>& result = out->heights_;
  std::fill(result.begin(), result.end(), -kInf);

  const bool by_rows = ry <= rx;  // runs along rows (one per dy), or along columns (one per dx)
  const int runs = by_rows ? ry : rx;
  const int longest = by_rows ? rx : ry;
  const int length = by_rows ? width_ : height_;
  const int lines = by_rows ? height_ : width_;
  auto index = [&](int line, int i) {
    return by_rows ? static_cast<std::size_t>(line) * width_ + i : static_cast<std::size_t>(i) * width_ + line;
  };
  std::vector<float> run_max(static_cast<std::size_t>(length));
  for (int k = -runs; k <= runs; ++k) {
    int half = -1;
    while (half < longest && (by_rows ? in_window(half + 1, k) : in_window(k, half + 1))) ++half;
    if (half < 0) continue;
    for (int line = std::max(0, -k); line < std::min(lines, lines - k); ++line) {
      slidingMax(length, half, [&](int i) { return source[index(line + k, i)]; }, run_max);
      for (int i = 0; i < length; ++i) result[index(line, i)] = std::max(result[index(line, i)], run_max[i]);
    }
  }
  double hi = -std::numeric_limits<double>::infinity();
  for (float& v : result) {
    if (v == kInf) {
      v = std::numeric_limits<float>::quiet_NaN();
    } else {
      hi = std::max(hi, static_cast<double>(v));
    }
  }
  out->max_height_m_ = hi;
  return out;
}

Eigen::Vector2d Heightfield::enToPixel(double east_m, double north_m) const {
  const double gx = (east_m - lattice_origin_m_.x()) / lattice_step_m_;
  const double gy = (north_m - lattice_origin_m_.y()) / lattice_step_m_;
  if (!(gx >= 0.0 && gy >= 0.0 && gx < lattice_nx_ - 1 && gy < lattice_ny_ - 1)) return {kNaN, kNaN};
  const int i = static_cast<int>(gx);
  const int j = static_cast<int>(gy);
  const double fx = gx - i;
  const double fy = gy - j;
  const std::size_t n00 = static_cast<std::size_t>(j) * lattice_nx_ + i;
  const Eigen::Vector2d& p00 = lattice_pixels_[n00];
  const Eigen::Vector2d& p10 = lattice_pixels_[n00 + 1];
  const Eigen::Vector2d& p01 = lattice_pixels_[n00 + lattice_nx_];
  const Eigen::Vector2d& p11 = lattice_pixels_[n00 + lattice_nx_ + 1];
  return (1 - fy) * ((1 - fx) * p00 + fx * p10) + fy * ((1 - fx) * p01 + fx * p11);
}

Eigen::Vector2d Heightfield::enToPixelExact(double east_m, double north_m) const {
  double x = east_m;
  double y = north_m;
  frame_.eastNorthToLonLat(&x, &y, 1);
  std::lock_guard<std::mutex> lock(crs_->mutex);
  if (!crs_->wgs84_to_dem->Transform(1, &x, &y)) return {kNaN, kNaN};
  return dem_->crsToPixel(x, y) - Eigen::Vector2d(0.5, 0.5);
}

Eigen::Vector2d Heightfield::pixelToEn(double col, double row) const {
  const Eigen::Vector2d c = dem_->pixelToCrs(col + 0.5, row + 0.5);
  double x = c.x();
  double y = c.y();
  {
    std::lock_guard<std::mutex> lock(crs_->mutex);
    if (!crs_->dem_to_wgs84->Transform(1, &x, &y)) return {kNaN, kNaN};
  }
  frame_.lonLatToEastNorth(&x, &y, 1);
  return {x, y};
}

double Heightfield::bilinear(double px, double py) const {
  if (!(px >= 0.0 && py >= 0.0 && px <= width_ - 1 && py <= height_ - 1)) return kNaN;
  int i = static_cast<int>(px);
  int j = static_cast<int>(py);
  if (i == width_ - 1) --i;
  if (j == height_ - 1) --j;
  const double u = px - i;
  const double v = py - j;
  const double h00 = heightCell(i, j);
  const double h10 = heightCell(i + 1, j);
  const double h01 = heightCell(i, j + 1);
  const double h11 = heightCell(i + 1, j + 1);
  return (1 - v) * ((1 - u) * h00 + u * h10) + v * ((1 - u) * h01 + u * h11);  // NaN propagates
}

double Heightfield::heightAt(double east_m, double north_m) const {
  const Eigen::Vector2d p = enToPixel(east_m, north_m);
  return bilinear(p.x(), p.y());
}

std::optional<double> Heightfield::height(const Eigen::Vector2d& en_m) const {
  const double h = heightAt(en_m.x(), en_m.y());
  if (std::isnan(h)) return std::nullopt;
  return h;
}

std::optional<double> Heightfield::heightAboveGround(const Eigen::Vector3d& p_m) const {
  const double h = heightAt(p_m.x(), p_m.y());
  if (std::isnan(h)) return std::nullopt;
  return p_m.z() - h;
}

bool Heightfield::inside(double east_m, double north_m) const {
  const Eigen::Vector2d p = enToPixel(east_m, north_m);
  return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= width_ - 1 && p.y() <= height_ - 1;
}

double Heightfield::minHeightAboveGround(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m) const {
  const double horizontal = (b_m.head<2>() - a_m.head<2>()).norm();
  if (horizontal > kMaxStraightPieceM) {
    const int pieces = static_cast<int>(std::ceil(horizontal / kMaxStraightPieceM));
    double lowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < pieces; ++k) {
      const Eigen::Vector3d p0 = a_m + (b_m - a_m) * (static_cast<double>(k) / pieces);
      const Eigen::Vector3d p1 = a_m + (b_m - a_m) * (static_cast<double>(k + 1) / pieces);
      const double m = minHeightAboveGround(p0, p1);
      if (std::isnan(m)) return kNaN;
      lowest = std::min(lowest, m);
    }
    return lowest;
  }
  const Eigen::Vector2d pa = enToPixel(a_m.x(), a_m.y());
  const Eigen::Vector2d pb = enToPixel(b_m.x(), b_m.y());
  auto in_grid = [&](const Eigen::Vector2d& p) {
    return p.x() >= 0.0 && p.y() >= 0.0 && p.x() <= width_ - 1 && p.y() <= height_ - 1;
  };
  if (!in_grid(pa) || !in_grid(pb)) return kNaN;  // the grid is convex: both ends inside => all inside
  const Eigen::Vector2d d = pb - pa;
  const double dz = b_m.z() - a_m.z();

  // Walk the cells [i, i+1] x [j, j+1] (corners at pixel centres) crossed by pa + t d.
  auto cell_index = [](double p, double dir, int max_index) {
    int i = static_cast<int>(std::floor(p));
    if (dir < 0.0 && p == std::floor(p)) --i;  // moving backwards from an edge: the cell behind it
    return std::clamp(i, 0, max_index - 1);
  };
  int i = cell_index(pa.x(), d.x(), width_ - 1);
  int j = cell_index(pa.y(), d.y(), height_ - 1);
  const int step_i = d.x() > 0 ? 1 : -1;
  const int step_j = d.y() > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_x = d.x() != 0.0 ? 1.0 / std::abs(d.x()) : inf;
  const double t_delta_y = d.y() != 0.0 ? 1.0 / std::abs(d.y()) : inf;
  double t_next_x = d.x() > 0 ? (i + 1 - pa.x()) / d.x() : (d.x() < 0 ? (i - pa.x()) / d.x() : inf);
  double t_next_y = d.y() > 0 ? (j + 1 - pa.y()) / d.y() : (d.y() < 0 ? (j - pa.y()) / d.y() : inf);

  double lowest = inf;
  double t0 = 0.0;
  while (true) {
    const double t1 = std::min({t_next_x, t_next_y, 1.0});
    const double h00 = heightCell(i, j);
    const double h10 = heightCell(i + 1, j);
    const double h01 = heightCell(i, j + 1);
    const double h11 = heightCell(i + 1, j + 1);
    if (std::isnan(h00 + h10 + h01 + h11)) return kNaN;
    // u(t) = u0 + d.x t, v(t) = v0 + d.y t: ground(t) = c0 + c1 t + c2 t^2 on this cell.
    const double u0 = pa.x() - i;
    const double v0 = pa.y() - j;
    const double a = h00;
    const double b = h10 - h00;
    const double c = h01 - h00;
    const double e = h00 - h10 - h01 + h11;
    const double c0 = a + b * u0 + c * v0 + e * u0 * v0;
    const double c1 = b * d.x() + c * d.y() + e * (u0 * d.y() + v0 * d.x());
    const double c2 = e * d.x() * d.y();
    // clearance f(t) = z(t) - ground(t)
    auto f = [&](double t) { return a_m.z() + dz * t - (c0 + c1 * t + c2 * t * t); };
    lowest = std::min({lowest, f(t0), f(t1)});
    if (c2 < 0.0) {  // f is convex in t: its minimum may lie inside the piece
      const double t_star = (dz - c1) / (2.0 * c2);
      if (t_star > t0 && t_star < t1) lowest = std::min(lowest, f(t_star));
    }
    if (t1 >= 1.0) break;
    if (t_next_x <= t_next_y) {
      i += step_i;
      t_next_x += t_delta_x;
    } else {
      j += step_j;
      t_next_y += t_delta_y;
    }
    i = std::clamp(i, 0, width_ - 2);
    j = std::clamp(j, 0, height_ - 2);
    t0 = t1;
  }
  return lowest;
}

std::size_t Heightfield::memoryBytes() const {
  return heights_.size() * sizeof(float) + lattice_pixels_.size() * sizeof(Eigen::Vector2d);
}

}  // namespace skyroute
