#include "service/map_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>

#include <cairo.h>

#include "service/figure_raster.hpp"

namespace skyroute {
namespace {

// The frame around the map, in pixels: room for latitude labels on the left, longitude labels
// below, the title above; the profile panel and its axis labels under that.
struct FrameMarginsPx {
  double left, top, right, bottom, profile_height, profile_bottom;
};
constexpr FrameMarginsPx kFrame{92.0, 40.0, 24.0, 46.0, 220.0, 46.0};

constexpr Rgb kGroundRgb{160, 120, 80};
constexpr Rgb kClearanceRgb{245, 170, 60};
constexpr Rgb kAltitudeRgb{220, 20, 20};
constexpr Rgb kStartRgb{20, 150, 40};
constexpr Rgb kEndRgb{200, 20, 20};

struct CairoDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, CairoDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, CairoDeleter>;

void setColour(cairo_t* cr, Rgb c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, alpha);
}

// Text placed by an anchor: align_x 0 left, 0.5 centre, 1 right of x; align_y likewise of y
// (0 top, 0.5 middle, 1 bottom of the glyphs).
void drawText(cairo_t* cr, const std::string& text, double x, double y, double size_px, double align_x, double align_y,
              bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size_px);
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  cairo_move_to(cr, x - e.x_bearing - align_x * e.width, y - e.y_bearing - align_y * e.height);
  cairo_show_text(cr, text.c_str());
}

// Everything the shared drawing needs to know about one figure's map area.
struct Frame {
  MapViewport viewport{Eigen::AlignedBox2d(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones()), 1};
  FigureRaster raster;
  std::vector<FrameTick> bottom_ticks;
  std::vector<FrameTick> left_ticks;
  double scale_bar_units = 0.0;
  std::string scale_bar_label;
  bool north_arrow = true;
  std::string unknown_label;  // the legend's name of hatched pixels
  std::string blocked_label;  // grid figures: the legend's name of blocked cells
  std::function<Eigen::Vector2d(const Eigen::Vector2d&)> toMapPixel;  // content coordinates -> map pixel
};

Eigen::AlignedBox2d contentBox(const MapFigureContent& content,
                               const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& toPlane) {
  Eigen::AlignedBox2d box;
  for (const FigureLine& line : content.lines) {
    for (const Eigen::Vector2d& p : line.points) {
      if (p.allFinite()) box.extend(toPlane(p));
    }
  }
  for (const FigureMarker& m : content.markers) {
    if (m.at.allFinite()) box.extend(toPlane(m.at));
  }
  return box;
}

void paintRaster(cairo_t* cr, const FigureRaster& raster) {
  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, raster.width, raster.height));
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < raster.height; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    for (int x = 0; x < raster.width; ++x) {
      const Rgb c = raster.pixels[static_cast<std::size_t>(y) * raster.width + x];
      row[x] = (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | std::uint32_t{c.b};
    }
  }
  cairo_surface_mark_dirty(surface.get());
  cairo_set_source_surface(cr, surface.get(), kFrame.left, kFrame.top);
  cairo_paint(cr);
}

void drawLines(cairo_t* cr, const Frame& frame, const std::vector<FigureLine>& lines) {
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (const FigureLine& line : lines) {
    if (line.points.size() < 2) continue;
    for (bool halo : {true, false}) {  // a light halo keeps a line readable on any terrain
      cairo_new_path(cr);
      for (const Eigen::Vector2d& p : line.points) {
        const Eigen::Vector2d px = frame.toMapPixel(p);
        cairo_line_to(cr, kFrame.left + px.x(), kFrame.top + px.y());
      }
      const double dash[] = {3.0 * line.width_px, 2.0 * line.width_px};
      cairo_set_dash(cr, dash, line.dashed && !halo ? 2 : 0, 0.0);
      cairo_set_line_width(cr, line.width_px + (halo ? 2.5 : 0.0));
      if (halo) {
        cairo_set_source_rgba(cr, 1, 1, 1, 0.7);
      } else {
        setColour(cr, line.colour);
      }
      cairo_stroke(cr);
    }
  }
  cairo_set_dash(cr, nullptr, 0, 0.0);
}

