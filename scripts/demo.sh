#!/usr/bin/env bash
# The main job on the embedded default terrain (the README's first command): sets up and builds,
# starts the planning daemon skyrouted, watches it as a ground station would (skyroute gcs),
# publishes the demo mission (skyroute request), then replays the shipped obstacle feed (three
# obstacles moving across the route, as Table 1 of seed 003) so the daemon replans and publishes
# new revisions. Everything stays on this machine (loopback), on DDS domain $SKYROUTE_DEMO_DOMAIN.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
mkdir -p out
skyroute=build/service/skyroute
skyrouted=build/service/skyrouted
domain=${SKYROUTE_DEMO_DOMAIN:-77}
watch_s=${SKYROUTE_DEMO_SECONDS:-40}

# Loopback only: `lo` has no multicast, so Cyclone finds its peers by unicast on 127.0.0.1, one
# participant index per process: MaxAutoParticipantIndex 120 allows 121 processes per domain.
if [[ -z "${CYCLONEDDS_URI:-}" ]]; then
  export CYCLONEDDS_URI='<CycloneDDS><Domain id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers><MaxAutoParticipantIndex>120</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>'
fi

$skyroute terrain info data/default_terrain.tif --png out/default_terrain_hillshade.png
echo

echo "== starting skyrouted on domain $domain (log: out/skyrouted.log)"
$skyrouted --domain "$domain" 2> out/skyrouted.log &
daemon=$!
gcs=""
cleanup() {
  kill -TERM "$daemon" 2> /dev/null || true
  if [[ -n "$gcs" ]]; then kill -TERM "$gcs" 2> /dev/null || true; fi
}
trap cleanup EXIT

echo "== ground station: skyroute gcs (prints every trajectory revision and status for ${watch_s} s)"
$skyroute gcs --domain "$domain" --timeout "$watch_s" --csv out/demo_trajectory.csv \
  --geojson out/demo_trajectory.geojson --kml out/demo_trajectory.kml &
gcs=$!

echo "== mission: skyroute request --file data/missions/demo_mission.json"
$skyroute request --domain "$domain" --file data/missions/demo_mission.json --wait 120

echo "== obstacles: skyroute replay data/feeds/default_terrain_table1.jsonl"
$skyroute replay data/feeds/default_terrain_table1.jsonl --domain "$domain" --readers 1

wait "$gcs" || true
gcs=""
kill -TERM "$daemon"
wait "$daemon" || true
trap - EXIT
echo
grep -c "event=replanned" out/skyrouted.log | xargs -I{} echo "replans while watching: {}"
echo "daemon log:  out/skyrouted.log"
echo "trajectory:  out/demo_trajectory.csv, out/demo_trajectory.geojson, out/demo_trajectory.kml"
echo "hillshade:   out/default_terrain_hillshade.png"
