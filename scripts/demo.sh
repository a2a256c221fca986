#!/usr/bin/env bash
# Set-up command 1 (the main job): install what is missing, build, and run the default demo: the
# project's quadruped trotting on granular terrain for 10 s at dt = 50 ms
# (models/scenes/quadruped_trot_sand3d.json: floating base, ne-pgm, the default trot, the 3-D sand
# model fitted from 3-D RFT samples in data/granular/), written to demo/trot.h5 as it runs, and
# plotted to demo/trot.png (torso height
# and forward distance against time, read back from the HDF5 file), and replayed by demo/trot.html
# (`nmdp view`: one self-contained page, opened in any browser). It installs and builds only what
# the demo needs (no GoogleTest, Google Benchmark, MuJoCo or chromium; no tests or benchmarks):
# scripts/test.sh installs and builds the rest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --demo
scripts/build.sh --nmdp
mkdir -p demo
echo
echo "== nmdp simulate models/scenes/quadruped_trot_sand3d.json --out demo/trot.h5"
build/nmdp simulate models/scenes/quadruped_trot_sand3d.json --out demo/trot.h5
# Debian's python3 has matplotlib and h5py (installed by install-deps.sh --demo); another python3 first on
# PATH (pyenv, conda) may not.
/usr/bin/python3 scripts/plot_run.py demo/trot.h5 demo/trot.png
echo
echo "== nmdp view demo/trot.h5 --out demo/trot.html"
# It prints how to open the page ("open it in a browser, e.g. chromium demo/trot.html").
build/nmdp view demo/trot.h5 --out demo/trot.html
