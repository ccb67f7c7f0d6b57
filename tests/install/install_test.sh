#!/usr/bin/env bash
# `cmake --install` of the build, staged under a temporary DESTDIR, then moved elsewhere:
#   - the layout: bin/skyroute and bin/skyrouted, the shipped data in share/skyroute, the
#     configuration /etc/skyroute/skyrouted.toml byte-identical to `skyrouted --print-config`, and
#     the systemd unit with its restart policy, its own user, its state folder and its sandbox
#     (checked by `systemd-analyze verify` and `security` when systemd-analyze is installed);
#   - the moved binaries find the default terrain in their own share/skyroute: `skyroute plan`
#     and `skyrouted` work without --dem;
#   - without the data, both fail with exit code 3, naming the folder they searched.
# Usage: install_test.sh BUILD_DIR [CMAKE] [DDS_DOMAIN]
set -euo pipefail
build="$1"
cmake_bin="${2:-cmake}"
domain="${3:-230}"

tmp="$(mktemp -d)"
daemon_pid=""
cleanup() {
  if [ -n "$daemon_pid" ]; then kill "$daemon_pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
failures=0
check() {  # check DESCRIPTION COMMAND...: runs the command, reports and counts a failure
  local what="$1"
  shift
  if "$@"; then echo "ok: $what"; else echo "FAILED: $what"; failures=$((failures + 1)); fi
}

DESTDIR="$tmp/stage" "$cmake_bin" --install "$build" --prefix /usr >"$tmp/install.log"
stage="$tmp/stage"

# Layout.
check "bin/skyroute is executable" test -x "$stage/usr/bin/skyroute"
check "bin/skyrouted is executable" test -x "$stage/usr/bin/skyrouted"
for f in default_terrain.tif README.md missions/demo_mission.json feeds/default_terrain_table1.jsonl; do
  check "share/skyroute/$f is installed" test -f "$stage/usr/share/skyroute/$f"
done
config="$stage/etc/skyroute/skyrouted.toml"
check "/etc/skyroute/skyrouted.toml is installed" test -f "$config"
"$stage/usr/bin/skyrouted" --print-config >"$tmp/print-config.toml"
check "skyrouted.toml is byte-identical to skyrouted --print-config" cmp "$config" "$tmp/print-config.toml"
check "skyrouted.toml documents its keys" grep -q '^# DEM raster path' "$config"

# The systemd unit.
unit="$stage/usr/lib/systemd/system/skyrouted.service"
check "lib/systemd/system/skyrouted.service is installed" test -f "$unit"
for line in "ExecStart=/usr/bin/skyrouted --config /etc/skyroute/skyrouted.toml" "Restart=on-failure" \
  "DynamicUser=yes" "StateDirectory=skyroute" "ProtectSystem=strict" "ProtectHome=yes" "PrivateTmp=yes" \
  "NoNewPrivileges=yes" "PrivateDevices=yes" "CapabilityBoundingSet=" "WantedBy=multi-user.target"; do
  check "unit has $line" grep -qxF "$line" "$unit"
done
if command -v systemd-analyze >/dev/null; then
  # verify wants the binary to exist: point a copy of the unit at the staged one.
  sed "s#/usr/bin/skyrouted#$stage/usr/bin/skyrouted#" "$unit" >"$tmp/skyrouted.service"
  verify_out="$(systemd-analyze verify "$tmp/skyrouted.service" 2>&1)" && verify_rc=0 || verify_rc=$?
  check "systemd-analyze verify passes without warnings ($verify_out)" test "$verify_rc" = 0 -a -z "$verify_out"
  exposure="$(systemd-analyze security --offline=yes "$tmp/skyrouted.service" 2>&1 | sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p')"
  check "systemd-analyze security rates the sandbox below 2.0 (got '$exposure')" \
    awk -v e="$exposure" 'BEGIN { exit !(e != "" && e + 0 < 2.0) }'
else
  echo "note: systemd-analyze is not installed; the unit's keys were checked by name only"
fi

# Moved elsewhere, the binaries find their data beside them.
moved="$tmp/elsewhere/prefix"
mkdir -p "$tmp/elsewhere"
mv "$stage/usr" "$moved"
plan_out="$("$moved/bin/skyroute" plan --mission "$moved/share/skyroute/missions/demo_mission.json" \
  --out "$tmp/plan.csv" 2>&1)" && plan_rc=0 || plan_rc=$?
check "moved skyroute plans without --dem (exit $plan_rc)" test "$plan_rc" = 0
check "it loaded the moved default terrain" grep -qF "loading $moved/share/skyroute/default_terrain.tif" <<<"$plan_out"
check "it wrote the trajectory" test "$(wc -l <"$tmp/plan.csv")" -gt 100

export CYCLONEDDS_URI='<CycloneDDS><Domain id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers><MaxAutoParticipantIndex>120</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>'
"$moved/bin/skyrouted" --domain "$domain" --config "$config" >"$tmp/daemon.log" 2>&1 &
daemon_pid=$!
for _ in $(seq 1 200); do
  grep -q "event=ready" "$tmp/daemon.log" && break
  kill -0 "$daemon_pid" 2>/dev/null || break
  sleep 0.1
done
check "moved skyrouted serves with the installed configuration and no --dem" grep -q "event=ready" "$tmp/daemon.log"
check "it loaded the moved default terrain" grep -qF "dem=$moved/share/skyroute/default_terrain.tif" "$tmp/daemon.log"
kill -TERM "$daemon_pid" 2>/dev/null || true
wait "$daemon_pid" && daemon_rc=0 || daemon_rc=$?
daemon_pid=""
check "it stops cleanly on SIGTERM (exit $daemon_rc)" test "$daemon_rc" = 0

# Without the data: a clear error naming the place searched, and the bad-input code.
mv "$moved/share/skyroute" "$tmp/data-away"
missing_out="$("$moved/bin/skyroute" plan --mission "$tmp/data-away/missions/demo_mission.json" 2>&1)" \
  && missing_rc=0 || missing_rc=$?
check "skyroute plan without its data exits 3 (got $missing_rc)" test "$missing_rc" = 3
check "it names the terrain and the folder searched ($missing_out)" \
  grep -qF "default_terrain.tif was not found; searched $moved/share/skyroute" <<<"$missing_out"
daemon_out="$("$moved/bin/skyrouted" --domain "$domain" 2>&1)" && missing_rc=0 || missing_rc=$?
check "skyrouted without its data exits 3 (got $missing_rc)" test "$missing_rc" = 3
check "it names the folder searched" grep -qF "searched $moved/share/skyroute" <<<"$daemon_out"

if [ "$failures" -ne 0 ]; then
  echo "$failures check(s) failed"
  exit 1
fi
echo "all install checks passed"
