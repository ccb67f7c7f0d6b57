#!/usr/bin/env bash
# Builds the libFuzzer harnesses (preset `fuzz`: clang-14, ASan + UBSan, in build-fuzz) and runs
# each for SECONDS (default 30), one after the other, from its seeds in tests/fuzz/corpus/<name>/
# plus what earlier runs found (build-fuzz/corpus/<name>/). Any crash, sanitizer report, hang (an
# input over 5 s), leak or allocation over 2 GB fails the run; the input is kept in
# build-fuzz/artifacts/<name>/ and the log in build-fuzz/logs/<name>.log. docs/fuzzing.md says more.
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS...]   (harnesses: the tests/fuzz/*_fuzzer.cpp names)
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=scripts/lib/install_packages.sh
source scripts/lib/install_packages.sh

seconds="${1:-30}"
if [ $# -gt 0 ]; then shift; fi
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "fuzz: SECONDS must be a positive integer (got '$seconds')" >&2
  exit 2
fi

# The compiler and libFuzzer, then what the fuzz build's find_package calls need (the libraries of
# the top-level and service/ CMakeLists; no tests, no benchmarks).
PACKAGES=(
  clang-14 libclang-rt-14-dev libfuzzer-14-dev
  cmake ccache pkg-config
  libeigen3-dev libgdal-dev liboctomap-dev libfcl-dev cyclonedds-dev cyclonedds-tools
  libnanoflann-dev libcli11-dev libspdlog-dev nlohmann-json3-dev libtomlplusplus-dev libcairo2-dev libssl-dev openssl libsqlite3-dev
)
install_missing_packages fuzz "${PACKAGES[@]}"

started=$(date +%s)
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"
echo "fuzz: build took $(( $(date +%s) - started )) s"

harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
  for f in tests/fuzz/*_fuzzer.cpp; do
    f=$(basename "$f" _fuzzer.cpp)
    harnesses+=("$f")
  done
fi

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
failed=()
summary=()
for name in "${harnesses[@]}"; do
  binary="build-fuzz/tests/fuzz/fuzz_$name"
  seeds="tests/fuzz/corpus/$name"
  if [ ! -x "$binary" ] || [ ! -d "$seeds" ]; then
    echo "fuzz: no harness '$name' (expected $binary and $seeds)" >&2
    exit 2
  fi
  corpus="build-fuzz/corpus/$name"
  artifacts="build-fuzz/artifacts/$name"
  log="build-fuzz/logs/$name.log"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  echo "fuzz: $name for $seconds s"
  status=0
  # New inputs go to the first folder (in build-fuzz); the seeds (with regressions/) are only read.
  # A fixed seed (SKYROUTE_FUZZ_SEED, default 1) makes a run reproducible: the same mutations in the
  # same order, as far as the time allows.
  "$binary" -seed="${SKYROUTE_FUZZ_SEED:-1}" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$artifacts/" "$corpus" "$seeds" >"$log" 2>&1 || status=$?
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  coverage=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1)
  line=$(printf '%-15s %10s executions %7s/s  %-22s' "$name" "${executions:-?}" "${rate:-?}" "${coverage:-cov: ?}")
  if [ "$status" -ne 0 ]; then
    failed+=("$name")
    line="$line FAILED (exit $status; $log)"
    echo "fuzz: $name failed; the end of its log:" >&2
    tail -n 40 "$log" >&2
  fi
  summary+=("$line")
done

echo
echo "fuzz: ${seconds} s per harness, $(( $(date +%s) - started )) s in all (build included)"
printf '%s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: FAILED: ${failed[*]} (inputs in build-fuzz/artifacts/)" >&2
  exit 1
fi
