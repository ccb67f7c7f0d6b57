// The output stage of HAB-PP and Improved HAB-PP: after the colony stops, the best ranked path is
// made taut within its route, or within the routes of the top ranked paths. The colony chooses the
// routes (which doors, which side of each obstacle); this stage removes the slack the ants'
// discrete steps leave in them and, given several ranked routes, picks the shortest way through
// them, so the output approaches the any-angle optimum of the colony's best route.
#pragma once

#include "planning/colony/hab_pp.hpp"

namespace skyroute::habpp {

// Shortest any-angle path found in the corridor of the route: the cells within corridor_cells
// (Chebyshev) of the cells the path's segments touch. Steps, Choice:
//   1. Theta* (planning/grid/any_angle_search) on a copy of the grid in which every cell outside the
//      corridor is blocked, so it can only follow the route (a door or gap farther than
//      corridor_cells from the route is closed to it);
//   2. the greedy farthest-visible shortcut and the vertex relaxation towards the obstacle corners
//      of tightenPath on that result and on the input;
//   3. the shorter of the two, the input when neither is shorter.
// The corridor keeps the route where the path stays more than corridor_cells from any door or gap
// it does not use; where it runs right past one (along the other side of a thin wall), the
// corridor holds that gap too and the output may take it when shorter (a local change of route).
// The result has the same endpoints, every segment passes GridLayer::lineOfSight on the original
// grid (the corridor only removes free cells), and it is never longer than the input.
// corridor_cells <= 0: step 2 on the input only.
Path tautPath(const GridLayer& grid, const Path& path, int corridor_cells, int tighten_passes);

// The same over several routes with common endpoints (the top ranked paths, best first): step 1
// runs twice, in the corridor of routes[0] and in the union of the corridors of all routes, whose
// shortest way may join pieces of different routes where they meet (as the path crossover does);
// step 2 takes routes[0] as the input; each other route is a candidate as it is. Never longer than
// tautPath(grid, routes[0], ...) or than any of the routes (that join the same endpoints); every cell
// it passes lies within corridor_cells of a cell some ranked route touched, so it never takes a
// door or gap that no ranked route went through or right past. routes must not be empty.
Path tautPath(const GridLayer& grid, const std::vector<Path>& routes, int corridor_cells, int tighten_passes);

// Local search by windowed re-planning, the output stage's last step. The corridor of tautPath
// keeps the route the colony chose; this step lets the route change locally, as a k-opt move
// does for a tour, where the colony went round the wrong side of an obstacle:
//   for each vertex i (start first) the window is the vertices i..j, j the farthest of i + segments
//   and the last vertex within span_cells of path length from i (j >= i + 2: a single segment
//   leaves nothing to gain); Theta* runs from vertex i to vertex j on the cells of the box that
//   bounds them, grown by margin_cells on each side (cells outside the box count as blocked); a
//   shorter way replaces the piece and the whole path is tightened again (tightenPath); passes over
//   the path repeat until one changes nothing, at most max_passes.
// Each accepted change makes the path strictly shorter and keeps every segment in sight on grid,
// so the result is never longer than the input and joins the same endpoints. The window is local
// by construction when given in segments (a few turns of the path); a span_cells as long as the
// path makes the step Theta* on the path's bounding box, which docs/benchmarks/habpp.md measures.
struct WindowOptions {
  int segments = 0;        // path segments per window; 0 or 1 (and span_cells 0): the step is off
  double span_cells = 0.0;  // windows reach at least this much path length, cells; 0: segments only
  int margin_cells = 8;    // the box around a window's vertices grows by this many cells per side
  int max_passes = 10;
};
Path replanWindows(const GridLayer& grid, const Path& path, const WindowOptions& options, int tighten_passes);

}  // namespace skyroute::habpp
