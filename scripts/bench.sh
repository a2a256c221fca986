#!/usr/bin/env bash
# Builds the benchmarks (Release), runs bench_multibody, bench_contact_models and bench_integrator single-threaded with repeated,
# randomly interleaved runs (--benchmark_enable_random_interleaving, so a burst of load on a shared
# machine spreads over all benchmarks instead of skewing one) and writes the median and the
# min–max range over the repetitions to docs/BENCHMARKS.md: the machine (CPU, compiler, -march flags, the BLAS
# libtorch runs on, load average before, during and after the run), the multibody core with the
# verdict on the 20 µs one-core target for the NE residual with its θ-Jacobian, and the contact
# models (bench/bench_contact_models.cpp: V and V+dV/dξ for 4 contacts) with their targets.
#
#   scripts/bench.sh                 # all benchmarks
#   scripts/bench.sh --benchmark_filter=quadruped   # extra arguments go to every benchmark binary
#
# Environment: NMDP_BUILD_DIR (default build), NMDP_BENCH_CPU (pin to this CPU with taskset),
# NMDP_BENCH_REPETITIONS (default 5), NMDP_BENCH_CONTACT_REPETITIONS (bench_contact_models, whose
# runs are short and noisy; default 10), NMDP_BENCH_INTEGRATOR_REPEATS (bench_integrator's runs per
# method, default 3), NMDP_BENCH_OUTPUT (default docs/BENCHMARKS.md; a relative
# path is taken from the directory the script is started in).
# A benchmark that was not run (filtered out, or the published RBF model without ../shared) gets a
# row that says so; a binary that fails stops the script (set -e) before the output is written.
set -euo pipefail
output=""
[ -n "${NMDP_BENCH_OUTPUT:-}" ] && output=$(realpath -m -- "$NMDP_BENCH_OUTPUT")
cd "$(dirname "$0")/.."
root=$(pwd)
output=${output:-$root/docs/BENCHMARKS.md}
build_dir=${NMDP_BUILD_DIR:-build}
repetitions=${NMDP_BENCH_REPETITIONS:-5}
contact_repetitions=${NMDP_BENCH_CONTACT_REPETITIONS:-10}

# The source state that is built (taken now: the tree may change while the benchmarks run).
source_commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
source_dirty=$(git status --porcelain --untracked-files=no 2>/dev/null | head -c1 || true)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DNMDP_BUILD_BENCH=ON >/dev/null
# The benchmarks this page reports. bench_fit (the fit times) and bench_mujoco (the
# side-by-side run, which writes docs/results/mujoco_a1.md) run on their own.
# A missing one fails the build below rather than leaving the page silently short of it.
targets=(bench_multibody bench_contact_models bench_integrator)
cmake --build "$build_dir" -j"$(nproc)" --target "${targets[@]}"

pin=()
if [ -n "${NMDP_BENCH_CPU:-}" ] && command -v taskset >/dev/null; then
  pin=(taskset -c "$NMDP_BENCH_CPU")
fi

