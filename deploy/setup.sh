#!/usr/bin/env bash
# Installs hcosim's Debian build and runtime dependencies, only what is missing.
# Idempotent: a second run with everything present only queries dpkg (well under a second).
set -euo pipefail

# libqhull-dev: the mujoco CMake package names its include directory.
# libbullet-dev: Bullet's soft body, a peer in hcosim bench massspring.
# jq: the tests read bench reports with it.
# clang, libclang-rt-14-dev: the sanitizer build and libFuzzer (deploy/fuzz.sh).
# openssl: hcosim security init; tshark: the wire test of DDS Security.
# clang-format-14: deploy/format.sh (.ci/run checks the formatting).
# libzstd-dev, liblz4-dev, zlib1g-dev: MCAP recordings' chunks and CRCs.
# libwebsocketpp-dev, libasio-dev: the live Foxglove bridge's WebSocket server.
# nodejs, npm (only where no node is installed): the MCAP test clients.
# calculix-ccx: CalculiX, the independent FEM reference (adapters/reference).
packages=(
  build-essential cmake ninja-build ccache pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libeigen3-dev libopencv-dev libopencv-contrib-dev libapriltag-dev
  libmujoco-dev libbullet-dev libqhull-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev googletest libgtest-dev
  libbenchmark-dev
  cyclonedds-dev cyclonedds-tools jq clang libclang-rt-14-dev
  openssl tshark clang-format-14 libzstd-dev liblz4-dev zlib1g-dev libwebsocketpp-dev libasio-dev
  calculix-ccx
)
command -v npm >/dev/null || packages+=(nodejs npm)

# MCAP's and Foxglove's npm libraries for integration.mcap and
# integration.foxglove, as each folder's lockfile pins them; a machine
# without the npm registry skips those tests.
npm_clients() {
  local root dir
  root="$(cd "$(dirname "$0")/.." && pwd)"
  for dir in "$root/tests/interop/mcap" "$root/tests/interop/foxglove"; do
    [ "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ] && continue
    echo "hcosim setup: npm ci in ${dir#"$root"/} (test clients)"
    (cd "$dir" && npm ci --no-audit --no-fund --ignore-scripts --loglevel=error >/dev/null) ||
      echo "hcosim setup: npm ci failed in ${dir#"$root"/}: its tests will be skipped" >&2
  done
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  npm_clients
  exit 0
fi

echo "hcosim setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
sudo=()
[ "$(id -u)" -ne 0 ] && sudo=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
npm_clients
echo "hcosim setup: done"
