// A1 trotting on flat ground, side by side with MuJoCo, on the same robot, the same PD targets and
// gains, the same initial state and the same friction coefficient.
//
// Ours: the scene models/scenes/a1_trot_flat.json built by buildSimulation (sim/simulation.hpp), as
// `nmdp simulate` builds it (robot, contact points, Coulomb model, terrain, gains, trot gait,
// initial state, integrator options), run with ne-pgm and pbd-pgm at several dt (each run a fresh
// Simulation with integrator.dt set). MuJoCo (2.2.x, the Debian package): A1's URDF handed to
// MuJoCo's own importer from memory with the oracle test's edits (tests/support/mujoco_urdf.hpp),
// plus a floating joint on the root link (MuJoCo's free joint) and a ground box with its top face at z = 0,
// all in the URDF text (no lossy MJCF round trip). Only the foot spheres of the URDF's collision
// geometry touch the ground (every other geom collides with nothing, as in ours, where only the
// feet are contact points); their friction and the ground's are μ of our Coulomb model (condim 3,
// MuJoCo's default pyramidal cone); joint limits are off (ours has none). MuJoCo's defaults
// otherwise: Euler integrator, Newton solver, solref/solimp (checked). The PD torque
// τ = kp (q* − q) + kd (q̇* − q̇) + τ_ff, with (q*, q̇*) our gait's target at the step's start time
// and our gains, goes into qfrc_applied before every mj_step: explicit PD at the old state, where
// our integrator evaluates the stable PD at the new state (q*, q̇* at t + h). A second MuJoCo
// configuration, "MuJoCo, implicit kd", is what a MuJoCo user would set up for stiff damped joints:
// the kd (−q̇) part as the joints' dof_damping, which MuJoCo's Euler integrator integrates
// implicitly, and only kp (q* − q) + kd q̇* + τ_ff in qfrc_applied.
//
// Speed at equal accuracy (bench/equal_accuracy.hpp): for each engine the cheapest configuration
// (family and dt) whose run stays within 5 % of its family's finest run, and the ratio of their wall
// times per simulated second. Our families are ne-pgm and pbd-pgm at the scene's other integrator
// settings, plus one per --ours-config (a list of integrator.* settings, e.g.
// "integrator.method=ne-pgm;integrator.order=2"), so that later integrator features are measured
// without changing this file.
//
// The scene as it is (its default gains: control/default_gains.hpp), and with --damped-kd KD a
// second scenario with every joint's kd set to KD.
//
// Per run: wall time and this thread's CPU time per simulated second (median over --repeats
// interleaved repeats, one core), stability, forward distance, and the RMS torso-position
// deviation from the finest run of the same engine/method over the coarser run's own time grid
// (every dt here is a multiple of the finest one, so the finest run is sampled at exactly those
// times). Output: a markdown table on stdout, also written to --out (default
// docs/results/mujoco_a1.md in the source tree).
//
// Usage: bench_mujoco [--repeats N] [--duration S] [--out FILE] [--scene SCENE.json] [--set key.path=value]...
//                     [--ours-config "integrator.key=value;..."]...
//                     [--mujoco-dts S,..] [--ours-dts S,..] [--mujoco-extra-dts S,..] [--ours-extra-dts S,..]
// (the extra dts are run once: the finest run of each family, never a candidate for the cheapest);
//                     [--damped-kd KD] [--mujoco-timeconst T] [--mujoco-elliptic 0|1]
// (the last two are diagnostics that leave MuJoCo's contact defaults, flagged in the output).
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "equal_accuracy.hpp"
#include "mujoco_a1_runs.hpp"
#include "contact_models/coulomb_model.hpp"
#include "sim/simulation.hpp"

using namespace nmdp;