// How each kind of marker looks: its shape, half its size, and whether it is filled with its
// colour (white outline) or a white ring in its colour; start and end have colours of their own.
enum class MarkerShape { kTriangle, kSquare, kCircle };
struct MarkerStyle {
  MarkerShape shape;
  double half_px;
  bool ring;
  double line_px;
  std::optional<Rgb> own_colour;
};

MarkerStyle styleOf(MarkerKind kind) {
  switch (kind) {
    case MarkerKind::kStart: return {MarkerShape::kTriangle, 9.0, false, 2.0, kStartRgb};
    case MarkerKind::kEnd: return {MarkerShape::kSquare, 8.0, false, 2.0, kEndRgb};
    case MarkerKind::kMissionPoint: return {MarkerShape::kCircle, 10.0, true, 2.0, std::nullopt};
    case MarkerKind::kTask: return {MarkerShape::kCircle, 6.0, true, 3.0, std::nullopt};
    case MarkerKind::kDepot: return {MarkerShape::kSquare, 7.0, false, 2.0, std::nullopt};
  }
  return {MarkerShape::kCircle, 6.0, true, 2.0, std::nullopt};
}

// One marker's symbol centred on (x, y): the same in the map and in the legend.
void drawMarkerSymbol(cairo_t* cr, MarkerKind kind, double x, double y, int number, Rgb colour) {
  const MarkerStyle style = styleOf(kind);
  const double h = style.half_px;
  cairo_new_path(cr);
  if (style.shape == MarkerShape::kTriangle) {
    cairo_move_to(cr, x, y - h - 1.0);
    cairo_line_to(cr, x + h, y + 0.8 * h);
    cairo_line_to(cr, x - h, y + 0.8 * h);
    cairo_close_path(cr);
  } else if (style.shape == MarkerShape::kSquare) {
    cairo_rectangle(cr, x - h, y - h, 2.0 * h, 2.0 * h);
  } else {
    cairo_arc(cr, x, y, h, 0, 2 * M_PI);
  }
  const Rgb fill = style.own_colour.value_or(colour);
  setColour(cr, style.ring ? Rgb{255, 255, 255} : fill);
  cairo_fill_preserve(cr);
  cairo_set_line_width(cr, style.line_px);
  setColour(cr, style.ring ? fill : Rgb{255, 255, 255});
  cairo_stroke(cr);
  if (kind == MarkerKind::kMissionPoint && number > 0) {
    setColour(cr, fill);
    drawText(cr, std::to_string(number), x, y, number > 9 ? 9.5 : 11.0, 0.5, 0.5, true);
  }
}

void drawMarkers(cairo_t* cr, const Frame& frame, const std::vector<FigureMarker>& markers) {
  for (const FigureMarker& m : markers) {
    if (!m.at.allFinite()) continue;
    const Eigen::Vector2d px = frame.toMapPixel(m.at);
    drawMarkerSymbol(cr, m.kind, kFrame.left + px.x(), kFrame.top + px.y(), m.number, m.colour);
  }
}

// Bottom left inside the map: a bar in two halves with its length; top right: an arrow to north.
void drawScaleAndNorth(cairo_t* cr, const Frame& frame) {
  const double bar_px = frame.scale_bar_units / frame.viewport.metresPerPixel();
  const double x0 = kFrame.left + 16.0;
  const double y0 = kFrame.top + frame.viewport.heightPx() - 20.0;
  cairo_set_source_rgba(cr, 1, 1, 1, 0.75);
  cairo_rectangle(cr, x0 - 8, y0 - 26, bar_px + 16, 36);
  cairo_fill(cr);
  for (int half = 0; half < 2; ++half) {
    cairo_rectangle(cr, x0 + half * bar_px / 2, y0, bar_px / 2, 6);
    setColour(cr, half == 0 ? Rgb{0, 0, 0} : Rgb{255, 255, 255});
    cairo_fill_preserve(cr);
    setColour(cr, Rgb{0, 0, 0});
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
  }
  setColour(cr, Rgb{0, 0, 0});
  drawText(cr, "0", x0, y0 - 4, 11, 0.5, 1.0);
  drawText(cr, frame.scale_bar_label, x0 + bar_px, y0 - 4, 11, 0.5, 1.0);
  if (!frame.north_arrow) return;
  const double nx = kFrame.left + frame.viewport.widthPx() - 28.0;
  const double ny = kFrame.top + 22.0;
  cairo_set_source_rgba(cr, 1, 1, 1, 0.75);
  cairo_arc(cr, nx, ny + 8, 18, 0, 2 * M_PI);
  cairo_fill(cr);
  cairo_move_to(cr, nx, ny - 4);
  cairo_line_to(cr, nx + 7, ny + 16);
  cairo_line_to(cr, nx, ny + 11);
  cairo_line_to(cr, nx - 7, ny + 16);
  cairo_close_path(cr);
  setColour(cr, Rgb{0, 0, 0});
  cairo_fill(cr);
  drawText(cr, "N", nx, ny - 6, 11, 0.5, 1.0, true);
}

