#!/usr/bin/env bash
# Reproduces the paper's evaluation and regenerates docs/RESULTS.md and docs/figures/*.png:
# a thin wrapper around scripts/evaluate.py (see its --help), with Debian's python3 (h5py, numpy,
# matplotlib; a pyenv or conda python3 first on PATH may lack them). Builds build/nmdp first if absent.
#   scripts/evaluate.sh            # full sweep
#   scripts/evaluate.sh --quick    # a couple of minutes
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ ! -x build/nmdp && " $* " != *" --nmdp "* ]]; then
  scripts/build.sh
fi
exec /usr/bin/python3 scripts/evaluate.py "$@"
