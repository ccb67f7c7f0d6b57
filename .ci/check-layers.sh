#!/usr/bin/env bash
# Fails when a lower layer includes a higher one, naming the file, the line and the include.
#
# Layers, lowest first (README's layout table):
#   planning/core      Eigen and the standard library only; includes itself only
#   terrain            planning/core, terrain
#   planning/<sub>     planning/core, terrain, itself, and the planning subfolders listed for it
#                      below (each may only name subfolders before it in PLANNING_ORDER: no cycles)
#   trajectory         planning/core, trajectory
#   bench/support      the planning layers it measures (never service/)
#   service            anything; but the headers idlc generates from idl/*.idl, and service/dds/,
#                      only from service/dds/, service/daemon/ and the CLI's DDS commands
# tests/ and the benchmarks themselves are not a layer: they may include what they exercise.
#
# Usage: .ci/check-layers.sh [--root DIR]   check the tree at DIR (default: this repository)
#        .ci/check-layers.sh --self-test    check that a tree with a violation of each kind fails
set -euo pipefail

# Planning subfolders in dependency order, and what each may include besides core and terrain.
PLANNING_ORDER=(grid mission sampling colony fleet)
declare -A PLANNING_USES=(
  [grid]=""
  [mission]="grid"
  [sampling]=""
  [colony]="grid"
  [fleet]="grid"
)
# The CLI files that speak DDS (service/cli/dds_commands.hpp registers them).
DDS_CLI_FILES=(
  service/cli/dds_cli_common.hpp service/cli/dds_cli_common.cpp service/cli/gcs_command.cpp
  service/cli/request_command.cpp service/cli/record_command.cpp service/cli/replay_command.cpp
  service/cli/px4_command.cpp service/cli/fleet_dds_command.cpp service/cli/cancel_command.cpp
  service/cli/status_command.cpp service/cli/nofly_command.cpp
)
# Libraries the Eigen-only layers must not reach (GDAL/OGR/CPL, FCL, OctoMap, Cyclone DDS, ...).
FOREIGN_HEADER_PATTERN='^(gdal|ogr|cpl_|ogrsf|fcl/|octomap/|dds/|ddsc/|nlohmann/|spdlog/|CLI/|toml\+\+/)'

