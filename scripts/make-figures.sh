#!/usr/bin/env bash
# Makes the example pictures of docs/figures.md (docs/figures/*.png) with the CLI, as a user would:
# `plan --png` and `fleet --png` on the embedded terrain, `grid path --png` on a Moving AI map from
# ../shared/data (skipped, with a message, when that folder is absent).
# Usage: scripts/make-figures.sh [OUT_DIR]   (builds with scripts/setup.sh if there is no build)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/figures}
skyroute=build/service/skyroute
[[ -x $skyroute ]] || scripts/setup.sh
mkdir -p "$out"
$skyroute plan --mission data/missions/demo_mission.json --png "$out/plan.png" > /dev/null
$skyroute fleet --file data/missions/demo_fleet.json --png "$out/fleet.png" > /dev/null
map=../shared/data/movingai/Boston_0_256.map
if [[ -f $map ]]; then
  $skyroute grid path --map "$map" --from 125,1 --to 26,233 --algo theta --png "$out/grid_path.png" > /dev/null
else
  echo "make-figures: $map is absent (../shared/data); no grid path picture" >&2
fi
ls -l "$out"/*.png
