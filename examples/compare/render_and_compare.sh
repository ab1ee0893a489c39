#!/bin/sh
# A renderer's regression test with `furnace compare` instead of a golden
# image and a hand-set threshold (docs/comparing.md).
#
#   render_and_compare.sh FURNACE REFERENCE_DIR K RENDER_COMMAND...
#
# RENDER_COMMAND is the renderer's command line for one render, with @SEED@
# where the random seed goes and @OUTPUT@ where the OpenEXR file goes, e.g.
#   myrenderer --scene cornell.xml --spp 256 --seed @SEED@ -o @OUTPUT@
#
# - REFERENCE_DIR holds the stored reference set, ref_1.exr ... ref_K.exr.
#   When it has none, or FURNACE_COMPARE_UPDATE=1, the script renders it
#   (seeds 1000001 ... 1000000 + K, never the test's seeds: the two sets must
#   be independent), stores it and exits 0. Commit that directory.
# - Otherwise it renders K new images (seeds 1 ... K) into a temporary
#   directory and runs `furnace compare --a new --b reference`; its exit code
#   is the script's: 0 SAME, 1 DIFFERENT, 2 bad input, 3 INCONCLUSIVE (the
#   test lacks power: add renders or spp, as the report says). The report
#   and REFERENCE_DIR/last_compare.json say which test rejected.
# Extra `furnace compare` options go in $FURNACE_COMPARE_OPTIONS
# (e.g. "--channels rgb --alpha 0.001").
#
# In CTest:
#   add_test(NAME cornell.compare
#            COMMAND sh render_and_compare.sh ${FURNACE} ${CMAKE_SOURCE_DIR}/test_refs/cornell 8
#                    $<TARGET_FILE:myrenderer> --scene cornell.xml --spp 256 --seed @SEED@ -o @OUTPUT@)
# Exit 1 and 3 fail the test; leave INCONCLUSIVE a failure, never a skip:
# a test without power passes every regression.
set -eu

if [ $# -lt 4 ]; then
  echo "usage: $0 FURNACE REFERENCE_DIR K RENDER_COMMAND... (with @SEED@ and @OUTPUT@)" >&2
  exit 2
fi
furnace=$1
reference_dir=$2
k=$3
shift 3

# Runs the render command with @SEED@ and @OUTPUT@ replaced.
render() {
  seed=$1
  output=$2
  shift 2
  first=1
  for arg in "$@"; do
    if [ $first = 1 ]; then
      set --
      first=0
    fi
    case $arg in
      *@SEED@*) arg=$(printf '%s' "$arg" | sed "s|@SEED@|$seed|g") ;;
    esac
    case $arg in
      *@OUTPUT@*) arg=$(printf '%s' "$arg" | sed "s|@OUTPUT@|$output|g") ;;
    esac
    set -- "$@" "$arg"
  done
  "$@" > /dev/null
}

reference_seed_offset=1000000
mkdir -p "$reference_dir"
if [ "${FURNACE_COMPARE_UPDATE:-0}" = 1 ] || [ ! -f "$reference_dir/ref_1.exr" ]; then
  i=1
  while [ "$i" -le "$k" ]; do
    render $((reference_seed_offset + i)) "$reference_dir/ref_$i.exr" "$@"
    i=$((i + 1))
  done
  echo "stored $k reference renders in $reference_dir"
  exit 0
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
args=""
i=1
while [ "$i" -le "$k" ]; do
  render "$i" "$work/new_$i.exr" "$@"
  args="$args --a $work/new_$i.exr --b $reference_dir/ref_$i.exr"
  i=$((i + 1))
done
status=0
# shellcheck disable=SC2086  # the file lists and options split on spaces
"$furnace" compare $args ${FURNACE_COMPARE_OPTIONS:-} --json "$reference_dir/last_compare.json" || status=$?
exit $status
