#!/usr/bin/env bash
# Installs the Debian packages tissuebench needs - only those missing, so a second
# run installs nothing - then configures and builds everything (Release) in build/.
# Sourced by scripts/main.sh and scripts/test.sh.
set -euo pipefail
TB_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

TB_PACKAGES=(
  build-essential cmake pkg-config ccache git
  libeigen3-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libhdf5-openmpi-dev
  libdeal.ii-dev libsundials-dev openmpi-bin libopenblas0-serial
  libgtest-dev libbenchmark-dev libboost-dev libcgal-dev
  python3 python3-numpy python3-h5py python3-matplotlib python3-jinja2 python3-yaml
  chromium
)

tb_install_missing() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "tissuebench: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# The viewer's npm packages (viewer/package-lock.json: three.js, uPlot, esbuild,
# playwright-core for the browser tests): Debian's npm when no npm is on PATH,
# then `npm ci` whenever the lock file is newer than the installed tree.
tb_viewer_packages() {
  command -v npm >/dev/null 2>&1 || tb_install_missing nodejs npm
  local v="$TB_ROOT/viewer"
  if [ ! -f "$v/node_modules/.package-lock.json" ] || [ "$v/package-lock.json" -nt "$v/node_modules/.package-lock.json" ]; then
    echo "tissuebench: installing the viewer's npm packages (viewer/package-lock.json)"
    npm ci --prefix "$v" --no-audit --no-fund --loglevel=error
  fi
}

tb_build() {
  cmake -S "$TB_ROOT" -B "$TB_ROOT/build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$TB_ROOT/build" -j"$(nproc)"
}

tb_install_missing "${TB_PACKAGES[@]}"
tb_viewer_packages
tb_build
