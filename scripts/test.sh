#!/usr/bin/env bash
# Sets up, builds and runs every test, then the docs' runnable commands (the README's second
# command; CI runs exactly this). A second run rebuilds nothing that is up to date.
# --fast, while developing: builds only the unit tests' executables (target unit_tests) and runs
# the tests labelled unit (in-process and quick) and check (the layer and docs checks' own tests).
# Usage: scripts/test.sh [--fast] [--preset default|asan] [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
preset=default
fast=false
while [ $# -gt 0 ]; do
  case "$1" in
    --fast) fast=true; shift ;;
    --preset) preset="$2"; shift 2 ;;
    *) break ;;
  esac
done
if $fast; then
  scripts/setup.sh --preset "$preset" --target unit_tests
  ctest --preset "$preset" -j "$(nproc)" -L '^(unit|check)$' "$@"
  exit
fi
scripts/setup.sh --preset "$preset"
ctest --preset "$preset" -j "$(nproc)" "$@"
# The commands README.md and docs/ mark runnable, with the default build they name (build/).
if [ "$preset" = default ]; then scripts/check-docs.sh; fi