namespace {

using namespace bench;

// ---- comparison -----------------------------------------------------------------------------------

struct Row {
  std::string family;  // kMujoco, kMujocoImplicitKd, or one of our configurations ("ne-pgm", ...)
  const Ours* ours = nullptr;  // our configuration's system, for our rows
  double dt = 0;
  std::vector<Run> runs;  // repeats
  // filled in later
  double wall_per_s = NAN, cpu_per_s = NAN;
  double rms = NAN;  // m
  bool has_rms = false;
  bool within = false;  // within 5 % of the family's finest run
  bool extra = false;   // run once: a convergence check or the finest run, never a candidate for the cheapest
};

bench::Accuracy accuracyOf(const Run& r) { return {r.stable, std::hypot(r.forward, r.lateral), r.yaw}; }

std::vector<double> parseList(const std::string& text) {  // "0.001,0.002"
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stod(item));
  return out;
}

// RMS of ‖p(t) − p_ref(t)‖ over the coarser run's grid (one dt must be a multiple of the other, so
// the finer run is sampled at exactly those times), up to where either run stopped.
bool rmsDeviation(const Run& run, double dt, const Run& ref, double dt_ref, double& out) {
  const bool coarser = dt >= dt_ref;
  const long ratio = std::lround(coarser ? dt / dt_ref : dt_ref / dt);
  if (std::abs(ratio * (coarser ? dt_ref : dt) - (coarser ? dt : dt_ref)) > 1e-9 * std::max(dt, dt_ref)) return false;
  const std::vector<Vec3>& a = coarser ? run.position : ref.position;  // coarse
  const std::vector<Vec3>& b = coarser ? ref.position : run.position;  // fine
  double sum = 0;
  long n = 0;
  for (size_t k = 0; k < a.size() && k * ratio < b.size(); ++k, ++n) sum += (a[k] - b[k * ratio]).squaredNorm();
  if (n == 0) return false;
  out = std::sqrt(sum / n);
  return true;
}

std::string fmtTime(double s) {
  char b[32];
  if (s >= 1) std::snprintf(b, sizeof b, "%.2f s", s);
  else if (s >= 1e-3) std::snprintf(b, sizeof b, "%.1f ms", 1e3 * s);
  else std::snprintf(b, sizeof b, "%.0f µs", 1e6 * s);
  return b;
}

std::string fmtDt(double dt) {
  char b[32];
  std::snprintf(b, sizeof b, "%g ms", 1e3 * dt);
  return b;
}

struct Args {
  int repeats = 3;
  double duration = 10.0;
  // Run once each, shown; the finest dt of a family is its reference.
  std::vector<double> mujoco_extra_dts = {0.0005}, ours_extra_dts = {0.001};
  std::string out_path = std::string(NMDP_SOURCE_DIR) + "/docs/results/mujoco_a1.md";
  std::string scene_path = std::string(NMDP_SOURCE_DIR) + "/models/scenes/a1_trot_flat.json";
  std::vector<std::string> overrides;  // --set key.path=value, as for nmdp simulate
  // Our configurations: a label and its integrator.* settings (--ours-config adds one each).
  std::vector<std::pair<std::string, std::vector<std::string>>> ours_configs = {
      {"ne-pgm", {"integrator.method=ne-pgm"}}, {"pbd-pgm", {"integrator.method=pbd-pgm"}}};
  std::vector<double> mujoco_dts = {0.001, 0.002, 0.005, 0.01, 0.02, 0.05};
  std::vector<double> ours_dts = {0.005, 0.01, 0.02, 0.03, 0.04, 0.05};
  double damped_kd = 0.0;  // the second scenario's controller.kd (0: no second scenario)
  double mujoco_timeconst = 0;  // > 0: MuJoCo contact solref time constant (diagnostics; default 0.02)
  bool mujoco_elliptic = false;  // diagnostics: elliptic friction cone
};

// "integrator.method=ne-pgm;integrator.order=2" → its settings; only integrator.* keys, so that every
// configuration runs the robot, gains and targets MuJoCo runs.
std::vector<std::string> parseConfiguration(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ';'))
    if (!item.empty()) {
      if (item.rfind("integrator.", 0) != 0 || item.find('=') == std::string::npos)
        throw std::runtime_error("--ours-config " + text + ": '" + item + "' is not an integrator.KEY=VALUE setting");
      out.push_back(item);
    }
  if (out.empty()) throw std::runtime_error("--ours-config " + text + ": no setting");
  return out;
}

