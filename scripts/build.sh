#!/usr/bin/env bash
# Configures and builds nmdp (Release) into build/, and the viewer bundle viewer/dist/nmdp-view.js
# that `nmdp view` puts in its pages (npm ci when viewer/node_modules is missing or older than
# viewer/package-lock.json, then esbuild).
#   scripts/build.sh          # everything: build/nmdp, the Python module (build/python), the tests,
#                             # the benchmarks and the viewer
#   scripts/build.sh --nmdp   # build/nmdp and the viewer only (the demo: needs no pybind11,
#                             # GoogleTest, Google Benchmark or MuJoCo)
set -euo pipefail
cd "$(dirname "$0")/.."
build_viewer() {
  # npm writes node_modules/.package-lock.json at each install: older than the lock file means the
  # lock changed since.
  if [ ! -f viewer/node_modules/.package-lock.json ] || [ viewer/package-lock.json -nt viewer/node_modules/.package-lock.json ]; then
    (cd viewer && npm ci --no-audit --no-fund --loglevel=error)
  fi
  (cd viewer && npm run --silent build)
}
case "${1:-}" in
  "") cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DNMDP_BUILD_TESTS=ON -DNMDP_BUILD_BENCH=ON -DNMDP_BUILD_PYTHON=ON >/dev/null
      cmake --build build -j"$(nproc)"
      build_viewer ;;
  --nmdp) cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DNMDP_BUILD_TESTS=OFF -DNMDP_BUILD_BENCH=OFF -DNMDP_BUILD_PYTHON=OFF >/dev/null
          cmake --build build -j"$(nproc)" --target nmdp
          build_viewer ;;
  *) echo "usage: $0 [--nmdp]" >&2; exit 2 ;;
esac
