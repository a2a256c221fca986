#!/usr/bin/env bash
# Runs every libFuzzer target (fuzz/) for SECONDS each, from the seed corpora made from models/,
# data/ and ../shared plus the inputs kept in fuzz/regressions/, in a clang build with
# AddressSanitizer and UndefinedBehaviorSanitizer: $NMDP_BUILD_DIR (CI: build-sanitize), by default
# build-fuzz/, configured here if it is not yet.
#   scripts/fuzz.sh SECONDS [TARGET ...]     e.g. scripts/fuzz.sh 30, scripts/fuzz.sh 1800 scene urdf
# A finding (crash, timeout, leak, out-of-memory, sanitizer report) stops that target with its
# reproducer in BUILD/fuzz/findings/<target>/ and makes the script exit non-zero after the rest
# have run. Each target's corpus grows in BUILD/fuzz/corpus/<target>/; libFuzzer's final
# statistics (executions, coverage) are in BUILD/fuzz/logs/<target>.log.
set -uo pipefail
cd "$(dirname "$0")/.."
seconds=${1:?usage: scripts/fuzz.sh SECONDS [TARGET ...]}
shift
build=${NMDP_BUILD_DIR:-build-fuzz}
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_FLAGS=-g1 -DCMAKE_CXX_FLAGS=-g1 -DNMDP_SANITIZE=address,undefined -DNMDP_BUILD_FUZZERS=ON \
    -DNMDP_BUILD_BENCH=OFF -DNMDP_BUILD_PYTHON=OFF >/dev/null
fi
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene urdf stl rbf_text model_h5 dataset_h5 force_csv heightfield_csv keyframes fit_config rft_config)
fi
cmake --build "$build" -j"$(nproc)" --target fuzz_make_seeds $(printf 'fuzz_%s ' "${targets[@]}")
out="$build/fuzz"
"$out/fuzz_make_seeds" "$out/seeds" >/dev/null
mkdir -p "$out/logs"
status=0
for t in "${targets[@]}"; do
  corpus="$out/corpus/$t" findings="$out/findings/$t"
  mkdir -p "$corpus" "$findings"
  regressions=()
  [ -d "fuzz/regressions/$t" ] && regressions=("fuzz/regressions/$t")
  # Inputs up to 1 MiB (the published RBF weights are 100 kB of text); 10 s or 2 GiB for one input
  # is a hang or an exhaustion; leaks are reported by LeakSanitizer.
  dict=()
  [ -s "$out/seeds/$t.dict" ] && dict=(-dict="$out/seeds/$t.dict")
  "$out/fuzz_$t" "$corpus" "$out/seeds/$t" "${regressions[@]}" "${dict[@]}" \
    -max_total_time="$seconds" -max_len=1048576 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" >"$out/logs/$t.log" 2>&1
  code=$?
  summary=$(grep -E "stat::number_of_executed_units|cov:" "$out/logs/$t.log" | tail -2 | tr '\n' ' ')
  if [ $code -ne 0 ]; then
    echo "fuzz_$t: FINDING (exit $code), see $out/logs/$t.log and $findings/"
    status=1
  else
    echo "fuzz_$t: ${seconds} s, no finding. $summary"
  fi
done
exit $status