// The smallest entry of a gain vector over the actuated coordinates (base coordinates hold zeros).
double actuatedMin(const Model& model, const Eigen::VectorXd& gain) {
  double out = INFINITY;
  for (int i = 0; i < model.nq; ++i)
    if (!model.bodies[i].is_base) out = std::min(out, gain[i]);
  return out;
}

// snprintf onto the end of `md` (one line of at most 1023 characters).
template <class... A>
void appendf(std::string& md, const char* fmt, A... args) {
  char line[1024];
  std::snprintf(line, sizeof line, fmt, args...);
  md += line;
}

// One scenario's engines: our configurations (the scene's as the first), MuJoCo's model of the same
// robot, the friction coefficient and the stability bounds.
struct Scenario {
  std::unique_ptr<Ours> base;
  std::vector<std::unique_ptr<Ours>> configurations;  // one per Args::ours_configs
  Mujoco mj;
  double mu = 0;
  Bounds bounds;
};

Scenario setUp(const Args& a, const std::vector<std::string>& overrides) {
  Scenario sc;
  sc.base = buildOurs(a.scene_path, overrides);
  const Ours& o = *sc.base;
  sc.mu = dynamic_cast<const CoulombModel&>(o.sim.contactModel()).parameters().mu;
  for (const auto& [label, settings] : a.ours_configs) {
    std::vector<std::string> all = overrides;
    all.insert(all.end(), settings.begin(), settings.end());
    sc.configurations.push_back(buildOurs(a.scene_path, all));
  }
  sc.mj = buildMujoco(o, sc.mu);
  // Diagnostics only (the tables are with MuJoCo's defaults): stiffer contacts, elliptic cone.
  if (a.mujoco_timeconst > 0)
    for (int g = 0; g < sc.mj.m->ngeom; ++g) sc.mj.m->geom_solref[mjNREF * g] = a.mujoco_timeconst;
  if (a.mujoco_elliptic) sc.mj.m->opt.cone = mjCONE_ELLIPTIC;
  Vec3 p, rpy;
  o.sim.basePose(p, rpy);  // the initial state
  sc.bounds.z_low = 0.5 * p.z();
  sc.bounds.z_high = 1.5 * p.z();
  return sc;
}

// Every run of the scenario, each engine's extra (finest) dts first, repeated interleaved; the rows
// run once (finer than the benchmarked grid) only in the first repeat.
std::vector<Row> runRows(const Args& a, Scenario& sc) {
  std::vector<Row> rows;
  auto add_row = [&](const std::string& family, const Ours* ours, double dt, bool extra) {
    Row row;
    row.family = family, row.ours = ours, row.dt = dt, row.extra = extra;
    rows.push_back(std::move(row));
  };
  for (const char* engine : {kMujoco, kMujocoImplicitKd}) {
    for (double dt : a.mujoco_extra_dts) add_row(engine, nullptr, dt, true);
    for (double dt : a.mujoco_dts) add_row(engine, nullptr, dt, false);
  }
  for (size_t k = 0; k < a.ours_configs.size(); ++k) {
    for (double dt : a.ours_extra_dts) add_row(a.ours_configs[k].first, sc.configurations[k].get(), dt, true);
    for (double dt : a.ours_dts) add_row(a.ours_configs[k].first, sc.configurations[k].get(), dt, false);
  }
  for (int rep = 0; rep < a.repeats; ++rep)
    for (Row& row : rows) {
      if (row.extra && rep > 0) continue;
      std::fprintf(stderr, "repeat %d: %s dt = %g ...", rep + 1, row.family.c_str(), row.dt);
      row.runs.push_back(isMujoco(row.family)
                             ? runMujoco(*sc.base, sc.mj, row.dt, a.duration, sc.bounds, row.family == kMujocoImplicitKd)
                             : runOurs(*row.ours, row.dt, a.duration, sc.bounds));
      const Run& r = row.runs.back();
      std::fprintf(stderr, " %.3f s wall, forward %.3f m%s%s\n", r.wall, r.forward, r.stable ? "" : ", unstable: ",
                   r.why.c_str());
    }
  return rows;
}

