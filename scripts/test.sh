#!/usr/bin/env bash
# Sets up, builds and runs every test, then the docs' runnable commands (the README's second
# command; CI runs exactly this). A second run rebuilds nothing that is up to date.
# Usage: scripts/test.sh [--preset default|asan] [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=default
if [ "${1:-}" = "--preset" ]; then preset="$2"; shift 2; fi
scripts/setup.sh --preset "$preset"
ctest --preset "$preset" -j "$(nproc)" "$@"
# The commands README.md and docs/ mark runnable, with the default build they name (build/).
if [ "$preset" = default ]; then scripts/check-docs.sh; fi
