#!/usr/bin/env bash
# Builds the Debian package from the build folder (./build, or $SKYROUTE_BUILD_DIR), after
# bringing the build up to date, and prints the package's path: build/skyroute_<version>_<arch>.deb.
# Its Depends are the runtime libraries the binaries link (dpkg-shlibdeps) and proj-data.
# Usage: scripts/package.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build="${SKYROUTE_BUILD_DIR:-build}"
[ -f "$build/CPackConfig.cmake" ] || cmake --preset default >/dev/null
rm -f "$build"/skyroute_*.deb
(cd "$build" && cpack -G DEB >/dev/null)
ls "$PWD/$build"/skyroute_*.deb