// Per row: medians; deviation from the finest run of the same family (its first repeat: every
// repeat is bit-identical), and whether it is within 5 % of it.
struct Summary {
  std::map<std::string, const Row*> finest;
  std::vector<bench::Configuration> timed;
};

Summary summarize(std::vector<Row>& rows) {
  Summary s;
  for (const Row& row : rows)
    if (!s.finest.count(row.family) || row.dt < s.finest[row.family]->dt) s.finest[row.family] = &row;
  for (Row& row : rows) {
    std::vector<double> wall, cpu;
    for (const Run& r : row.runs)
      if (r.t_end > 0) wall.push_back(r.wall / r.t_end), cpu.push_back(r.cpu / r.t_end);
    row.wall_per_s = median(wall);
    row.cpu_per_s = median(cpu);
    const Row& ref = *s.finest[row.family];
    row.has_rms = rmsDeviation(row.runs.front(), row.dt, ref.runs.front(), ref.dt, row.rms);
    row.within = bench::withinTolerance(accuracyOf(row.runs.front()), row.has_rms ? row.rms : NAN, accuracyOf(ref.runs.front()));
    s.timed.push_back({isMujoco(row.family) ? "MuJoCo" : "nmdp", row.family, row.dt, row.wall_per_s, row.cpu_per_s,
                       row.within, !row.extra});
  }
  return s;
}

double targetCost(const Ours& o) {  // s per evaluation of our gait target
  PdTarget t;
  t.position = Eigen::VectorXd::Zero(o.sim.model().nq);
  t.velocity = Eigen::VectorXd::Zero(o.sim.model().nq);
  const int n = 20000;
  const double c0 = threadCpuSeconds();
  for (int i = 0; i < n; ++i) o.sim.targets().evaluate(1e-3 * i, t);
  return (threadCpuSeconds() - c0) / n;
}

std::string introduction(const Args& a, const Scenario& sc) {
  const Model& model = sc.base->sim.model();
  const PdGains& gains = sc.base->sim.system().gains;
  std::string md;
  appendf(md,
          "A1 (%d DOF, %.2f kg) trotting on flat ground for %g s (`%s`: floating base, "
          "Coulomb μ = %g, the built-in trot, gains kp %.4g–%.4g, kd %.4g–%.4g over the joints), ours vs MuJoCo %s (Euler, Newton solver, pyramidal cone; PD explicit via qfrc_applied, "
          "or, as \"MuJoCo, implicit kd\", its kd part as implicit joint damping) on the same "
          "robot, PD targets, gains and initial standing pose; one core, %d interleaved repeats (medians), "
          "`bench/bench_mujoco.cpp`.\n\n",
          model.nq, model.total_mass, a.duration, std::filesystem::path(a.scene_path).filename().c_str(), sc.mu,
          actuatedMin(model, gains.kp), gains.kp.maxCoeff(), actuatedMin(model, gains.kd), gains.kd.maxCoeff(),
          mujocoVersion().c_str(), a.repeats);
  if (a.ours_configs.size() > 2) {
    md += "Our configurations (each an nmdp family with its own finest run): ";
    for (size_t k = 0; k < a.ours_configs.size(); ++k) {
      md += (k ? "; " : "") + std::string("**") + a.ours_configs[k].first + "**:";
      for (const std::string& s : a.ours_configs[k].second) md += " `" + s + "`";
    }
    md += ".\n\n";
  }
  return md;
}

