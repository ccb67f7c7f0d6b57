// The background of a map figure, one colour per pixel of the map area: the terrain's tinted
// hillshade (unknown cells hatched, ground outside the DEM plain grey), or a grid's free and
// blocked cells.
#pragma once

#include <vector>

#include "planning/core/result.hpp"
#include "service/figure_layout.hpp"
#include "service/map_image.hpp"
#include "terrain/grid_layer.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

struct FigureRaster {
  int width = 0;
  int height = 0;
  std::vector<Rgb> pixels;   // row by row from the top
  bool has_unknown = false;  // some pixel is hatched
};

inline constexpr Rgb kFigureOutsideRgb{226, 226, 226};
inline constexpr Rgb kFigureBlockedRgb{90, 90, 90};
inline constexpr Rgb kFigureFreeRgb{255, 255, 255};

// Diagonal stripes: what a person reads as "no data" (unlike a colour, which reads as a value).
Rgb figureHatch(int x, int y);

// The hillshade of the DEM window under the viewport, sampled bilinearly.
Result<FigureRaster> terrainFigureRaster(const Heightfield& terrain, const MapViewport& viewport);
// Cells of a grid drawn as a north-up plane: cell (x, y) covers [x, x + 1] east and [y, y + 1]
// north when north_up, [-(y + 1), -y] otherwise (rows that grow southwards).
FigureRaster gridFigureRaster(const GridLayer& grid, bool north_up, const MapViewport& viewport);

}  // namespace skyroute
