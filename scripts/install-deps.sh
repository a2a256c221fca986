#!/usr/bin/env bash
# Installs the Debian packages nmdp needs, only those missing (idempotent; quick when all are there).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev liburdfdom-dev libtinyxml-dev libhdf5-dev nlohmann-json3-dev libtorch-dev libopenblas0-pthread
  googletest libgtest-dev libbenchmark-dev
  libmujoco-dev libqhull-dev libgl-dev
  python3-matplotlib python3-h5py
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "installing: ${missing[*]}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
