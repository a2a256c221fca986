#!/usr/bin/env bash
# The step-size evaluation with the scene defaults; regenerates docs/RESULTS.md and
# docs/figures/steps_*.png: a thin wrapper around scripts/evaluate.py (see its --help), with Debian's
# python3 (h5py, numpy, matplotlib; a pyenv or conda python3 first on PATH may lack them). Builds
# build/nmdp first if absent.
#   scripts/evaluate.sh                   # the evaluation (10 s runs)
#   scripts/evaluate.sh --duration 0.2    # a smoke run, written to build/evaluation-short/
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ ! -x build/nmdp && " $* " != *" --nmdp "* ]]; then
  scripts/build.sh
fi
exec /usr/bin/python3 scripts/evaluate.py "$@"