void drawFrameAndTicks(cairo_t* cr, const Frame& frame) {
  const double w = frame.viewport.widthPx();
  const double h = frame.viewport.heightPx();
  setColour(cr, Rgb{0, 0, 0});
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, kFrame.left - 0.5, kFrame.top - 0.5, w + 1, h + 1);
  cairo_stroke(cr);
  // A tick on both edges of one axis (outwards), labelled on the outer edge.
  auto segment = [cr](double x0, double y0, double x1, double y1) {
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
  };
  for (const FrameTick& t : frame.bottom_ticks) {
    const double x = kFrame.left + t.at_px;
    segment(x, kFrame.top + h, x, kFrame.top + h + 6);
    segment(x, kFrame.top, x, kFrame.top - 4);
    cairo_stroke(cr);
    drawText(cr, t.label, x, kFrame.top + h + 9, 11, 0.5, 0.0);
  }
  for (const FrameTick& t : frame.left_ticks) {
    const double y = kFrame.top + t.at_px;
    segment(kFrame.left, y, kFrame.left - 6, y);
    segment(kFrame.left + w, y, kFrame.left + w + 4, y);
    cairo_stroke(cr);
    drawText(cr, t.label, kFrame.left - 9, y, 11, 1.0, 0.5);
  }
}

// Top left inside the map: one row per line label, per marker kind drawn, and per background kind.
void drawLegend(cairo_t* cr, const Frame& frame, const MapFigureContent& content) {
  struct Row {
    std::function<void(double x, double y)> symbol;
    std::string label;
  };
  std::vector<Row> rows;
  std::vector<std::string> seen;
  for (const FigureLine& line : content.lines) {
    if (line.label.empty() || std::find(seen.begin(), seen.end(), line.label) != seen.end()) continue;
    seen.push_back(line.label);
    rows.push_back({[cr, line](double x, double y) {
                      cairo_move_to(cr, x - 12, y);
                      cairo_line_to(cr, x + 12, y);
                      const double dash[] = {6.0, 4.0};
                      cairo_set_dash(cr, dash, line.dashed ? 2 : 0, 0.0);
                      cairo_set_line_width(cr, std::min(line.width_px, 5.0));
                      setColour(cr, line.colour);
                      cairo_stroke(cr);
                      cairo_set_dash(cr, nullptr, 0, 0.0);
                    },
                    line.label});
  }
  const std::pair<MarkerKind, const char*> kinds[] = {{MarkerKind::kStart, "start"},
                                                      {MarkerKind::kEnd, "end"},
                                                      {MarkerKind::kMissionPoint, "mission point (visiting order)"},
                                                      {MarkerKind::kDepot, "depot"},
                                                      {MarkerKind::kTask, "task"}};
  for (const auto& [kind, label] : kinds) {
    auto m = std::find_if(content.markers.begin(), content.markers.end(),
                          [kind = kind](const FigureMarker& f) { return f.kind == kind; });
    if (m == content.markers.end()) continue;
    const FigureMarker shown = *m;
    rows.push_back({[cr, shown](double x, double y) {
                      setColour(cr, shown.colour);
                      drawMarkerSymbol(cr, shown.kind, x, y, shown.kind == MarkerKind::kMissionPoint ? 1 : 0,
                                       shown.colour);
                    },
                    label});
  }
  auto swatch = [cr](std::function<Rgb(int, int)> colourAt) {
    return [cr, colourAt](double x, double y) {
      for (int dy = -7; dy < 7; ++dy) {
        for (int dx = -11; dx < 11; ++dx) {
          setColour(cr, colourAt(dx + 11, dy + 7));
          cairo_rectangle(cr, x + dx, y + dy, 1, 1);
          cairo_fill(cr);
        }
      }
    };
  };
  if (!frame.blocked_label.empty()) {
    rows.push_back({swatch([](int, int) { return kFigureBlockedRgb; }), frame.blocked_label});
  }
  if (frame.raster.has_unknown && !frame.unknown_label.empty()) {
    rows.push_back({swatch([](int x, int y) { return figureHatch(x, y); }), frame.unknown_label});
  }
  if (rows.empty()) return;
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 12);
  double widest = 0.0;
  for (const Row& r : rows) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, r.label.c_str(), &e);
    widest = std::max(widest, e.x_advance);
  }
  const double row_px = 24.0;
  const double x = kFrame.left + 10.0;
  const double y = kFrame.top + 10.0;
  cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
  cairo_rectangle(cr, x, y, widest + 56.0, rows.size() * row_px + 8.0);
  cairo_fill(cr);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double cy = y + 4.0 + row_px * (i + 0.5);
    rows[i].symbol(x + 20.0, cy);
    setColour(cr, Rgb{0, 0, 0});
    drawText(cr, rows[i].label, x + 40.0, cy, 12, 0.0, 0.5);
  }
}

