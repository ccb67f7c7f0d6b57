#!/usr/bin/env bash
# Makes docs/gcs_map.png: the live map of `skyroute gcs --serve` during the demo, shot by headless
# chromium. Starts skyrouted and the ground station on loopback (DDS domain $SKYROUTE_SHOT_DOMAIN),
# publishes data/missions/demo_mission.json and a second vehicle's mission, replays the shipped
# obstacle feed so the daemon replans, lets the vehicles fly on for $SKYROUTE_SHOT_AFTER_S
# seconds, then shoots the page.
# Usage: scripts/gcs-screenshot.sh [OUT.png]   (builds with scripts/setup.sh if there is no build)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/gcs_map.png}
skyroute=build/service/skyroute
skyrouted=build/service/skyrouted
domain=${SKYROUTE_SHOT_DOMAIN:-208}
after_s=${SKYROUTE_SHOT_AFTER_S:-20}
[[ -x $skyroute && -x $skyrouted ]] || scripts/setup.sh
command -v chromium > /dev/null || { echo "gcs-screenshot: needs chromium (scripts/setup.sh installs it)" >&2; exit 1; }

# Loopback only, as scripts/demo.sh: `lo` has no multicast, so Cyclone finds peers on 127.0.0.1.
if [[ -z "${CYCLONEDDS_URI:-}" ]]; then
  export CYCLONEDDS_URI='<CycloneDDS><Domain id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>'
fi

work=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2> /dev/null || true; done
  wait || true
  rm -rf "$work"
}
trap cleanup EXIT

$skyrouted --domain "$domain" 2> "$work/skyrouted.log" &
pids+=($!)
$skyroute gcs --domain "$domain" --serve 127.0.0.1:0 > "$work/gcs.out" 2>&1 &
pids+=($!)
url=""
for _ in $(seq 200); do  # the ground station prints the page's address once it serves
  url=$(grep -o 'http://[^ ]*' "$work/gcs.out" 2> /dev/null || true)
  [[ -n $url ]] && break
  sleep 0.1
done
[[ -n $url ]] || { echo "gcs-screenshot: the ground station did not serve:" >&2; cat "$work/gcs.out" >&2; exit 1; }
echo "== live map at $url"

$skyroute request --domain "$domain" --file data/missions/demo_mission.json --wait 120
# A second vehicle with the demo's limits, so the picture shows how vehicles are told apart.
$skyroute request --domain "$domain" --file data/missions/demo_mission.json --vehicle uav-survey \
  --request-id survey-1 --begin 46.905,15.025,1000 --points "46.975,15.030,1000;46.985,15.120,1000" \
  --end 46.930,15.150,1000 --wait 120
$skyroute replay data/feeds/default_terrain_table1.jsonl --domain "$domain" --readers 2  # the daemon and the map
sleep "$after_s"

# --timeout: stop loading after 3 s (the event stream never ends) and shoot what is drawn.
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking \
  --disable-component-update --disable-sync --user-data-dir="$work/chromium" --hide-scrollbars \
  --window-size=1400,1000 --timeout=3000 --screenshot="$out" "$url" 2> "$work/chromium.log" \
  || { cat "$work/chromium.log" >&2; exit 1; }
echo "wrote $out"
