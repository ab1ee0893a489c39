#!/bin/sh
# `furnace report` without a Python that imports matplotlib, or with a bad
# scene, is bad input: exit 2, one line on stderr naming what is missing,
# before any rendering and with nothing written (the output directory is not
# even created). Needs no Python itself.
# Usage: report_missing_tools_test.sh FURNACE SCENE_DIR WORK_DIR
set -u
furnace=$1 scene_dir=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $1"; exit 1; }

expect_bad_input() {  # name, then the command's arguments after FURNACE_PYTHON
  name=$1; shift
  FURNACE_PYTHON=$1 "$furnace" report --scene "$2" --max-spp 8 --output-dir "$work/out" >"$work/stdout" 2>"$work/stderr"
  status=$?
  [ "$status" -eq 2 ] || fail "$name: exit $status, expected 2"
  [ "$(wc -l <"$work/stderr")" -eq 1 ] || fail "$name: stderr is not one line: $(cat "$work/stderr")"
  [ ! -e "$work/out" ] || fail "$name: $work/out was created"
  echo "$name: $(cat "$work/stderr")"
}

expect_bad_input "no such python" "$work/no-python-here" "$scene_dir/disk_occluder.json"
grep -q "matplotlib" "$work/stderr" || fail "the message does not name matplotlib"
grep -q "no-python-here" "$work/stderr" || fail "the message does not name the interpreter tried"
expect_bad_input "python without matplotlib" "/bin/false" "$scene_dir/disk_occluder.json"
grep -q "cannot import matplotlib" "$work/stderr" || fail "the message does not say matplotlib is missing"
# A bad scene is refused before rendering too (when the plotting tools exist).
if python3 -c "import matplotlib" >/dev/null 2>&1 || /usr/bin/python3 -c "import matplotlib" >/dev/null 2>&1; then
  unset FURNACE_PYTHON
  "$furnace" report --scene "$work/missing.json" --max-spp 8 --output-dir "$work/out" >/dev/null 2>"$work/stderr"
  status=$?
  [ "$status" -eq 2 ] || fail "missing scene: exit $status, expected 2"
  grep -q "missing.json" "$work/stderr" || fail "missing scene: the message does not name the file"
  [ ! -e "$work/out" ] || fail "missing scene: $work/out was created"
  echo "missing scene: $(cat "$work/stderr")"
fi
echo "PASS"
