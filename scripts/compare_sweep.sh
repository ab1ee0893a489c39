#!/bin/sh
# The false-alarm sweep of `furnace compare` on real renders quoted in
# docs/comparing.md: TRIALS same-distribution pairs of K furnace renders per
# side (seeds 1000t + j and 1000t + 500 + j), compared at alpha 0.05; one line
# per pair: trial, exit code, the families that rejected (- for none), the
# detectable relative difference of the image mean, the families the
# rare-event guard held (- for none).
#   scripts/compare_sweep.sh FURNACE SCENE_FILE STRATEGY SPP K TRIALS WORK_DIR > sweep.txt
set -eu
furnace=$1 scene=$2 strategy=$3 spp=$4 k=$5 trials=$6 work=$7
mkdir -p "$work"
t=1
while [ $t -le "$trials" ]; do
  args=""
  j=1
  while [ $j -le "$k" ]; do
    "$furnace" render --scene "$scene" --strategy "$strategy" --spp "$spp" --seed $((t * 1000 + j)) --threads 1 --output "$work/a$j.exr" > /dev/null
    "$furnace" render --scene "$scene" --strategy "$strategy" --spp "$spp" --seed $((t * 1000 + 500 + j)) --threads 1 --output "$work/b$j.exr" > /dev/null
    args="$args --a $work/a$j.exr --b $work/b$j.exr"
    j=$((j + 1))
  done
  status=0
  # shellcheck disable=SC2086
  "$furnace" compare $args --alpha 0.05 --max-detectable-difference 1 --json "$work/r.json" > /dev/null || status=$?
  echo "$t $status $(python3 -c "import json; j=json.load(open('$work/r.json')); print(','.join(j['rejected']) or '-', j['detectable_relative_difference'], ','.join(j['held']) or '-')")"
  t=$((t + 1))
done