// One table row per configuration and dt.
std::string tableRow(const Row& row, const Row& ref) {
  const Run& r = row.runs.front();
  const bool is_ref = &ref == &row;
  std::string stable = r.stable ? "yes" : "no: " + r.why;
  char rb[64] = "—", rel[64] = "—";
  if (is_ref) std::snprintf(rb, sizeof rb, "(reference)"), std::snprintf(rel, sizeof rel, "—");
  else if (row.has_rms) {
    std::snprintf(rb, sizeof rb, "%.4f m%s", row.rms, r.stable ? "" : " (until it stopped)");
    if (ref.runs.front().stable)
      std::snprintf(rel, sizeof rel, "%.1f %%", 100 * row.rms / std::max(1e-9, accuracyOf(ref.runs.front()).displacement));
    else
      std::snprintf(rel, sizeof rel, "— (reference fell)");
  }
  char fwd[64];
  if (r.stable) std::snprintf(fwd, sizeof fwd, "%.3f m", r.forward);
  else std::snprintf(fwd, sizeof fwd, "(%.3f m by t = %.2f s)", r.forward, r.t_end);
  char dxy[64];
  std::snprintf(dxy, sizeof dxy, "%.3f m, %+.2f rad", accuracyOf(r).displacement, r.yaw);
  char it[64] = "—";
  if (!isMujoco(row.family) && r.steps > 0)
    std::snprintf(it, sizeof it, "%.2f, %.1f", double(r.substeps) / r.steps, double(r.outer) / r.steps);
  char z[64];
  std::snprintf(z, sizeof z, "%.3f–%.3f m", r.z_min, r.z_max);
  std::string md;
  appendf(md, "| %s%s | %s | %s | %s | %.1f× | %s | %s | %s | %s | %s | %s | %s | %s |\n", row.family.c_str(),
          row.extra ? " (1 run)" : "", fmtDt(row.dt).c_str(), fmtTime(row.wall_per_s).c_str(), fmtTime(row.cpu_per_s).c_str(),
          1.0 / row.wall_per_s, stable.c_str(), fwd, dxy, rb, rel, row.within ? "yes" : "no", z, it);
  return md;
}

std::string table(const std::vector<Row>& rows, const Summary& s, const Scenario& sc, double duration) {
  std::string md;
  appendf(md,
          "| engine / configuration | dt | wall / simulated s | CPU / simulated s | real-time factor | stable? | forward in %g s | "
          "|Δ(x, y)|, yaw | RMS deviation from own finest run | same, / its |Δ(x, y)| | within 5 %% | torso height | "
          "sub-steps, outer it. / step |\n",
          duration);
  appendf(md, "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---|---:|---:|\n");
  for (const Row& row : rows) md += tableRow(row, *s.finest.at(row.family));
  appendf(md,
          "\nStable: no NaN, torso height within [%.3f, %.3f] m (0.5–1.5× the initial %.3f m), |roll|, |pitch| < 1 rad, "
          "every step of ours converged, no MuJoCo bad-qacc reset; an unstable run stops there (its time per simulated "
          "second is over the time it ran). Deviation: RMS over the run's own time grid of the 3-D torso-position "
          "difference from the same family's finest run, in metres and relative to that finest run's |Δ(x, y)|. "
          "Real-time factor: simulated / wall time. MuJoCo's times include evaluating our gait target and the PD torque "
          "every step (the target alone: %.2f µs per evaluation, measured here), as ours include its target per sub-step.\n\n",
          sc.bounds.z_low, sc.bounds.z_high, sc.bounds.z_low * 2, 1e6 * targetCost(*sc.base));
  appendf(md,
          "Within 5 %%: the run and its family's finest run are stable, the run's horizontal displacement |Δ(x, y)| is "
          "within %g %% of the finest run's, its RMS torso deviation is below %g %% of that distance, and its final |yaw| "
          "is below %g rad. Rows marked (1 run) are run once and are never the cheapest.\n\n",
          100 * bench::kDistanceTolerance, 100 * bench::kRmsTolerance, bench::kYawMax);
  return md;
}

