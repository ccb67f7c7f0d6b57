#include "terrain/terrain_generator.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace skyroute {
namespace {

// Value noise on an integer lattice with smoothstep interpolation; the lattice values come from a
// seeded generator so the terrain is the same for the same seed on every machine.
class ValueNoise {
 public:
  ValueNoise(std::uint32_t seed, int size) : size_(size), values_(static_cast<std::size_t>(size) * size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (double& v : values_) v = uniform(rng);
  }
  double at(double x, double y) const {
    const int i = static_cast<int>(std::floor(x));
    const int j = static_cast<int>(std::floor(y));
    const double fx = smooth(x - i);
    const double fy = smooth(y - j);
    const double a = lattice(i, j) + fx * (lattice(i + 1, j) - lattice(i, j));
    const double b = lattice(i, j + 1) + fx * (lattice(i + 1, j + 1) - lattice(i, j + 1));
    return a + fy * (b - a);
  }

 private:
  static double smooth(double t) { return t * t * t * (t * (6.0 * t - 15.0) + 10.0); }  // C2 quintic
  double lattice(int i, int j) const {
    const int x = ((i % size_) + size_) % size_;
    const int y = ((j % size_) + size_) % size_;
    return values_[static_cast<std::size_t>(y) * size_ + x];
  }
  int size_;
  std::vector<double> values_;
};

}  // namespace

std::vector<float> generateTerrainHeights(const TerrainGeneratorOptions& o) {
  ValueNoise noise(o.seed, 256);
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double width_m = o.cell_size_m * o.width;
  const double height_m = o.cell_size_m * o.height;
  // Rounded hills scattered over the map.
  struct Hill {
    double x, y, radius, height;
  };
  std::vector<Hill> hills(28);
  for (Hill& h : hills) {
    h = Hill{unit(rng) * width_m, unit(rng) * height_m, 500.0 + 1500.0 * unit(rng), 0.15 + 0.45 * unit(rng)};
  }
  // A main ridge running north-south with a wavy crest and two passes, and a spur running east.
  const double wave_phase = 2.0 * M_PI * unit(rng);
  const double pass1 = 0.25 + 0.15 * unit(rng);
  const double pass2 = 0.6 + 0.15 * unit(rng);
  std::vector<float> heights(static_cast<std::size_t>(o.width) * o.height);
  for (int row = 0; row < o.height; ++row) {
    for (int col = 0; col < o.width; ++col) {
      const double x = (col + 0.5) * o.cell_size_m;  // metres east of the west edge
      const double y = (row + 0.5) * o.cell_size_m;  // metres south of the north edge
      const double fy = y / height_m;
      double h = 0.0;
      for (const Hill& hill : hills) {
        const double d2 = ((x - hill.x) * (x - hill.x) + (y - hill.y) * (y - hill.y)) / (hill.radius * hill.radius);
        h += hill.height * std::exp(-d2);
      }
      const double crest_x = width_m * (0.45 + 0.06 * std::sin(2.0 * M_PI * 1.3 * fy + wave_phase));
      const double across = (x - crest_x) / 700.0;
      const double gap1 = (fy - pass1) / 0.05;
      const double gap2 = (fy - pass2) / 0.04;
      const double passes = 1.0 - 0.55 * std::exp(-gap1 * gap1) - 0.45 * std::exp(-gap2 * gap2);
      h += 0.95 * std::exp(-across * across) * passes;
      const double spur_y = height_m * 0.7;
      const double spur_across = (y - spur_y - 0.15 * (x - crest_x)) / 450.0;
      if (x > crest_x) h += 0.55 * std::exp(-spur_across * spur_across) * std::exp(-(x - crest_x) / (0.45 * width_m));
      // Fractal roughness on top: gullies and knolls a few tens of metres high.
      double rough = 0.0;
      double amplitude = 1.0;
      double frequency = 8.0;
      for (int octave = 0; octave < 5; ++octave) {
        rough += amplitude * (noise.at(x / width_m * frequency + 13.0 * octave, y / height_m * frequency) - 0.5);
        amplitude *= 0.5;
        frequency *= 2.0;
      }
      const double value = o.base_height_m + o.relief_m * std::min(1.1, h) * (1.0 + 0.25 * rough) + 25.0 * rough;
      heights[static_cast<std::size_t>(row) * o.width + col] = static_cast<float>(value);
    }
  }
  return heights;
}

}  // namespace skyroute
