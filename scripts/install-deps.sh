#!/usr/bin/env bash
# Installs the Debian packages nmdp needs, only those missing (idempotent; quick when all are there).
#   scripts/install-deps.sh               # everything: nmdp, its Python module and sweeps, the viewer, the
#                                         # tests (chromium for the viewer's), the benchmarks (scripts/test.sh)
#   scripts/install-deps.sh --demo        # what scripts/demo.sh needs: nmdp, the plot and node/npm for the
#                                         # viewer page (no GoogleTest, Google Benchmark, MuJoCo or chromium)
#   scripts/install-deps.sh --sanitizers  # clang 14 with its sanitizer and libFuzzer runtimes and
#                                         # llvm-symbolizer (CI's sanitizer and fuzzing configuration)
set -euo pipefail
nmdp=(
  build-essential cmake pkg-config
  libeigen3-dev liburdfdom-dev libtinyxml-dev libhdf5-dev nlohmann-json3-dev libtorch-dev libopenblas0-pthread
  python3-matplotlib python3-h5py
)
# The Python module (pybind11, for Debian's /usr/bin/python3), Dask for `nmdp sweep`, pytest.
python=(
  python3-dev python3-numpy pybind11-dev python3-pybind11 python3-distributed python3-pytest
)
# Node.js and npm build the viewer bundle (viewer/, esbuild) that `nmdp view` puts in its page.
viewer=(nodejs npm)
tests=(
  googletest libgtest-dev libbenchmark-dev
  libmujoco-dev libqhull-dev libgl-dev
  chromium
)
sanitizers=(clang-14 libclang-rt-14-dev llvm-14)
case "${1:-}" in
  "") packages=("${nmdp[@]}" "${viewer[@]}" "${python[@]}" "${tests[@]}") ;;
  --demo) packages=("${nmdp[@]}" "${viewer[@]}") ;;
  --sanitizers) packages=("${sanitizers[@]}") ;;
  *) echo "usage: $0 [--demo | --sanitizers]" >&2; exit 2 ;;
esac
missing=()
for p in "${packages[@]}"; do
  # A node and npm from elsewhere (NodeSource's nodejs carries its own npm) count as installed: Debian's
  # npm package would pull in Debian's nodejs beside it.
  case "$p" in
    nodejs) command -v node >/dev/null && continue ;;
    npm) command -v npm >/dev/null && continue ;;
  esac
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
