// A saved PNG's pixels read back through GDAL (independent of the library that drew them), for
// tests of pictures.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <gdal.h>

#include "service/map_image.hpp"

namespace skyroute::testing {

struct Picture {
  int width = 0;  // 0 when the file could not be read
  int height = 0;
  std::vector<std::uint8_t> bands[3];
  Rgb at(double x, double y) const {
    const auto col = static_cast<std::size_t>(std::floor(x));
    const auto row = static_cast<std::size_t>(std::floor(y));
    const std::size_t i = row * static_cast<std::size_t>(width) + col;
    return Rgb{bands[0][i], bands[1][i], bands[2][i]};
  }
  // How many pixels are within `tolerance` of `colour` in every channel.
  int count(Rgb colour, int tolerance) const;
};

inline bool nearRgb(Rgb a, Rgb b, int tolerance = 12) {
  return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance && std::abs(a.b - b.b) <= tolerance;
}

inline int Picture::count(Rgb colour, int tolerance) const {
  int n = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) n += nearRgb(at(x, y), colour, tolerance) ? 1 : 0;
  }
  return n;
}

inline Picture readPng(const std::string& path) {
  GDALAllRegister();
  Picture picture;
  GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
  if (!ds) return picture;
  picture.width = GDALGetRasterXSize(ds);
  picture.height = GDALGetRasterYSize(ds);
  for (int b = 0; b < 3; ++b) {
    picture.bands[b].resize(static_cast<std::size_t>(picture.width) * picture.height);
    if (b >= GDALGetRasterCount(ds) ||
        GDALRasterIO(GDALGetRasterBand(ds, b + 1), GF_Read, 0, 0, picture.width, picture.height,
                     picture.bands[b].data(), picture.width, picture.height, GDT_Byte, 0, 0) != CE_None) {
      picture.width = picture.height = 0;
      break;
    }
  }
  GDALClose(ds);
  return picture;
}

}  // namespace skyroute::testing