// Below the map: altitude and ground against distance, with labelled axes.
void drawProfile(cairo_t* cr, const Frame& frame, const FigureProfile& profile) {
  const std::size_t n = std::min({profile.distance_m.size(), profile.altitude_m.size(), profile.ground_m.size()});
  if (n < 2) return;
  const double top = kFrame.top + frame.viewport.heightPx() + kFrame.bottom + 10.0;
  const double left = kFrame.left;
  const double width = frame.viewport.widthPx();
  const double height = kFrame.profile_height - 10.0;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    for (double v : {profile.altitude_m[i], profile.ground_m[i]}) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi > lo)) hi = lo + 1.0;
  const double pad = 0.08 * (hi - lo);
  lo -= pad;
  hi += pad;
  const double d_max = std::max(profile.distance_m[n - 1], 1e-9);
  auto at = [&](double d, double v) {
    return Eigen::Vector2d(left + width * d / d_max, top + height * (1.0 - (v - lo) / (hi - lo)));
  };
  cairo_save(cr);
  cairo_rectangle(cr, left, top, width, height);
  cairo_clip(cr);
  cairo_new_path(cr);
  bool open = false;
  for (std::size_t i = 0; i <= n; ++i) {
    const bool known = i < n && std::isfinite(profile.ground_m[i]);
    if (known && !open) {
      cairo_move_to(cr, at(profile.distance_m[i], lo).x(), top + height);
      open = true;
    }
    if (known) {
      const Eigen::Vector2d p = at(profile.distance_m[i], profile.ground_m[i]);
      cairo_line_to(cr, p.x(), p.y());
    } else if (open) {
      cairo_line_to(cr, at(profile.distance_m[i - 1], lo).x(), top + height);
      cairo_close_path(cr);
      open = false;
    }
  }
  setColour(cr, kGroundRgb);
  cairo_fill(cr);
  if (profile.clearance_m > 0.0) {  // the clearance band: from the ground up by the clearance
    for (std::size_t i = 1; i < n; ++i) {
      if (!std::isfinite(profile.ground_m[i - 1]) || !std::isfinite(profile.ground_m[i])) continue;
      const Eigen::Vector2d a = at(profile.distance_m[i - 1], profile.ground_m[i - 1]);
      const Eigen::Vector2d b = at(profile.distance_m[i], profile.ground_m[i]);
      const Eigen::Vector2d c = at(profile.distance_m[i], profile.ground_m[i] + profile.clearance_m);
      const Eigen::Vector2d d = at(profile.distance_m[i - 1], profile.ground_m[i - 1] + profile.clearance_m);
      cairo_move_to(cr, a.x(), a.y());
      cairo_line_to(cr, b.x(), b.y());
      cairo_line_to(cr, c.x(), c.y());
      cairo_line_to(cr, d.x(), d.y());
      cairo_close_path(cr);
    }
    setColour(cr, kClearanceRgb, 0.45);
    cairo_fill(cr);
  }
  cairo_new_path(cr);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = at(profile.distance_m[i], profile.altitude_m[i]);
    cairo_line_to(cr, p.x(), p.y());
  }
  setColour(cr, kAltitudeRgb);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);
  cairo_restore(cr);
  setColour(cr, Rgb{0, 0, 0});
  cairo_set_line_width(cr, 1.0);
  cairo_rectangle(cr, left - 0.5, top - 0.5, width + 1, height + 1);
  cairo_stroke(cr);
  for (double v : roundTicks(lo, hi, 5)) {
    const double y = at(0.0, v).y();
    cairo_move_to(cr, left, y);
    cairo_line_to(cr, left - 6, y);
    cairo_stroke(cr);
    drawText(cr, formatDistance(v), left - 9, y, 11, 1.0, 0.5);
  }
  for (double d : roundTicks(0.0, d_max, 8)) {
    const double x = at(d, lo).x();
    cairo_move_to(cr, x, top + height);
    cairo_line_to(cr, x, top + height + 6);
    cairo_stroke(cr);
    drawText(cr, formatDistance(d), x, top + height + 9, 11, 0.5, 0.0);
  }
  drawText(cr, "distance along the trajectory", left + width / 2, top + height + 26, 12, 0.5, 0.0);
  drawText(cr, "altitude AMSL", left + 6, top + 6, 12, 0.0, 0.0, true);
  setColour(cr, kAltitudeRgb);
  drawText(cr, "flight", left + width - 70, top + 6, 12, 1.0, 0.0, true);
  setColour(cr, kGroundRgb);
  drawText(cr, "ground", left + width - 8, top + 6, 12, 1.0, 0.0, true);
  if (profile.clearance_m > 0.0) {
    setColour(cr, Rgb{200, 120, 30});
    char band[48];
    std::snprintf(band, sizeof band, "clearance %g m", profile.clearance_m);
    drawText(cr, band, left + width - 130, top + 6, 12, 1.0, 0.0, true);
  }
}

