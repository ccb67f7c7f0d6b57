#!/usr/bin/env bash
# CI: the Debian package as a user gets it. Builds the .deb from build/, checks its Depends,
# installs it with apt-get, and from a folder outside the checkout plans the README's demo mission
# with the installed binary and data only (/usr/bin/skyroute, /usr/share/skyroute); checks the
# installed configuration and systemd unit. A package that was not installed before is purged
# afterwards. Needs root and apt-get (a Debian CI machine); elsewhere it says so and does nothing.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v apt-get >/dev/null || [ "$(id -u)" -ne 0 ]; then
  echo "install-deb: skipped (needs root and apt-get)"
  exit 0
fi

deb="$(scripts/package.sh)"
echo "install-deb: built $deb"
depends="$(dpkg-deb -f "$deb" Depends)"
for needed in libgdal libddsc0 libproj libspdlog liboctomap libfcl proj-data; do
  if ! grep -q "$needed" <<<"$depends"; then
    echo "install-deb: Depends lacks $needed: $depends"
    exit 1
  fi
done

was_installed=no
dpkg-query -W -f='${Status}' skyroute 2>/dev/null | grep -q "install ok installed" && was_installed=yes
tmp="$(mktemp -d)"
cleanup() {
  cd / && rm -rf "$tmp"
  if [ "$was_installed" = no ]; then DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq skyroute >/dev/null || true; fi
}
trap cleanup EXIT
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$deb" >/dev/null
echo "install-deb: installed $(dpkg-query -W -f='${Package} ${Version}' skyroute)"

cd "$tmp"  # nothing of the checkout is reachable from here by a relative path
/usr/bin/skyroute plan --mission /usr/share/skyroute/missions/demo_mission.json --out "$tmp/plan.csv" \
  --png "$tmp/plan.png" 2>&1 | tee "$tmp/plan.log"
grep -qF "loading /usr/share/skyroute/default_terrain.tif" "$tmp/plan.log"
[ "$(wc -l <"$tmp/plan.csv")" -gt 100 ]
cmp /etc/skyroute/skyrouted.toml <(/usr/bin/skyrouted --print-config)
if command -v systemd-analyze >/dev/null; then
  out="$(systemd-analyze verify /usr/lib/systemd/system/skyrouted.service 2>&1)"
  [ -z "$out" ] || { echo "install-deb: systemd-analyze verify: $out"; exit 1; }
fi
echo "install-deb: the installed package plans from /usr/bin and /usr/share/skyroute"
