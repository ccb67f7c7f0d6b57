#!/usr/bin/env bash
# Sets up, builds and runs the main job on the embedded default terrain (the README's first command):
# the terrain summary with a hillshade, then a 3D route across the ridge (RRT*, LOSPO, 7th-order
# spline trajectory) written as CSV, GeoJSON and a picture.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out
skyroute=build/service/skyroute
dem=data/default_terrain.tif
$skyroute terrain info "$dem" --png out/default_terrain_hillshade.png
echo
$skyroute plan --dem "$dem" --from 46.920,15.050,500 --via 46.950,15.090,700 --to 46.960,15.120,500 \
  --clearance 50 --vref 50 --seed 1 --budget-ms 300 \
  --out out/demo_route.csv --png out/demo_route.png
$skyroute plan --dem "$dem" --from 46.920,15.050,500 --via 46.950,15.090,700 --to 46.960,15.120,500 \
  --clearance 50 --vref 50 --seed 1 --budget-ms 300 --out out/demo_route.geojson > /dev/null
echo
echo "hillshade: out/default_terrain_hillshade.png"
echo "route:     out/demo_route.csv, out/demo_route.geojson, out/demo_route.png"
