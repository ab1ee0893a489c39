#!/bin/sh
# examples/compare/render_and_compare.sh end to end, with `furnace render` as
# the renderer under test: store a reference set (8 renders of disk_occluder
# at 256 spp), then the same renderer → exit 0 (SAME), the renderer with the
# drop_light_cosine defect → exit 1 (DIFFERENT), a demand for a 0.01 %
# detectable difference → exit 3 (INCONCLUSIVE), and a missing argument → 2.
#   compare_example_test.sh FURNACE SCENE_DIR WORK_DIR
set -u
furnace=$1
scene=$2/disk_occluder.json
work=$3
example=$(dirname "$0")/../../examples/compare/render_and_compare.sh
rm -rf "$work"
mkdir -p "$work"
failures=0

expect() {
  want=$1
  shift
  "$@" > "$work/out.txt" 2>&1
  got=$?
  if [ "$got" != "$want" ]; then
    echo "FAILED: expected exit $want, got $got: $*"
    cat "$work/out.txt"
    failures=$((failures + 1))
  else
    echo "ok: exit $got: $(grep -E '^(verdict|stored|different in)' "$work/out.txt" | tr '\n' ' ')"
  fi
}

render="$furnace render --scene $scene --strategy light_area --spp 256 --threads 2 --seed @SEED@ --output @OUTPUT@"
# shellcheck disable=SC2086
expect 0 sh "$example" "$furnace" "$work/refs" 8 $render
# shellcheck disable=SC2086
expect 0 sh "$example" "$furnace" "$work/refs" 8 $render
# shellcheck disable=SC2086
expect 1 sh "$example" "$furnace" "$work/refs" 8 $render --defect drop_light_cosine
# shellcheck disable=SC2086
FURNACE_COMPARE_OPTIONS="--max-detectable-difference 0.0001" expect 3 sh "$example" "$furnace" "$work/refs" 8 $render
expect 2 sh "$example" "$furnace" "$work/refs"
[ "$failures" = 0 ]