# The layer a repository path (a file, or a quoted include) belongs to; "" when none.
layer_of() {
  local path="$1"
  case "$path" in
    planning/core/*) echo "planning/core" ;;
    planning/*/*) echo "planning/$(cut -d/ -f2 <<<"$path")" ;;
    planning/*) echo "planning" ;;  # a file straight in planning/: not allowed (see below)
    terrain/*) echo "terrain" ;;
    trajectory/*) echo "trajectory" ;;
    bench/support/*) echo "bench/support" ;;
    bench/*) echo "bench" ;;
    service/*) echo "service" ;;
    tests/*) echo "tests" ;;
    *) echo "" ;;
  esac
}

# Space-separated layers a layer may include.
allowed_for() {
  local layer="$1" sub uses dep
  case "$layer" in
    planning/core) echo "planning/core" ;;
    terrain) echo "planning/core terrain" ;;
    trajectory) echo "planning/core trajectory" ;;
    bench/support)
      local all="planning/core terrain bench/support"
      for sub in "${PLANNING_ORDER[@]}"; do all+=" planning/$sub"; done
      echo "$all" ;;
    planning/*)
      sub="${layer#planning/}"
      [[ -v "PLANNING_USES[$sub]" ]] || { echo "?"; return; }
      uses="planning/core terrain $layer"
      for dep in ${PLANNING_USES[$sub]}; do uses+=" planning/$dep"; done
      echo "$uses" ;;
    *) echo "*" ;;
  esac
}

# The planning table itself must be acyclic: a subfolder may only use subfolders listed before it.
check_table() {
  local i j sub dep ok=0 found
  for i in "${!PLANNING_ORDER[@]}"; do
    sub="${PLANNING_ORDER[$i]}"
    for dep in ${PLANNING_USES[$sub]}; do
      found=0
      for ((j = 0; j < i; ++j)); do [[ "${PLANNING_ORDER[$j]}" == "$dep" ]] && found=1; done
      if ((found == 0)); then
        echo "check-layers.sh: planning/$sub may use planning/$dep, which is not before it in PLANNING_ORDER (a cycle)"
        ok=1
      fi
    done
  done
  return $ok
}

is_dds_place() {
  local file="$1" f
  case "$file" in service/dds/* | service/daemon/*) return 0 ;; esac
  for f in "${DDS_CLI_FILES[@]}"; do [[ "$file" == "$f" ]] && return 0; done
  return 1
}

# Checks the tree at $1; prints one line per violation; returns 1 when there is any.
check_tree() {
  local root="$1" failures=0
  check_table || failures=1
  local -A idl_headers=()
  local idl
  for idl in "$root"/idl/*.idl; do
    [[ -e "$idl" ]] && idl_headers["$(basename "${idl%.idl}").h"]=1
  done
  local file layer allowed line number text target target_layer
  while IFS= read -r file; do
    file="${file#"$root"/}"
    layer="$(layer_of "$file")"
    if [[ "$layer" == "planning" ]]; then
      echo "$file: lies straight in planning/; put it in planning/core or a planning subfolder"
      failures=1
      continue
    fi
    allowed="$(allowed_for "$layer")"
    if [[ "$allowed" == "?" ]]; then
      echo "$file: planning/${layer#planning/} has no rule in .ci/check-layers.sh (add it to PLANNING_ORDER and PLANNING_USES)"
      failures=1
      continue
    fi
    while IFS= read -r line; do
      number="${line%%:*}"
      text="${line#*:}"
      if [[ "$text" =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([^\"]+)\" ]]; then
        target="${BASH_REMATCH[1]}"
        if [[ -n "${idl_headers[$target]:-}" || "$target" == service/dds/* ]]; then
          if ! is_dds_place "$file"; then
            echo "$file:$number: includes \"$target\" (DDS types): only service/dds/, service/daemon/ and the CLI's DDS commands may"
            failures=1
          fi
          continue
        fi
        target_layer="$(layer_of "$target")"
        [[ -z "$target_layer" || "$allowed" == "*" ]] && continue
        if [[ " $allowed " != *" $target_layer "* ]]; then
          echo "$file:$number: includes \"$target\": layer $layer may include only $allowed"
          failures=1
        fi
      elif [[ "$text" =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*\<([^\>]+)\> ]]; then
        target="${BASH_REMATCH[1]}"
        case "$layer" in
          planning/core | trajectory)
            if [[ "$target" =~ $FOREIGN_HEADER_PATTERN || -n "${idl_headers[$target]:-}" ]]; then
              echo "$file:$number: includes <$target>: layer $layer may use only Eigen and the standard library"
              failures=1
            fi ;;
        esac
      fi
    done < <(grep -n -E '^[[:space:]]*#[[:space:]]*include' "$root/$file" || true)
  done < <(find "$root/planning" "$root/terrain" "$root/trajectory" "$root/service" "$root/bench/support" \
             -type f \( -name '*.hpp' -o -name '*.cpp' -o -name '*.h' \) 2>/dev/null | sort)
  return $failures
}

# Builds small trees with one violation each (and one clean tree) and checks the verdicts.
self_test() {
  local tmp status=0
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' RETURN
  make_clean_tree() {
    local t="$1"
    mkdir -p "$t"/{planning/core,planning/grid,planning/fleet,terrain,trajectory,service/dds,service/cli,idl}
    printf '#include <Eigen/Core>\n' >"$t/planning/core/result.hpp"
    printf '#include "planning/core/result.hpp"\n#include <gdal_priv.h>\n' >"$t/terrain/dem.hpp"
    printf '#include "terrain/dem.hpp"\n#include "planning/core/result.hpp"\n' >"$t/planning/grid/search.hpp"
    printf '#include "planning/grid/search.hpp"\n' >"$t/planning/fleet/paths.hpp"
    printf '#include "planning/core/result.hpp"\n' >"$t/trajectory/spline.hpp"
    printf '#include "planning/fleet/paths.hpp"\n#include "trajectory/spline.hpp"\n' >"$t/service/engine.cpp"
    printf '#include "example.h"\n' >"$t/service/dds/conversions.hpp"
    printf '#include "service/dds/conversions.hpp"\n' >"$t/service/cli/gcs_command.cpp"
    printf 'module m {};\n' >"$t/idl/example.idl"
  }
  # name | file to write | its content | what the report must name
  local cases=(
    "clean|||"
    "core includes terrain|planning/core/bad.hpp|#include \"terrain/dem.hpp\"|planning/core/bad.hpp:1: includes \"terrain/dem.hpp\""
    "core includes GDAL|planning/core/bad.hpp|#include <gdal_priv.h>|planning/core/bad.hpp:1: includes <gdal_priv.h>"
    "terrain includes planning|terrain/bad.cpp|#include \"planning/grid/search.hpp\"|terrain/bad.cpp:1: includes \"planning/grid/search.hpp\""
    "grid includes fleet|planning/grid/bad.cpp|#include \"planning/fleet/paths.hpp\"|planning/grid/bad.cpp:1: includes \"planning/fleet/paths.hpp\""
    "trajectory includes terrain|trajectory/bad.cpp|// a comment\n#include \"terrain/dem.hpp\"|trajectory/bad.cpp:2: includes \"terrain/dem.hpp\""
    "trajectory includes service|trajectory/bad.hpp|#include \"service/engine.hpp\"|trajectory/bad.hpp:1: includes \"service/engine.hpp\""
    "engine includes IDL types|service/bad.cpp|#include \"example.h\"|service/bad.cpp:1: includes \"example.h\" (DDS types)"
    "engine includes the DDS edge|service/bad.cpp|#include \"service/dds/conversions.hpp\"|service/bad.cpp:1: includes \"service/dds/conversions.hpp\""
    "file straight in planning|planning/bad.cpp|#include \"planning/core/result.hpp\"|planning/bad.cpp: lies straight in planning/"
    "unknown planning subfolder|planning/extra/bad.cpp|#include \"planning/core/result.hpp\"|planning/extra/bad.cpp: planning/extra has no rule"
  )
  local entry name file content expected tree output verdict
  for entry in "${cases[@]}"; do
    IFS='|' read -r name file content expected <<<"$entry"
    tree="$tmp/${name// /_}"
    make_clean_tree "$tree"
    if [[ -n "$file" ]]; then
      mkdir -p "$(dirname "$tree/$file")"
      printf '%b\n' "$content" >"$tree/$file"
    fi
    verdict=0
    output="$(check_tree "$tree")" || verdict=1
    if [[ -z "$file" ]]; then
      if ((verdict != 0)); then
        echo "self-test FAILED: the clean tree was refused:"
        echo "$output"
        status=1
      else
        echo "self-test ok: the clean tree passes"
      fi
    elif ((verdict == 0)); then
      echo "self-test FAILED: \"$name\" was not caught"
      status=1
    elif [[ "$output" != *"$expected"* ]]; then
      echo "self-test FAILED: \"$name\" was caught, but the report does not say \"$expected\":"
      echo "$output"
      status=1
    else
      echo "self-test ok: $name -> $(head -n 1 <<<"$output")"
    fi
  done
  return $status
}

root="$(cd "$(dirname "$0")/.." && pwd)"
case "${1:-}" in
  --self-test)
    self_test
    exit $? ;;
  --root)
    root="$(cd "$2" && pwd)" ;;
  "") ;;
  *)
    echo "usage: $0 [--root DIR] | --self-test" >&2
    exit 2 ;;
esac
if check_tree "$root"; then
  echo "check-layers: no layer includes a higher one"
else
  echo "check-layers: FAILED (see the lines above)"
  exit 1
fi