Status drawFigure(const Frame& frame, const MapFigureContent& content, const std::string& png_path) {
  const bool with_profile = content.profile && content.profile->distance_m.size() >= 2;
  const int width = static_cast<int>(kFrame.left + frame.viewport.widthPx() + kFrame.right);
  const int height = static_cast<int>(kFrame.top + frame.viewport.heightPx() + kFrame.bottom +
                                      (with_profile ? kFrame.profile_height + kFrame.profile_bottom : 0.0));
  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height));
  ContextPtr context(cairo_create(surface.get()));
  cairo_t* cr = context.get();
  setColour(cr, Rgb{255, 255, 255});
  cairo_paint(cr);
  paintRaster(cr, frame.raster);
  cairo_save(cr);
  cairo_rectangle(cr, kFrame.left, kFrame.top, frame.viewport.widthPx(), frame.viewport.heightPx());
  cairo_clip(cr);
  drawLines(cr, frame, content.lines);
  drawMarkers(cr, frame, content.markers);
  drawScaleAndNorth(cr, frame);
  drawLegend(cr, frame, content);
  cairo_restore(cr);
  drawFrameAndTicks(cr, frame);
  setColour(cr, Rgb{0, 0, 0});
  if (!content.title.empty()) drawText(cr, content.title, kFrame.left, kFrame.top / 2, 14, 0.0, 0.5, true);
  if (with_profile) drawProfile(cr, frame, *content.profile);
  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
    return make_error(ErrorCode::kInternal, png_path, std::string("drawing failed: ") + cairo_status_to_string(cairo_status(cr)));
  }
  const cairo_status_t written = cairo_surface_write_to_png(surface.get(), png_path.c_str());
  if (written != CAIRO_STATUS_SUCCESS) {
    return make_error(ErrorCode::kInvalidArgument, png_path,
                      std::string("cannot write PNG: ") + cairo_status_to_string(written));
  }
  return Status::success();
}

}  // namespace

Eigen::Vector2d figureMapOrigin() { return {kFrame.left, kFrame.top}; }