// The headline: each engine's cheapest configuration within 5 % of its own finest run.
std::string speedAtEqualAccuracy(const std::vector<bench::Configuration>& timed) {
  std::string md;
  const bench::Configuration* mj_best = bench::cheapestWithin(timed, "MuJoCo");
  const bench::Configuration* ours_best = bench::cheapestWithin(timed, "nmdp");
  if (mj_best && ours_best)
    appendf(md,
            "- **Speed at equal accuracy**: the cheapest configuration of each engine within 5 %% of its own finest run: "
            "nmdp %s at %s (%s per simulated second), MuJoCo%s at %s (%s); nmdp / MuJoCo = **%.2f×** wall time (%.2f× "
            "CPU time); target at most 0.5×: **%s**.\n",
            ours_best->family.c_str(), fmtDt(ours_best->dt).c_str(), fmtTime(ours_best->wall_per_s).c_str(),
            mj_best->family == kMujoco ? "" : (" (" + mj_best->family.substr(std::strlen(kMujoco) + 2) + ")").c_str(),
            fmtDt(mj_best->dt).c_str(), fmtTime(mj_best->wall_per_s).c_str(), ours_best->wall_per_s / mj_best->wall_per_s,
            ours_best->cpu_per_s / mj_best->cpu_per_s, ours_best->wall_per_s <= 0.5 * mj_best->wall_per_s ? "met" : "not met");
  else
    appendf(md, "- **Speed at equal accuracy**: undefined: %s within 5 %% of its own finest run.\n",
            !mj_best && !ours_best ? "neither engine has a timed run" : !mj_best ? "MuJoCo has no timed run" : "nmdp has no timed run");
  return md;
}

// Speed at equal accuracy: per family its cheapest run within 5 %, then per engine.
std::string conclusions(const std::vector<Row>& rows, const Summary& s, double duration) {
  std::string md;
  std::vector<std::string> families;  // in the table's order
  for (const Row& row : rows)
    if (std::find(families.begin(), families.end(), row.family) == families.end()) families.push_back(row.family);
  for (const std::string& family : families) {
    const Row* ref = s.finest.at(family);
    const bench::Configuration* best = nullptr;
    for (const bench::Configuration& c : s.timed)
      if (c.family == family && c.candidate && c.within && (!best || c.wall_per_s < best->wall_per_s)) best = &c;
    const Run& fr = ref->runs.front();
    if (best)
      appendf(md, "- %s: cheapest within 5 %% of its %s run: %s (%s wall, %s CPU per simulated second).\n", family.c_str(),
              fmtDt(ref->dt).c_str(), fmtDt(best->dt).c_str(), fmtTime(best->wall_per_s).c_str(), fmtTime(best->cpu_per_s).c_str());
    else if (!fr.stable)
      appendf(md, "- %s: its finest run (%s) is itself not stable (%s): nothing to be accurate to.\n", family.c_str(),
              fmtDt(ref->dt).c_str(), fr.why.c_str());
    else
      appendf(md, "- %s: no timed run within 5 %% of its %s run.\n", family.c_str(), fmtDt(ref->dt).c_str());
  }
  md += speedAtEqualAccuracy(s.timed);
  std::string fine;
  for (const Row& row : rows)
    if (&row == s.finest.at(row.family)) {
      const Run& r = row.runs.front();
      char b[200];
      if (r.stable)
        std::snprintf(b, sizeof b, "%s%s at %s %.3f m (|Δ(x, y)| %.3f m, yaw %+.2f rad)", fine.empty() ? "" : "; ",
                      row.family.c_str(), fmtDt(row.dt).c_str(), r.forward, accuracyOf(r).displacement, r.yaw);
      else std::snprintf(b, sizeof b, "%s%s at %s falls (%s)", fine.empty() ? "" : "; ", row.family.c_str(), fmtDt(row.dt).c_str(), r.why.c_str());
      fine += b;
    }
  appendf(md, "- Forward distance in %g s at the finest dt of each: %s.\n", duration, fine.c_str());
  return md;
}

// One scenario: every run, the table and the ratios, as markdown.
std::string scenario(const Args& a, const std::vector<std::string>& overrides, const std::string& title) {
  Scenario sc = setUp(a, overrides);
  std::vector<Row> rows = runRows(a, sc);
  const Summary summary = summarize(rows);
  return "### " + title + "\n\n" + introduction(a, sc) + table(rows, summary, sc, a.duration) +
         conclusions(rows, summary, a.duration);
}

}  // namespace