results_dir="$build_dir/bench/results"
mkdir -p "$results_dir"
rm -f "$results_dir"/bench_*.json  # no stale results from an earlier run or a removed benchmark
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
# Sample the 1-min load average every 2 s while the benchmarks run (how busy the machine was).
load_samples="$results_dir/loadavg.txt"
cut -d' ' -f1 /proc/loadavg >"$load_samples"
( while sleep 2; do cut -d' ' -f1 /proc/loadavg; done ) >>"$load_samples" &
sampler=$!
trap 'kill "$sampler" 2>/dev/null || true' EXIT
json_files=()
for target in "${targets[@]}"; do
  [ "$target" = bench_integrator ] && continue  # not a Google Benchmark binary: run below
  out="$results_dir/$target.json"
  reps=$repetitions
  [ "$target" = bench_contact_models ] && reps=$contact_repetitions
  echo "running $target ($reps repetitions, interleaved) ..." >&2
  # The file keeps every repetition (for the range); aggregates only on the console.
  "${pin[@]}" "$build_dir/bench/$target" \
    --benchmark_repetitions="$reps" --benchmark_enable_random_interleaving=true \
    --benchmark_display_aggregates_only=true \
    --benchmark_format=json --benchmark_out="$out" --benchmark_out_format=json "$@" >/dev/null
  json_files+=("$out")
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
kill "$sampler" 2>/dev/null || true
wait "$sampler" 2>/dev/null || true
trap - EXIT
cut -d' ' -f1 /proc/loadavg >>"$load_samples"
load_during=$(awk 'NR == 1 { min = max = $1 } { sum += $1; if ($1 < min) min = $1; if ($1 > max) max = $1 }
  END { if (NR) printf "%.2f–%.2f (mean %.2f, %d samples)", min, max, sum / NR, NR }' "$load_samples")
load_max=$(sort -g "$load_samples" | tail -n1)

compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
compiler_version=$("${compiler:-c++}" --version | head -n1)
flags=$(sed -n 's/^CMAKE_CXX_FLAGS_RELEASE:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
eigen_version=$(sed -n 's/^#define EIGEN_\(WORLD\|MAJOR\|MINOR\)_VERSION \([0-9]*\)/\2/p' \
  /usr/include/eigen3/Eigen/src/Core/util/Macros.h 2>/dev/null | paste -sd. || true)
cpu_model=$(sed -n 's/^model name[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo | head -n1)
# The target flags the benchmarks were compiled with (add_compile_options, e.g. NMDP_NATIVE's
# -march=native -mno-avx512f, are not in CMAKE_CXX_FLAGS_RELEASE) and what -march=native means here.
target_flags=""
for target in "${targets[@]}"; do
  flags_make="$build_dir/bench/CMakeFiles/$target.dir/flags.make"
  if [ -f "$flags_make" ]; then
    target_flags=$(sed -n 's/^CXX_FLAGS = //p' "$flags_make" | tr ' ' '\n' | grep -E '^-m' | paste -sd' ' || true)
    break
  fi
done
native_arch=""
case " $target_flags " in
  *" -march=native "*)
    native_arch=$("${compiler:-c++}" -march=native -Q --help=target 2>/dev/null |
      sed -n 's/^[[:space:]]*-march=[[:space:]]*//p' | head -n1 || true) ;;
esac
# The BLAS libtorch calls (Debian's alternatives link libblas.so.3 to the chosen implementation).
blas_link=/usr/lib/x86_64-linux-gnu/libblas.so.3
blas_path=$(readlink -f "$blas_link" 2>/dev/null || true)
blas_package=""
if [ -n "$blas_path" ] && [ -e "$blas_path" ]; then
  blas_package=$(dpkg -S "$blas_path" 2>/dev/null | head -n1 | cut -d: -f1 || true)
  if [ -n "$blas_package" ]; then
    blas_package="$blas_package $(dpkg-query -W -f='${Version}' "$blas_package" 2>/dev/null || true)"
  fi
else
  blas_path="not found ($blas_link absent)"
fi
rbf_present=""
[ -e "$root/../shared/granular/robosimian_sand_rbf" ] && rbf_present=1

mkdir -p "$(dirname "$output")"
NMDP_NPROC=$(nproc) NMDP_CPU="$cpu_model" NMDP_DATE="$(date -u '+%Y-%m-%d %H:%M UTC')" \
NMDP_COMPILER="$compiler_version" NMDP_FLAGS="$flags" NMDP_EIGEN="${eigen_version:-unknown}" \
NMDP_LOAD_BEFORE="$load_before" NMDP_LOAD_AFTER="$load_after" NMDP_REPS="$repetitions" \
NMDP_CONTACT_REPS="$contact_repetitions" \
NMDP_LOAD_DURING="$load_during" NMDP_LOAD_MAX="$load_max" \
NMDP_TARGET_FLAGS="$target_flags" NMDP_NATIVE_ARCH="$native_arch" \
NMDP_BLAS_PATH="$blas_path" NMDP_BLAS_PACKAGE="$blas_package" \
NMDP_OPENBLAS_THREADS="${OPENBLAS_NUM_THREADS:-unset}" NMDP_RBF_PRESENT="$rbf_present" \
NMDP_SOURCES="${targets[*]}" \
NMDP_PIN="${pin[*]:-}" NMDP_COMMIT="$source_commit" NMDP_DIRTY="$source_dirty" \
python3 - "${json_files[@]}" >"$output.partial" <<'PY'
import json, os, statistics, sys
from collections import OrderedDict

TARGET_NS = 20000.0
TARGET_BENCH, TARGET_ROBOT = "NeResidualWithContactsAndJacobian", "quadruped"
DESCRIPTIONS = {
    "ForwardKinematics": "world pose and motion axis of every body, world spatial inertias",
    "Rnea": "inverse dynamics τ(q, q̇, q̈), gravity included",
    "Crba": "joint-space mass matrix H(q)",
    "RneaDerivatives": "analytic ∂τ/∂q, ∂τ/∂q̇ and H (with τ)",
    "RneaDerivativesFiniteDifference": "∂τ/∂q and ∂τ/∂q̇ by central differences (4n RNEA calls)",
    "NeResidual": "NE residual G(θ) = RNEA(θ, θ̇, θ̈), no Jacobian",
    "NeResidualWithJacobian": "G and analytic ∂G/∂θ = ∂τ/∂q + ∂τ/∂q̇ / h + H / h²",
    "NeResidualJacobianFiniteDifference": "∂G/∂θ by central differences (2n RNEA calls)",
    "NeResidualWithContactsAndJacobian": "G and ∂G/∂θ including 4 foot contacts: J_cᵀ f_c and (∂J_cᵀ/∂θ) f_c",
    "ContactJacobianTerms": "the contact part of the previous row alone (4 × J_c, J_cᵀ f_c, (∂J_cᵀ/∂θ) f_c)",
    "TransformEnergyGradHess": "PBD inertial transform energy with gradient and exact Hessian",
    "GravityPotentialGradHess": "gravity potential with gradient and exact Hessian",
    "PbdEnergyGradHess": "forward kinematics + full PBD ∇E, ∇²E (inertial + gravity, summed)",
}

# Contact models (bench/bench_contact_models.cpp): benchmark name, what it is, target for V+dV (ns),
# and whether it needs ../shared (registered only when ../shared exists).
CONTACT_FILE = "bench_contact_models"
CONTACT_MODELS = [
    ("Coulomb4", "smooth Coulomb cone, K = 6", 1000.0, False),
    ("RbfPublished4", "published RBF sand model (`../shared/granular/robosimian_sand_rbf`), "
                      "103 centres × 26 vertices", 20000.0, True),
    ("Mlp2x64_4", "2×64 tanh MLP, libtorch autograd, K = 26", 100000.0, False),
]

rows = OrderedDict()    # kernel -> robot -> dict (multibody benchmarks)
robots = OrderedDict()  # robot -> nq
contact = OrderedDict() # model -> "V" / "V+dV" -> dict
contact_ran = False     # bench_contact_models produced a result file
context = None

def record(entry, b):
    scale = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
    if b.get("run_type") == "iteration":  # one repetition: kept for the range
        entry.setdefault("reps_real", []).append(b["real_time"] * scale)
        entry.setdefault("reps_cpu", []).append(b["cpu_time"] * scale)
        return
    agg = b.get("aggregate_name")
    if agg == "cv":
        entry["cv"] = b["real_time"]  # cv aggregates are ratios, reported in real_time
    elif agg == "median":
        entry["real"] = b["real_time"] * scale
        entry["cpu"] = b["cpu_time"] * scale

def finish(entry):
    # Range over the repetitions; the median from them too when Google Benchmark gave no aggregates.
    for key in ("real", "cpu"):
        reps = entry.get("reps_" + key)
        if not reps:
            continue
        entry[key + "_min"], entry[key + "_max"] = min(reps), max(reps)
        entry.setdefault(key, statistics.median(reps))

for path in sys.argv[1:]:
    is_contact = os.path.basename(path).startswith(CONTACT_FILE)
    contact_ran = contact_ran or is_contact
    try:
        with open(path) as f:
            doc = json.load(f)
    except (OSError, ValueError):
        continue  # no output: the filter matched nothing in this binary
    context = context or doc.get("context", {})
    for b in doc.get("benchmarks", []):
        if b.get("run_type") not in ("iteration", "aggregate"):
            continue
        parts = b.get("run_name", b["name"]).split("/")
        if is_contact:
            variant = parts[1] if len(parts) > 1 else "V"
            record(contact.setdefault(parts[0], OrderedDict()).setdefault(variant, {}), b)
            continue
        kernel = parts[0]
        robot = parts[1] if len(parts) > 1 else "-"
        nq = parts[2].split(":")[1] if len(parts) > 2 and parts[2].startswith("nq:") else "?"
        robots.setdefault(robot, nq)
        entry = rows.setdefault(kernel, OrderedDict()).setdefault(robot, {})
        record(entry, b)

for per_robot in rows.values():
    for e in per_robot.values():
        finish(e)
for per in contact.values():
    for e in per.values():
        finish(e)

def fmt(ns):
    return f"{ns:,.0f}" if ns is not None else "—"

env = os.environ
out = []
out.append("# Benchmarks")
out.append("")
sources = ", ".join(f"`bench/{t}.cpp`" for t in env.get("NMDP_SOURCES", "bench_multibody").split())
out.append(f"Generated by `scripts/bench.sh` (do not edit by hand). Sources: {sources}.")
out.append("")
out.append("## Machine")
out.append("")
out.append(f"- date: {env['NMDP_DATE']}")
out.append(f"- CPU: {env['NMDP_CPU']} — `nproc` = {env['NMDP_NPROC']}"
           + (f", {context.get('mhz_per_cpu')} MHz" if context and context.get('mhz_per_cpu') else ""))
out.append(f"- compiler: {env['NMDP_COMPILER']}, flags `{env['NMDP_FLAGS']}` (CMake Release), Eigen {env['NMDP_EIGEN']}")
if env.get("NMDP_TARGET_FLAGS"):
    native = f" (`-march=native` = `{env['NMDP_NATIVE_ARCH']}` here)" if env.get("NMDP_NATIVE_ARCH") else ""
    out.append(f"- target flags: `{env['NMDP_TARGET_FLAGS']}`{native}")
else:
    out.append("- target flags: none (`NMDP_NATIVE=OFF`: generic x86-64)")
blas_pkg = f" (package {env['NMDP_BLAS_PACKAGE']})" if env.get("NMDP_BLAS_PACKAGE") else ""
out.append(f"- BLAS used by libtorch: `libblas.so.3` → `{env['NMDP_BLAS_PATH']}`{blas_pkg}; "
           f"libtorch intra-op threads set to 1 by the MLP, `OPENBLAS_NUM_THREADS` {env['NMDP_OPENBLAS_THREADS']}")
commit = env["NMDP_COMMIT"] + (" + uncommitted changes to tracked files" if env.get("NMDP_DIRTY") else "")
out.append(f"- source: commit {commit}")
out.append(f"- load average (1, 5, 15 min) before: {env['NMDP_LOAD_BEFORE']}, after: {env['NMDP_LOAD_AFTER']}"
           + (f"; 1-min load during the run (every 2 s): {env['NMDP_LOAD_DURING']}" if env.get("NMDP_LOAD_DURING") else ""))
if context and context.get("library_build_type") == "debug":
    out.append("- the distribution's Google Benchmark library reports itself as a debug build; this affects"
               " only the harness, the measured code is built Release")
out.append("")
out.append("## Method")
out.append("")
out.append(f"Every benchmark runs on one thread{' pinned with `' + env['NMDP_PIN'] + '`' if env.get('NMDP_PIN') else ''}, "
           f"at one fixed random state per robot, with all outputs preallocated; "
           f"{env['NMDP_REPS']} repetitions run in random interleaved order "
           "(`--benchmark_repetitions`, `--benchmark_enable_random_interleaving`), so that a burst of load "
           "spreads over all benchmarks. The first table gives the **median wall-clock time per call in ns** "
           "over the repetitions and, in parentheses, the fastest–slowest repetition. "
           "A second table gives the median CPU time; when the machine is shared the two differ and "
           "the CPU time is the better estimate of the cost on an idle core.")
out.append("")
out.append("Robots (floating base unless stated): `quadruped` is the project's 18-DOF quadruped "
           "(`models/quadruped/quadruped.urdf`); `a1` the Unitree A1, `robosimian` RoboSimian with all "
           "32 joints active, `robosimian_paper_planar` RoboSimian in the paper's configuration (planar "
           "base, joints 2, 4, 6 of each limb) — these three from `../shared/robots`, skipped when absent. "
           "Contacts: `FL/FR/RL/RR_foot` (RoboSimian: `limb{1..4}_link7`), at the link origin.")
out.append("")

def table(key, title):
    names = list(robots)
    out.append(f"## {title}")
    out.append("")
    if not names:
        out.append("No multibody benchmark in this run (filtered out).")
        out.append("")
        return
    out.append("| benchmark | " + " | ".join(f"{r} (n={robots[r]})" for r in names) + " | what |")
    out.append("|---|" + "---:|" * len(names) + "---|")
    for kernel, per_robot in rows.items():
        cells = []
        for r in names:
            e = per_robot.get(r)
            if not e or key not in e:
                cells.append("—")
                continue
            cell = fmt(e[key])
            if kernel == TARGET_BENCH and r == TARGET_ROBOT:
                cell = f"**{cell}**"
            if key == "real" and "real_min" in e:
                cell += f" ({fmt(e['real_min'])}–{fmt(e['real_max'])})"
            cells.append(cell)
        out.append(f"| {kernel} | " + " | ".join(cells) + f" | {DESCRIPTIONS.get(kernel, '')} |")
    out.append("")

table("real", "Median wall-clock time per call (ns; fastest–slowest repetition in parentheses)")
table("cpu", "Median CPU time per call (ns)")

# Analytic against finite differences.
out.append("## Analytic derivatives against finite differences (measured)")
out.append("")
out.append("Ratios of median CPU times (less sensitive than wall-clock time to other load on the machine).")
out.append("")
out.append("| robot | ∂τ/∂q, ∂τ/∂q̇: FD / analytic | ∂G/∂θ: FD / analytic |")
out.append("|---|---:|---:|")
for r in robots:
    def ratio(num, den):
        a, b = rows.get(num, {}).get(r, {}).get("cpu"), rows.get(den, {}).get(r, {}).get("cpu")
        return f"{a / b:.1f}× ({fmt(a)} vs {fmt(b)} ns)" if a and b else "—"
    out.append(f"| {r} | {ratio('RneaDerivativesFiniteDifference', 'RneaDerivatives')} | "
               f"{ratio('NeResidualJacobianFiniteDifference', 'NeResidualWithJacobian')} |")
out.append("")
out.append("The analytic ∂τ/∂q, ∂τ/∂q̇ also return H (which finite differences would need n more RNEA "
           "calls for) and are exact to round-off.")
out.append("")

# The machine counts as shared when the 1-min load average reached nproc − ½ before, during or after.
busy = max(float(env[k].split()[0]) for k in ("NMDP_LOAD_BEFORE", "NMDP_LOAD_AFTER", "NMDP_LOAD_MAX")
           if env.get(k)) > float(env["NMDP_NPROC"]) - 0.5

# The target.
out.append("## Target: the NE residual with its θ-Jacobian in 20 µs on one core")
out.append("")
e = rows.get(TARGET_BENCH, {}).get(TARGET_ROBOT)
if not e:
    out.append(f"**Not measured**: `{TARGET_BENCH}/{TARGET_ROBOT}` is missing from this run.")
else:
    real, cpu = e["real"], e["cpu"]
    def verdict(t):
        return "**met**" if t <= TARGET_NS else "**NOT met**"
    out.append(f"Target: `{TARGET_BENCH}` on the 18-DOF quadruped (floating base, 4 foot contacts: "
               f"G(θ) = RNEA(θ, θ̇, θ̈) − Σ J_cᵀ f_c and the complete ∂G/∂θ of DESIGN.md 2.1 for a fixed "
               f"wrench per foot) ≤ {TARGET_NS / 1000:.0f} µs per call on one core.")
    out.append("")
    if busy:
        out.append(f"The machine was shared during this run (load average ≥ {env['NMDP_NPROC']} − ½): the "
                   "wall-clock time includes time the thread waited for a core, so the **CPU time is the "
                   "figure to judge the one-core target by**; rerun on an idle machine for a clean wall-clock number.")
        out.append("")
    out.append(f"- median wall-clock time: {real / 1000:.1f} µs — target {verdict(real)} "
               f"({real / TARGET_NS:.2f}× the budget)")
    out.append(f"- median CPU time: {cpu / 1000:.1f} µs — target {verdict(cpu)} ({cpu / TARGET_NS:.2f}× the budget)")
    if "real_min" in e:
        out.append(f"- fastest of the {env['NMDP_REPS']} repetitions (the least disturbed one): "
                   f"{e['real_min'] / 1000:.1f} µs wall-clock, {e['cpu_min'] / 1000:.1f} µs CPU")
    out.append("")
    if real > TARGET_NS or cpu > TARGET_NS:
        parts = []
        for k in ("NeResidual", "RneaDerivatives", "NeResidualWithJacobian", "ContactJacobianTerms"):
            v = rows.get(k, {}).get(TARGET_ROBOT, {}).get("cpu")
            if v:
                parts.append(f"`{k}` {v / 1000:.1f} µs")
        out.append("Where the time goes (median CPU time on the quadruped): " + ", ".join(parts) + ".")
        out.append("")
# Contact models.
def us(ns):
    if ns is None:
        return "—"
    v = ns / 1000
    return f"{v:.2f}" if v < 10 else f"{v:.1f}" if v < 1000 else f"{v:,.0f}"

out.append("## Contact models (4 contacts, one core)")
out.append("")
out.append("`bench/bench_contact_models.cpp`: one `ContactModel::evaluate` call for the 4 feet of a quadruped "
           "standing a few mm deep on a plane, legs slightly tilted, outputs preallocated: **V** is the "
           "wrench at the contact vertices alone, **V+dV** adds its derivatives dV/dξ. Same method as "
           f"above (one thread, {env['NMDP_CONTACT_REPS']} repetitions, randomly interleaved); times in **µs**: "
           "the median over the repetitions and, in parentheses, the fastest–slowest repetition. "
           "The targets are on the median V+dV.")
out.append("")
if busy:
    out.append(f"The machine was shared during this run (load average ≥ {env['NMDP_NPROC']} − ½): judge the "
               "targets by the **CPU time**; the wall-clock time includes time the thread waited for a core.")
    out.append("")
out.append("| model | V wall | V CPU | V+dV wall | V+dV CPU | target (V+dV) | met? | what |")
out.append("|---|---:|---:|---:|---:|---:|---|---|")

def cell_us(e, key):
    if not e or key not in e:
        return "—"
    c = us(e[key])
    if key + "_min" in e:
        c += f" ({us(e[key + '_min'])}–{us(e[key + '_max'])})"
    return c

def times(r):
    s = f"{r:.2f}"
    return (f"{r:.3f}" if s == "1.00" else s) + "×"  # 0.995× and 1.004× do not both read 1.00×

def verdict(e, target):
    if not e or "real" not in e or target is None:
        return "—"
    cpu_ok, real_ok = e["cpu"] < target, e["real"] < target
    if cpu_ok and real_ok:
        return f"**met** ({times(e['cpu'] / target)} the budget)"
    if cpu_ok:
        return f"**met** on CPU time ({times(e['cpu'] / target)}), not on wall-clock ({times(e['real'] / target)})"
    return f"**NOT met** ({times(e['cpu'] / target)} the budget on CPU time)"

known = [m[0] for m in CONTACT_MODELS]
models = list(CONTACT_MODELS) + [(name, "", None, False) for name in contact if name not in known]
for name, what, target, needs_shared in models:
    target_cell = f"< {target / 1000:g} µs" if target else "—"
    per = contact.get(name)
    if not per:
        if needs_shared and not env.get("NMDP_RBF_PRESENT"):
            reason = "skipped (../shared absent)"
        elif not contact_ran:
            reason = "not measured (`bench_contact_models` not run)"
        else:
            reason = "not measured (filtered out)"
        out.append(f"| {name} | {reason} | | | | {target_cell} | — | {what} |")
        continue
    v, dv = per.get("V"), per.get("V+dV")
    out.append(f"| {name} | {cell_us(v, 'real')} | {cell_us(v, 'cpu')} | {cell_us(dv, 'real')} | "
               f"{cell_us(dv, 'cpu')} | {target_cell} | {verdict(dv, target)} | {what} |")
out.append("")
fastest = [f"{m[0]} {us(contact[m[0]]['V+dV']['real_min'])} µs wall / {us(contact[m[0]]['V+dV']['cpu_min'])} µs CPU"
           for m in models if "real_min" in contact.get(m[0], {}).get("V+dV", {})]
if fastest:
    out.append(f"Fastest of the {env['NMDP_CONTACT_REPS']} repetitions of V+dV (the least disturbed one): "
               + "; ".join(fastest) + ".")
    out.append("")
print("\n".join(out))
PY
# The integrator: whole simulated steps of a trotting quadruped, which Google Benchmark's
# fixed-input loop does not fit; the binary interleaves its repeated runs itself.
echo "running bench_integrator (${NMDP_BENCH_INTEGRATOR_REPEATS:-3} interleaved runs per method) ..." >&2
{
  echo "## The integrator: the project's quadruped trotting (bench/bench_integrator.cpp)"
  echo
  echo "Target: ne-pgm at most 0.5 ms per 50 ms step, the zeroth-order variants at most 3× their"
  echo "first-order twins, no heap allocation inside a step once warmed up."
  echo
  "${pin[@]}" "$build_dir/bench/bench_integrator" --repeats "${NMDP_BENCH_INTEGRATOR_REPEATS:-3}"
  echo
} >>"$output.partial"
mv -f "$output.partial" "$output"
echo "wrote $output" >&2