TerrainFigureLayout layoutTerrainFigure(const Heightfield& terrain, const MapFigureContent& content,
                                        const MapFigureOptions& options) {
  const Eigen::AlignedBox2d box = cropAround(contentBox(content, [](const Eigen::Vector2d& p) { return p; }),
                                             terrain.boundsEn(), options.margin_fraction, options.min_margin_m);
  TerrainFigureLayout layout;
  layout.viewport = MapViewport(box, options.map_long_side_px);
  const MapViewport& viewport = layout.viewport;
  const LocalFrame& local = terrain.frame();
  layout.ticks = geoTicks(
      viewport,
      [&](const Eigen::Vector2d& px) {
        Eigen::Vector2d en = viewport.toEastNorth(px);
        local.eastNorthToLonLat(&en.x(), &en.y(), 1);
        return en;
      },
      6);
  layout.scale_bar_m = roundStepAtMost(0.25 * viewport.widthPx() * viewport.metresPerPixel());
  return layout;
}

Status saveTerrainFigure(const Heightfield& terrain, const MapFigureContent& content, const std::string& png_path,
                         const MapFigureOptions& options) {
  const TerrainFigureLayout layout = layoutTerrainFigure(terrain, content, options);
  Frame frame;
  frame.viewport = layout.viewport;
  auto raster = terrainFigureRaster(terrain, frame.viewport);
  if (!raster.ok()) return raster.error();
  frame.raster = std::move(raster).value();
  frame.bottom_ticks = layout.ticks.longitudes;
  frame.left_ticks = layout.ticks.latitudes;
  frame.scale_bar_units = layout.scale_bar_m;
  frame.scale_bar_label = formatDistance(layout.scale_bar_m);
  frame.unknown_label = "no elevation data";
  frame.toMapPixel = [&viewport = frame.viewport](const Eigen::Vector2d& en) { return viewport.toPixel(en); };
  return drawFigure(frame, content, png_path);
}

Status saveGridFigure(const GridLayer& grid, bool north_up, const MapFigureContent& content,
                      const std::string& png_path, const MapFigureOptions& options) {
  // Cells become a north-up plane of unit squares: cell (x, y) covers [x, x + 1] east and, for
  // rows that grow southwards, [-(y + 1), -y] north.
  auto toPlane = [north_up](const Eigen::Vector2d& cell) {
    return Eigen::Vector2d(cell.x() + 0.5, north_up ? cell.y() + 0.5 : -(cell.y() + 0.5));
  };
  const Eigen::AlignedBox2d limits(Eigen::Vector2d(0.0, north_up ? 0.0 : -grid.height()),
                                   Eigen::Vector2d(grid.width(), north_up ? grid.height() : 0.0));
  const Eigen::AlignedBox2d box =
      cropAround(contentBox(content, toPlane), limits, options.margin_fraction, options.min_margin_cells);
  Frame frame;
  frame.viewport = MapViewport(box, options.map_long_side_px);
  const MapViewport& viewport = frame.viewport;
  frame.raster = gridFigureRaster(grid, north_up, viewport);
  const auto cellTicks = [](double lo, double hi, double at_lo_px, double px_per_cell, bool flip) {
    std::vector<FrameTick> ticks;
    for (double v : roundTicks(lo, hi, 6)) {
      const double index = flip ? -v : v;
      ticks.push_back({at_lo_px + (v - lo) * px_per_cell, index, std::to_string(static_cast<long>(std::lround(index)))});
    }
    return ticks;
  };
  const double px_per_cell = 1.0 / viewport.metresPerPixel();
  frame.bottom_ticks = cellTicks(box.min().x(), box.max().x(), 0.0, px_per_cell, false);
  // The left edge runs top to bottom: northing from max to min.
  for (FrameTick t : cellTicks(box.min().y(), box.max().y(), 0.0, px_per_cell, !north_up)) {
    t.at_px = viewport.heightPx() - t.at_px;
    frame.left_ticks.push_back(t);
  }
  frame.scale_bar_units = std::max(1.0, roundStepAtMost(0.25 * box.sizes().x()));
  char cells[32];
  std::snprintf(cells, sizeof cells, "%g cells", frame.scale_bar_units);
  frame.scale_bar_label = cells;
  frame.north_arrow = north_up;
  frame.blocked_label = "blocked cell";
  frame.toMapPixel = [&viewport, toPlane](const Eigen::Vector2d& cell) { return viewport.toPixel(toPlane(cell)); };
  return drawFigure(frame, content, png_path);
}

}  // namespace skyroute
