#!/usr/bin/env bash
# Sets up, builds and runs the main job on the embedded default terrain (the README's first command).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out
build/service/skyroute terrain info data/default_terrain.tif --png out/default_terrain_hillshade.png
echo "hillshade written to out/default_terrain_hillshade.png"
