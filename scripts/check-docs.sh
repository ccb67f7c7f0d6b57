#!/usr/bin/env bash
# Runs every command the docs mark runnable, as a user would type it from the checkout's root, so
# README.md and docs/ cannot drift from the tools. A runnable block is a ```sh fence right after
# the line `<!-- runnable -->`; each block runs in its own bash (set -euo pipefail) with the
# loopback DDS configuration, and must exit 0. A block that reads ../shared/data is skipped, with a
# message, when that folder is absent (it fails instead with SKYROUTE_REQUIRE_DATA=1, as in CI).
# Needs a build in ./build (scripts/setup.sh).
# Usage: scripts/check-docs.sh [--list] [FILE.md ...] | --self-test
set -euo pipefail
cd "$(dirname "$0")/.."

# The check's own test: a failing marked block fails it, an unmarked one is not run, a file
# without marked blocks is an error (a marker lost in an edit must not pass silently).
if [ "${1:-}" = "--self-test" ]; then
  dir=$(mktemp -d)
  trap 'rm -rf "$dir"' EXIT
  fence='```'
  printf '# ok\n<!-- runnable -->\n%ssh\ntest -f README.md\n%s\n%ssh\nfalse\n%s\n' "$fence" "$fence" "$fence" "$fence" > "$dir/ok.md"
  printf '# bad\n<!-- runnable -->\n%ssh\ntrue\n%s\n<!-- runnable -->\n%ssh\nfalse\n%s\n' "$fence" "$fence" "$fence" "$fence" > "$dir/bad.md"
  printf '# none\n%ssh\ntrue\n%s\n' "$fence" "$fence" > "$dir/none.md"
  "$0" "$dir/ok.md" > /dev/null || { echo "self-test: a passing block failed" >&2; exit 1; }
  if "$0" "$dir/bad.md" > /dev/null 2>&1; then echo "self-test: a failing block passed" >&2; exit 1; fi
  if "$0" "$dir/none.md" > /dev/null 2>&1; then echo "self-test: a file without runnable blocks passed" >&2; exit 1; fi
  echo "check-docs self-test: ok"
  exit 0
fi

list_only=0
if [ "${1:-}" = "--list" ]; then list_only=1; shift; fi
files=("$@")
if [ ${#files[@]} -eq 0 ]; then files=(README.md docs/*.md); fi

if [[ -z "${CYCLONEDDS_URI:-}" ]]; then
  export CYCLONEDDS_URI='<CycloneDDS><Domain id="any"><General><Interfaces><NetworkInterface name="lo"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers><MaxAutoParticipantIndex>120</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>'
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Splits the marked blocks of each file into $work/<n>.sh, with a header naming file and line.
count=0
for file in "${files[@]}"; do
  awk -v file="$file" -v dir="$work" -v start="$count" '
    BEGIN { n = start; marked = 0; inside = 0 }
    inside && /^```/ { inside = 0; close(out); next }
    inside { print > out; next }
    /^<!-- runnable -->[[:space:]]*$/ { marked = 1; next }
    marked && /^```sh[[:space:]]*$/ { n++; out = dir "/" n ".sh"; print "# " file ":" NR > out; inside = 1; marked = 0; next }
    { marked = 0 }
    END { print n > (dir "/count") }
  ' "$file"
  count=$(cat "$work/count")
done

if [ "$count" -eq 0 ]; then
  echo "check-docs: no runnable blocks found in ${files[*]}" >&2
  exit 1
fi

failed=0
skipped=0
for ((i = 1; i <= count; i++)); do
  block="$work/$i.sh"
  where=$(head -1 "$block" | cut -c3-)
  if [ "$list_only" -eq 1 ]; then
    echo "== $where"
    tail -n +2 "$block"
    continue
  fi
  if grep -q '\.\./shared/data' "$block" && [ ! -d ../shared/data ]; then
    if [ "${SKYROUTE_REQUIRE_DATA:-0}" = "1" ]; then
      echo "check-docs: $where needs ../shared/data, which is missing" >&2
      failed=$((failed + 1))
    else
      echo "check-docs: skipped $where (../shared/data not found)"
      skipped=$((skipped + 1))
    fi
    continue
  fi
  started=$(date +%s.%N)
  if bash -euo pipefail "$block" > "$work/$i.out" 2>&1; then
    printf 'check-docs: ok      %s (%.1f s)\n' "$where" "$(echo "$(date +%s.%N) - $started" | bc)"
  else
    echo "check-docs: FAILED  $where; its output:" >&2
    sed 's/^/    /' "$work/$i.out" >&2
    failed=$((failed + 1))
  fi
done
[ "$list_only" -eq 1 ] && exit 0
echo "check-docs: $count runnable blocks, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]
