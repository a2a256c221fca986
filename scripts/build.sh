#!/usr/bin/env bash
# Configures and builds nmdp (Release) into build/.
#   scripts/build.sh          # everything: build/nmdp, the Python module (build/python), the tests
#                             # and the benchmarks
#   scripts/build.sh --nmdp   # build/nmdp only (the demo: needs no pybind11, GoogleTest, Google
#                             # Benchmark or MuJoCo)
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  "") cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DNMDP_BUILD_TESTS=ON -DNMDP_BUILD_BENCH=ON -DNMDP_BUILD_PYTHON=ON >/dev/null
      cmake --build build -j"$(nproc)" ;;
  --nmdp) cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DNMDP_BUILD_TESTS=OFF -DNMDP_BUILD_BENCH=OFF -DNMDP_BUILD_PYTHON=OFF >/dev/null
          cmake --build build -j"$(nproc)" --target nmdp ;;
  *) echo "usage: $0 [--nmdp]" >&2; exit 2 ;;
esac
