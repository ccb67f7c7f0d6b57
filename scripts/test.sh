#!/usr/bin/env bash
# Sets up, builds and runs every test (the README's second command; CI runs exactly this).
# Usage: scripts/test.sh [--preset default|asan] [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=default
if [ "${1:-}" = "--preset" ]; then preset="$2"; shift 2; fi
scripts/setup.sh --preset "$preset"
ctest --preset "$preset" -j "$(nproc)" "$@"
