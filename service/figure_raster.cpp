#include "service/figure_raster.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace skyroute {

Rgb figureHatch(int x, int y) { return (x + y) % 8 < 2 ? Rgb{150, 150, 150} : Rgb{238, 238, 238}; }

Result<FigureRaster> terrainFigureRaster(const Heightfield& terrain, const MapViewport& viewport) {
  const Dem& dem = terrain.dem();
  Eigen::AlignedBox2d window;
  for (int i = 0; i <= 8; ++i) {
    const double f = i / 8.0;
    for (const Eigen::Vector2d& px : {Eigen::Vector2d(f * viewport.widthPx(), 0.0),
                                      Eigen::Vector2d(f * viewport.widthPx(), viewport.heightPx()),
                                      Eigen::Vector2d(0.0, f * viewport.heightPx()),
                                      Eigen::Vector2d(viewport.widthPx(), f * viewport.heightPx())}) {
      const Eigen::Vector2d en = viewport.toEastNorth(px);
      window.extend(terrain.enToPixel(en.x(), en.y()));
    }
  }
  const int col0 = std::clamp(static_cast<int>(std::floor(window.min().x())) - 2, 0, dem.width() - 1);
  const int row0 = std::clamp(static_cast<int>(std::floor(window.min().y())) - 2, 0, dem.height() - 1);
  const int col1 = std::clamp(static_cast<int>(std::ceil(window.max().x())) + 2, col0, dem.width() - 1);
  const int row1 = std::clamp(static_cast<int>(std::ceil(window.max().y())) + 2, row0, dem.height() - 1);
  auto shade = MapImage::hillshade(dem, col0, row0, col1 - col0 + 1, row1 - row0 + 1);
  if (!shade.ok()) return shade.error();
  FigureRaster raster;
  raster.width = viewport.widthPx();
  raster.height = viewport.heightPx();
  raster.pixels.resize(static_cast<std::size_t>(raster.width) * raster.height);
  auto known = [&](int c, int r) {
    return c >= col0 && r >= row0 && c <= col1 && r <= row1 && !std::isnan(dem.cell(c, r));
  };
  for (int y = 0; y < raster.height; ++y) {
    for (int x = 0; x < raster.width; ++x) {
      Rgb& out = raster.pixels[static_cast<std::size_t>(y) * raster.width + x];
      const Eigen::Vector2d en = viewport.toEastNorth({x + 0.5, y + 0.5});
      const Eigen::Vector2d p = terrain.enToPixel(en.x(), en.y());
      const int c = static_cast<int>(std::lround(p.x()));
      const int r = static_cast<int>(std::lround(p.y()));
      if (c < 0 || r < 0 || c >= dem.width() || r >= dem.height()) {
        out = kFigureOutsideRgb;
        continue;
      }
      if (!known(c, r)) {
        out = figureHatch(x, y);
        raster.has_unknown = true;
        continue;
      }
      const int c0 = static_cast<int>(std::floor(p.x()));
      const int r0 = static_cast<int>(std::floor(p.y()));
      if (!known(c0, r0) || !known(c0 + 1, r0) || !known(c0, r0 + 1) || !known(c0 + 1, r0 + 1)) {
        out = shade->pixel(c - col0, r - row0);
        continue;
      }
      const double fx = p.x() - c0;
      const double fy = p.y() - r0;
      const Rgb a = shade->pixel(c0 - col0, r0 - row0), b = shade->pixel(c0 + 1 - col0, r0 - row0);
      const Rgb d = shade->pixel(c0 - col0, r0 + 1 - row0), e = shade->pixel(c0 + 1 - col0, r0 + 1 - row0);
      auto mix = [&](std::uint8_t va, std::uint8_t vb, std::uint8_t vd, std::uint8_t ve) {
        const double v = (1 - fy) * ((1 - fx) * va + fx * vb) + fy * ((1 - fx) * vd + fx * ve);
        return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      };
      out = Rgb{mix(a.r, b.r, d.r, e.r), mix(a.g, b.g, d.g, e.g), mix(a.b, b.b, d.b, e.b)};
    }
  }
  return raster;
}

FigureRaster gridFigureRaster(const GridLayer& grid, bool north_up, const MapViewport& viewport) {
  FigureRaster raster;
  raster.width = viewport.widthPx();
  raster.height = viewport.heightPx();
  raster.pixels.resize(static_cast<std::size_t>(raster.width) * raster.height);
  for (int y = 0; y < raster.height; ++y) {
    for (int x = 0; x < raster.width; ++x) {
      const Eigen::Vector2d p = viewport.toEastNorth({x + 0.5, y + 0.5});
      const GridCell cell{static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(north_up ? p.y() : -p.y()))};
      raster.pixels[static_cast<std::size_t>(y) * raster.width + x] =
          !grid.inside(cell) ? kFigureOutsideRgb : (grid.blocked(cell) ? kFigureBlockedRgb : kFigureFreeRgb);
    }
  }
  return raster;
}

}  // namespace skyroute
