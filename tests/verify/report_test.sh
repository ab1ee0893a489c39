#!/bin/sh
# The HTML report end to end (ctest label `report`): `furnace report` on
# disk_occluder with three strategies up to 64 spp, then report_check.py
# checks the folder. Exit 77 (ctest: skipped) with one line saying so when no
# Python 3 with matplotlib is found, as furnace itself looks for it.
# Usage: report_test.sh FURNACE SCENE_DIR OUTPUT_DIR
set -u
furnace=$1 scene_dir=$2 out=$3
here=$(dirname "$0")
python=""
for candidate in ${FURNACE_PYTHON:-python3 /usr/bin/python3}; do
  if "$candidate" -c "import matplotlib, numpy" >/dev/null 2>&1; then python=$candidate; break; fi
done
if [ -z "$python" ]; then
  echo "skipped: no Python 3 with matplotlib (apt-get install python3-matplotlib, or set FURNACE_PYTHON)"
  exit 77
fi
rm -rf "$out"
"$furnace" report --scene "$scene_dir/disk_occluder.json" --strategy uniform_hemisphere --strategy light_area \
  --strategy mis_power --max-spp 64 --threads 2 --output-dir "$out" || { echo "furnace report failed"; exit 1; }
exec "$python" "$here/report_check.py" "$out"
