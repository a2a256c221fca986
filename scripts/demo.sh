#!/usr/bin/env bash
# Set-up command 1 (the main job): install what is missing, build, and run the demo of what the
# toolkit does today: load the project's quadruped (and the real robots of ../shared when present),
# print their summaries, and time the articulated-body core.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
echo
echo "== nmdp inspect models/quadruped/quadruped.urdf"
build/nmdp inspect models/quadruped/quadruped.urdf
if [ -d ../shared/robots ]; then
  for robot in a1/urdf/a1.urdf solo12/urdf/solo12.urdf; do
    echo
    echo "== nmdp inspect ../shared/robots/$robot  (dof, mass and feet)"
    build/nmdp inspect "../shared/robots/$robot" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(json.dumps({k: d[k] for k in ("robot","dof","total_mass","feet") if k in d}, indent=1))'
  done
  echo
  echo "== RoboSimian as in the paper: planar base, joints 2, 4, 6 of each limb active"
  locks=()
  for limb in 1 2 3 4; do for j in 0 1 3 5 7; do locks+=(--lock "limb${limb}_joint${j}=0"); done; done
  build/nmdp inspect ../shared/robots/robosimian/robosimian_caesar_new_all_active.urdf --base planar "${locks[@]}" \
    | python3 -c 'import json,sys; d=json.load(sys.stdin); print(json.dumps({k: d[k] for k in ("robot","dof","joint_names","total_mass","feet") if k in d}))'
else
  echo "(../shared is absent: skipping the real robots)"
fi
echo
echo "== articulated-body core timings (18-DOF quadruped, one core)"
build/bench/bench_multibody --benchmark_filter='/quadruped/' --benchmark_min_time=0.2 2>/dev/null
