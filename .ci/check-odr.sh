#!/usr/bin/env bash
# Fails when two product files define a class or struct of the same name at namespace scope
# (outside an anonymous namespace), naming both files and lines. Two such definitions in one
# namespace break the one-definition rule without a compiler error when no file includes both:
# each library emits its inline member functions (an implicit destructor, say) under one symbol,
# the linker keeps one, and the other side runs it on a different layout. Product code only
# (terrain/, planning/, trajectory/, service/, bench/support/); tests and benchmarks may repeat
# helper names in their own files.
#
# It reads our layout: namespace-scope definitions start in column 0 (namespaces are not
# indented; clang-format keeps it so), nested ones are indented, and an anonymous namespace opens
# with "namespace {" in column 0 and closes with "}  // namespace" in column 0.
#
# Usage: .ci/check-odr.sh [--root DIR]   check the tree at DIR (default: this repository)
#        .ci/check-odr.sh --self-test    check that a tree with a repeated name fails
set -euo pipefail

# Prints "name<TAB>file:line" for each namespace-scope definition of one file.
definitions_of() {
  local file="$1"
  awk -v file="$file" '
    /^namespace[[:space:]]*\{/ { anonymous++; next }
    /^}[[:space:]]*\/\/[[:space:]]*namespace[[:space:]]*$/ { if (anonymous > 0) anonymous--; next }
    anonymous > 0 { next }
    /^(struct|class)[[:space:]]+[A-Za-z_][A-Za-z0-9_]*([[:space:]]+final)?[[:space:]]*(\{|:[^:])/ {
      name = $2
      sub(/[^A-Za-z0-9_].*$/, "", name)
      printf "%s\t%s:%d\n", name, file, NR
    }
  ' "$file"
}

check_tree() {
  local root="$1"
  local listing
  listing="$(cd "$root" && find terrain planning trajectory service bench/support \
    \( -name '*.hpp' -o -name '*.cpp' -o -name '*.h' \) -type f 2>/dev/null | LC_ALL=C sort |
    while read -r f; do definitions_of "$f"; done)"
  local repeated
  repeated="$(cut -f1 <<<"$listing" | LC_ALL=C sort | uniq -d)"
  if [ -z "$repeated" ]; then
    echo "odr check: $(grep -c . <<<"$listing") class and struct definitions, each name once"
    return 0
  fi
  echo "odr check: a class or struct name is defined in more than one product file:" >&2
  local name
  while read -r name; do
    echo "  $name:" >&2
    awk -F'\t' -v n="$name" '$1 == n { print "    " $2 }' <<<"$listing" >&2
  done <<<"$repeated"
  return 1
}

self_test() {
  local tree
  tree="$(mktemp -d)"
  trap 'rm -rf "$tree"' RETURN
  mkdir -p "$tree/planning/mission" "$tree/service"
  printf 'namespace skyroute {\nstruct Plan {\n  int a;\n};\n}  // namespace skyroute\n' >"$tree/planning/mission/a.hpp"
  printf 'namespace skyroute {\nnamespace {\nstruct Local {};\n}  // namespace\nstruct Other {\n  struct Plan {};\n};\n}  // namespace skyroute\n' \
    >"$tree/service/b.cpp"
  if ! check_tree "$tree" >/dev/null 2>&1; then
    echo "odr self-test: a clean tree (nested and anonymous-namespace names) was refused" >&2
    return 1
  fi
  printf 'namespace skyroute {\nstruct Plan final : Base {\n  double b;\n};\n}  // namespace skyroute\n' \
    >"$tree/service/c.hpp"
  local out
  if out="$(check_tree "$tree" 2>&1)"; then
    echo "odr self-test: a repeated struct name was not refused" >&2
    return 1
  fi
  if ! grep -q "planning/mission/a.hpp:2" <<<"$out" || ! grep -q "service/c.hpp:2" <<<"$out"; then
    echo "odr self-test: the refusal does not name both files: $out" >&2
    return 1
  fi
  echo "odr self-test: passed"
}

root="$(cd "$(dirname "$0")/.." && pwd)"
case "${1:-}" in
  --self-test) self_test ;;
  --root) check_tree "$2" ;;
  "") check_tree "$root" ;;
  *) echo "usage: $0 [--root DIR | --self-test]" >&2; exit 2 ;;
esac
