#!/usr/bin/env bash
# Installs every Debian package the build, tests and benchmarks need (skipping what is there),
# then configures (the first time) and builds skyroute in the preset's folder (build/, build-asan/).
# Usage: scripts/setup.sh [--preset default|asan] [extra cmake --build args, e.g. --target skyroute]
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=scripts/lib/install_packages.sh
source scripts/lib/install_packages.sh

PACKAGES=(
  build-essential cmake ccache pkg-config
  libeigen3-dev libgdal-dev gdal-bin liboctomap-dev libfcl-dev
  libproj-dev proj-data
  cyclonedds-dev cyclonedds-tools
  libnanoflann-dev libcli11-dev libspdlog-dev nlohmann-json3-dev libtomlplusplus-dev libcairo2-dev libssl-dev openssl libsqlite3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libompl-dev
  tshark  # the ROS 2 mirror's packet-capture test (tests/daemon/ros2_e2e_test.cpp)
  libcpp-httplib-dev chromium chromium-driver
  systemd  # systemd-analyze checks the installed unit (tests/install/install_test.sh)
)

install_missing_packages setup "${PACKAGES[@]}"

preset=default
if [ "${1:-}" = "--preset" ]; then preset="$2"; shift 2; fi
case "$preset" in
  default) build_dir=build ;;
  *) build_dir="build-$preset" ;;
esac
# Configure once: afterwards the build itself re-runs CMake when a CMakeLists.txt changed, so a
# second run neither reconfigures nor rebuilds what is up to date.
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake --preset "$preset" >/dev/null
fi
cmake --build --preset "$preset" -j "$(nproc)" "$@"
