#!/usr/bin/env bash
# Checks the installed package the way a user meets it: installs a built
# tree into a fresh prefix, compiles every installed header on its own (so no
# public header needs an internal one), then configures and builds the
# stand-alone examples/sampler_test against the prefix and runs its tests,
# printing their numbers.
#   scripts/example.sh [BUILD_DIR (default build)] [WORK_DIR (default: a temporary directory, removed after)]
# The example build honours CMAKE_CXX_COMPILER_LAUNCHER (e.g. ccache) from the environment.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$repo/build}" && pwd)"
if [[ $# -ge 2 ]]; then
  work="$2"
  mkdir -p "$work"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
prefix="$work/prefix"
rm -rf "$prefix"

cmake --install "$build" --prefix "$prefix" >"$work/install.log"
echo "example: installed $(find "$prefix" -type f | wc -l) files into $prefix"

include="$prefix/include/furnace"
cxx="${CXX:-c++}"
for h in $(cd "$include" && find . -name '*.h' | sort); do
  echo "#include \"${h#./}\"" | "$cxx" -std=c++17 -fsyntax-only -I "$include" -x c++ - ||
    { echo "example: the installed header ${h#./} does not compile on its own" >&2; exit 1; }
done
echo "example: every installed header compiles on its own"

generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
cmake -S "$repo/examples/sampler_test" -B "$work/example-build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log"
cmake --build "$work/example-build" -j "${FURNACE_JOBS:-2}" >"$work/build.log" ||
  { cat "$work/build.log"; exit 1; }
"$work/example-build/sampler_test"
