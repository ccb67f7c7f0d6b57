// What a planned trajectory contributes to a map figure: its ground track as a line and its
// altitude against the ground as a profile (distance measured horizontally along the track).
#pragma once

#include <string>
#include <vector>

#include "service/map_figure.hpp"
#include "service/mission_types.hpp"
#include "terrain/heightfield.hpp"

namespace skyroute {

FigureLine trajectoryLine(const TrajectoryData& trajectory, const std::string& label, Rgb colour,
                          double width_px = 3.0);
FigureProfile trajectoryProfile(const Heightfield& terrain, const TrajectoryData& trajectory);
// A 3D polyline's ground track.
std::vector<Eigen::Vector2d> groundTrack(const std::vector<Eigen::Vector3d>& path_m);

}  // namespace skyroute