int run(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--repeats")) a.repeats = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--duration")) a.duration = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--out")) a.out_path = argv[i + 1];
    else if (!std::strcmp(argv[i], "--scene")) a.scene_path = argv[i + 1];
    else if (!std::strcmp(argv[i], "--mujoco-extra-dts")) a.mujoco_extra_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--ours-extra-dts")) a.ours_extra_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--set")) a.overrides.push_back(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--ours-config")) a.ours_configs.emplace_back(argv[i + 1], parseConfiguration(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--mujoco-dts")) a.mujoco_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--ours-dts")) a.ours_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--damped-kd")) a.damped_kd = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--mujoco-timeconst")) a.mujoco_timeconst = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--mujoco-elliptic")) a.mujoco_elliptic = std::atoi(argv[i + 1]) != 0;
    else {
      std::fprintf(stderr,
                   "usage: bench_mujoco [--repeats N] [--duration S] [--out FILE] [--scene SCENE.json] [--set key.path=value]...\n"
                   "                    [--ours-config \"integrator.key=value;...\"]... (another nmdp configuration to compare)\n"
                   "                    [--mujoco-dts S,..] [--ours-dts S,..] [--mujoco-extra-dts S,..] [--ours-extra-dts S,..]\n"
                   "                    [--damped-kd KD (0: skip the second scenario)]\n"
                   "                    diagnostics (not MuJoCo's defaults; flagged in the output): [--mujoco-timeconst T] [--mujoco-elliptic 0|1]\n");
      return 2;
    }
  }
  if (argc % 2 == 0) {
    std::fprintf(stderr, "bench_mujoco: option %s needs a value\n", argv[argc - 1]);
    return 2;
  }
  std::string md;
  {
    char when[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::string load = readFileOr("/proc/loadavg");
    load = load.substr(0, load.find(' ', load.find(' ', load.find(' ') + 1) + 1));
    std::string command;
    for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
    md += std::string("Run ") + when + ", `bench_mujoco" + command + "`, load average (1, 5, 15 min) at the start " +
          load + " on a machine with " + std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) +
          " cores: wall times include other work's interference; the CPU time of the stepping thread is the steadier "
          "figure.\n\n"
          "MuJoCo's model: A1's URDF through MuJoCo's own importer from memory, with the oracle test's edits "
          "(tests/support/mujoco_urdf.hpp: visuals removed, no inertia alterations, principal-axes inertias, static links "
          "fused), a floating joint (MuJoCo's free joint) on the root link, and a ground box whose top face is z = 0. "
          "Only the four foot spheres (r = 0.02 m, matched to our contact points by position and radius) collide, and "
          "only with the ground; friction μ on both, condim 3; joint limits off (ours has none); no armature or "
          "friction loss in either, and no joint damping but the implicit-kd configuration's. MuJoCo's defaults otherwise: Euler integrator, Newton solver, pyramidal cone, "
          "solref (0.02, 1), solimp (0.9, 0.95, 0.001). PD: MuJoCo gets τ = kp (q* − q) + kd (q̇* − q̇) in qfrc_applied "
          "before each mj_step, from the state and our gait's target at the step's start (explicit); \"MuJoCo, implicit "
          "kd\" gets kd as the joints' damping (dof_damping, which MuJoCo's Euler integrator integrates implicitly) and "
          "kp (q* − q) + kd q̇* in qfrc_applied, the usual set-up for stiff damped joints in MuJoCo. Ours evaluates "
          "the same gains as stable PD at the new state, with the target at the step's end.\n\n";
  }
  if (a.mujoco_timeconst > 0 || a.mujoco_elliptic)
    md += "**Diagnostic run: MuJoCo's contact is NOT at its defaults here** (--mujoco-timeconst / --mujoco-elliptic).\n\n";
  md += scenario(a, a.overrides, "The scene as it is (`controller.kd` default)");
  if (a.damped_kd > 0) {
    std::vector<std::string> damped = a.overrides;
    char kd[64];
    std::snprintf(kd, sizeof kd, "controller.kd=%g", a.damped_kd);
    damped.push_back(kd);
    md += "\n" + scenario(a, damped, std::string("The same with `--set ") + kd + "` (more joint damping)");
  }
  std::fputs(md.c_str(), stdout);
  std::ofstream out(a.out_path);
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", a.out_path.c_str());
    return 1;
  }
  out << md;
  return 0;
}

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mujoco: %s\n", e.what());
    return 1;
  }
}
