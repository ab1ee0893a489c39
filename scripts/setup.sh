#!/usr/bin/env bash
# Installs furnace's build dependencies from Debian 12's archive (idempotent,
# non-interactive). Run as root or with sudo available.
#   --peers  also installs the peer renderers Debian ships, for the peer tests
#            (ctest -L peer): Blender, whose Cycles they render with (about
#            160 packages, 580 MB, under 2 minutes).
set -euo pipefail

peers=0
for arg in "$@"; do
  case "$arg" in
    --peers) peers=1 ;;
    *) echo "setup: unknown option '$arg' (accepted: --peers)" >&2; exit 2 ;;
  esac
done

packages=(
  cmake g++ ninja-build
  libembree-dev libtbb-dev
  libcgal-dev libgmp-dev libmpfr-dev
  libboost-dev libboost-math-dev
  libopenexr-dev libimath-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libbenchmark-dev
  python3-matplotlib
)
if [ "$peers" -eq 1 ]; then packages+=(blender); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
