// Map figures a person can read, for `plan --png`, `fleet --png` and `grid path --png`: the map
// cropped to what is drawn plus a margin; routes; start, end and numbered mission-point markers; a
// scale bar with a north arrow; latitude/longitude ticks on the frame (cell ticks on grid maps); a
// legend; unknown terrain hatched; and, below the map, an altitude profile with labelled axes.
// Drawn with Cairo and saved as PNG.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "planning/core/result.hpp"
#include "service/figure_layout.hpp"
#include "service/map_image.hpp"
#include "terrain/grid_layer.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

// Coordinates are east/north metres of the terrain's local frame on terrain figures, and cell
// coordinates (column, row; cell centres at +0.5 are not assumed: pass cell indices) on grid ones.
struct FigureLine {
  std::string label;  // in the legend; lines sharing a label appear once
  std::vector<Eigen::Vector2d> points;
  Rgb colour;
  double width_px = 3.0;
  bool dashed = false;
};

enum class MarkerKind { kStart, kEnd, kMissionPoint, kTask, kDepot };

struct FigureMarker {
  MarkerKind kind = MarkerKind::kMissionPoint;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  int number = 0;  // drawn inside mission-point markers (the visiting order, from 1)
  Rgb colour{30, 60, 200};
};

// Altitude and the ground under it against distance along the route (metres).
struct FigureProfile {
  std::vector<double> distance_m;
  std::vector<double> altitude_m;
  std::vector<double> ground_m;
  double clearance_m = 0.0;  // shaded above the ground: the band the flight must stay over (0: none)
};

struct MapFigureContent {
  std::string title;
  std::vector<FigureLine> lines;
  std::vector<FigureMarker> markers;
  std::optional<FigureProfile> profile;
};

struct MapFigureOptions {
  int map_long_side_px = 1000;   // the map area, without frame, legend or profile
  double margin_fraction = 0.15; // around what is drawn, of its larger extent
  double min_margin_m = 300.0;   // terrain figures; grid figures use min_margin_cells
  double min_margin_cells = 3.0;
};

// Where the map of a terrain figure lies and where its ticks fall (for tests and callers that
// annotate further).
struct TerrainFigureLayout {
  MapViewport viewport{Eigen::AlignedBox2d(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones()), 1};
  GeoTicks ticks;
  double scale_bar_m = 0.0;
};

TerrainFigureLayout layoutTerrainFigure(const Heightfield& terrain, const MapFigureContent& content,
                                        const MapFigureOptions& options = {});

// Pixel offsets of the map area inside the saved image (the frame's left and top margins).
Eigen::Vector2d figureMapOrigin();

Status saveTerrainFigure(const Heightfield& terrain, const MapFigureContent& content, const std::string& png_path,
                         const MapFigureOptions& options = {});
// north_up: row numbers grow northwards (grids made from terrain), so rows are drawn flipped.
Status saveGridFigure(const GridLayer& grid, bool north_up, const MapFigureContent& content,
                      const std::string& png_path, const MapFigureOptions& options = {});

}  // namespace skyroute
