#!/bin/sh
# `furnace compare --html DIR`: index.html names the verdict and shows
# compare_gray.png (a PNG file); with the drop_light_cosine defect on one side
# the page says DIFFERENT. Skipped (exit 77) without a Python 3 that imports
# matplotlib (compare then exits 2 naming it).
#   compare_html_test.sh FURNACE SCENE_DIR WORK_DIR
set -u
furnace=$1
scene=$2/disk_occluder.json
work=$3
rm -rf "$work"
mkdir -p "$work"
for s in 1 2 3 4; do
  "$furnace" render --scene "$scene" --strategy light_area --spp 64 --threads 2 --seed $s --output "$work/a$s.exr" > /dev/null || exit 1
  "$furnace" render --scene "$scene" --strategy light_area --spp 64 --threads 2 --seed $((s + 100)) --output "$work/b$s.exr" > /dev/null || exit 1
  "$furnace" render --scene "$scene" --strategy light_area --spp 64 --threads 2 --seed $((s + 200)) --defect drop_light_cosine --output "$work/d$s.exr" > /dev/null || exit 1
done
sides() { for s in 1 2 3 4; do printf ' --a %s/%s%s.exr --b %s/b%s.exr' "$work" "$1" $s "$work" $s; done; }
# shellcheck disable=SC2046
"$furnace" compare $(sides a) --html "$work/same" > "$work/same.txt" 2> "$work/same.err"
status=$?
if [ $status = 2 ] && grep -q matplotlib "$work/same.err"; then
  echo "skipped: $(cat "$work/same.err")"
  exit 77
fi
failures=0
check_page() {  # DIR VERDICT
  if ! grep -q "furnace compare: $2" "$1/index.html"; then echo "FAILED: $1/index.html does not say $2"; failures=$((failures + 1)); fi
  if ! grep -q 'src="compare_gray.png"' "$1/index.html"; then echo "FAILED: $1/index.html has no compare_gray.png"; failures=$((failures + 1)); fi
  if [ "$(head -c 4 "$1/compare_gray.png" | tail -c 3)" != "PNG" ]; then echo "FAILED: $1/compare_gray.png is not a PNG"; failures=$((failures + 1)); fi
}
[ $status = 0 ] || [ $status = 3 ] || { echo "FAILED: same renders: exit $status"; cat "$work/same.err"; failures=$((failures + 1)); }
verdict=$(sed -n 's/^verdict: //p' "$work/same.txt")
check_page "$work/same" "$verdict"
# shellcheck disable=SC2046
"$furnace" compare $(sides d) --html "$work/defect" > /dev/null 2>&1
[ $? = 1 ] || { echo "FAILED: defect renders: not exit 1"; failures=$((failures + 1)); }
check_page "$work/defect" DIFFERENT
echo "same: $verdict; defect: DIFFERENT; failures: $failures"
[ $failures = 0 ]
