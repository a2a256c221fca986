#!/usr/bin/env bash
# Installs the Debian packages nmdp needs, only those missing (idempotent; quick when all are there).
#   scripts/install-deps.sh               # everything: nmdp, its Python module and sweeps, the tests, the
#                                         # benchmarks (scripts/test.sh)
#   scripts/install-deps.sh --demo        # what scripts/demo.sh needs: nmdp and the plot (no GoogleTest,
#                                         # Google Benchmark or MuJoCo)
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
tests=(
  googletest libgtest-dev libbenchmark-dev
  libmujoco-dev libqhull-dev libgl-dev
)
sanitizers=(clang-14 libclang-rt-14-dev llvm-14)
case "${1:-}" in
  "") packages=("${nmdp[@]}" "${python[@]}" "${tests[@]}") ;;
  --demo) packages=("${nmdp[@]}") ;;
  --sanitizers) packages=("${sanitizers[@]}") ;;
  *) echo "usage: $0 [--demo | --sanitizers]" >&2; exit 2 ;;
esac
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
