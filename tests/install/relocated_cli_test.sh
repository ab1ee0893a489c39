#!/usr/bin/env bash
# The installed command with the source and build trees out of reach:
#   1. `cmake --install BUILD --prefix W/installed`, then the prefix is renamed
#      (W/moved): the installed paths the binary could have recorded are gone.
#   2. Inside a user and mount namespace (unshare -rm), an empty tmpfs is
#      mounted over the build tree and over the source tree, so the source
#      paths compiled into the binary (its build-tree fallback, see
#      verify/resources.h) do not exist for it, as after moving both trees.
#      W is a temporary directory outside both trees.
#   3. There, W/moved/bin/furnace must run `verify --strategy light_area` on
#      the built-in suite and `report --scene` (HTML: the built-in seed-figure
#      scene and the plotting script) from its own share/furnace.
# Negative controls, same hiding: the same binary copied where no
# share/furnace is beside it must fail with exit 2 naming its scenes (so the
# hiding is real and the lookup is relative to the executable), and the
# moved prefix without its plot_report.py must fail report with exit 2.
# Skipped (exit 77) where unprivileged namespaces are not allowed, or (the
# report part) without a Python 3 that imports matplotlib.
#   relocated_cli_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd -P)"
source="$(cd "$2" && pwd -P)"
work="$(mktemp -d "${TMPDIR:-/tmp}/furnace_install_test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
case "$work/" in "$build/"* | "$source/"*) echo "FAIL: $work is inside the build or source tree" >&2; exit 1 ;; esac
fail() { echo "FAIL: $*" >&2; exit 1; }

if ! unshare --user --map-root-user --mount true 2>/dev/null; then
  echo "skipped: unprivileged user and mount namespaces (unshare -rm) are not allowed here, and they hide the trees"
  exit 77
fi

cmake --install "$build" --prefix "$work/installed" >"$work/install.log"
mv "$work/installed" "$work/moved"
prefix="$work/moved"
[ -x "$prefix/bin/furnace" ] || fail "no bin/furnace in the installed prefix"
[ -f "$prefix/share/furnace/plot_report.py" ] || fail "no share/furnace/plot_report.py in the installed prefix"
[ -f "$prefix/share/furnace/scenes/disk_occluder.json" ] || fail "no share/furnace/scenes in the installed prefix"

# hidden CMD...: runs CMD with an empty tmpfs over the build and source trees
# (the build tree first: it may lie inside the source tree); stdout and
# stderr to $work/out and $work/err, the exit status in $status.
hidden() {
  set +e
  unshare --user --map-root-user --mount sh -c '
    build=$1 source=$2; shift 2
    for dir in "$build" "$source"; do
      if [ -d "$dir" ]; then mount -t tmpfs tmpfs "$dir" || exit 99; fi
    done
    [ -z "$(ls -A "$source")" ] || exit 98
    exec "$@"' sh "$build" "$source" "$@" >"$work/out" 2>"$work/err"
  status=$?
  set -e
  [ "$status" -ne 99 ] || fail "could not mount a tmpfs over the trees: $(cat "$work/err")"
  [ "$status" -ne 98 ] || fail "the source tree is still visible inside the namespace"
}

spp=512  # light_area's calibrated spp (verify::min_calibrated_spp): alpha holds there
hidden "$prefix/bin/furnace" verify --strategy light_area --spp "$spp" --json "$work/verify.json"
[ "$status" -eq 0 ] || fail "installed verify --strategy light_area: exit $status: $(cat "$work/err") $(tail -5 "$work/out")"
grep -q "verdict: PASS" "$work/out" || fail "installed verify printed no PASS verdict"
cases=$(grep -c '^      "scene": ' "$work/verify.json" || true)  # one per case (JSON indented by 2)
[ "$cases" -gt 0 ] || fail "installed verify wrote no case to its JSON"
echo "installed verify --strategy light_area --spp $spp: PASS, $cases cases"

# Negative control: the same binary with no share/furnace beside it.
mkdir -p "$work/bare/bin"
cp "$prefix/bin/furnace" "$work/bare/bin/furnace"
hidden "$work/bare/bin/furnace" verify --strategy light_area --spp "$spp"
[ "$status" -eq 2 ] || fail "a furnace without share/furnace and with the trees hidden: exit $status, expected 2"
grep -q "built-in scenes" "$work/err" || fail "the missing scenes are not named: $(cat "$work/err")"
[ "$(wc -l <"$work/err")" -eq 1 ] || fail "the missing-scenes error is not one line: $(cat "$work/err")"
echo "negative control (no share/furnace beside the binary): exit 2, $(cat "$work/err")"

python_ok=0
for python in python3 /usr/bin/python3; do
  if "$python" -c "import matplotlib, numpy" >/dev/null 2>&1; then python_ok=1; fi
done
if [ "$python_ok" -eq 0 ]; then
  echo "skipped: the report part needs a Python 3 that imports matplotlib (Debian: python3-matplotlib)"
  exit 77
fi

scene="$prefix/share/furnace/scenes/disk_occluder.json"
hidden "$prefix/bin/furnace" report --scene "$scene" --strategy light_area --min-spp 2 --max-spp 8 \
  --output-dir "$work/report"
[ "$status" -eq 0 ] || fail "installed report --scene: exit $status: $(cat "$work/err")"
[ -s "$work/report/index.html" ] || fail "installed report wrote no index.html"
echo "installed report --scene disk_occluder.json: index.html and $(ls "$work/report" | grep -c '\.png$') PNG files"

# Negative control: the moved prefix without its plotting script.
mv "$prefix/share/furnace/plot_report.py" "$work/plot_report.py.away"
hidden "$prefix/bin/furnace" report --scene "$scene" --strategy light_area --min-spp 2 --max-spp 8 \
  --output-dir "$work/report2"
mv "$work/plot_report.py.away" "$prefix/share/furnace/plot_report.py"
[ "$status" -eq 2 ] || fail "report without its plotting script: exit $status, expected 2"
grep -q "plot_report.py" "$work/err" || fail "the missing script is not named: $(cat "$work/err")"
[ ! -e "$work/report2" ] || fail "report without its plotting script created its output directory"
echo "negative control (no plot_report.py): exit 2, $(cat "$work/err")"
echo "PASS"
