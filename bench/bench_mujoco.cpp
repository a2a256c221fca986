// Issue 7, the MuJoCo half: A1 trotting on flat ground, side by side with MuJoCo, on the same robot,
// the same PD targets and gains, the same initial state and the same friction coefficient.
//
// Ours: the scene models/scenes/a1_trot_flat.json built exactly as `nmdp simulate` builds it (robot,
// contact points, Coulomb model, terrain, gains, trot gait, initial state, integrator options), run
// with ne-pgm and pbd-pgm at several dt. MuJoCo (2.2.x, the Debian package): A1's URDF handed to
// MuJoCo's own importer from memory with the oracle test's edits (tests/mujoco_urdf.hpp), plus a
// floating joint on the root link (MuJoCo's free joint) and a ground box with its top face at z = 0,
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
// implicitly, and only kp (q* − q) + kd q̇* + τ_ff in qfrc_applied. The speed goal is judged against
// the faster of the two configurations' largest dt within 5 % of their own 1 ms run.
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
//                     [--mujoco-dts S,..] [--ours-dts S,..] [--mujoco-extra-dts S,..] [--ours-extra-dts S,..]
//                     [--damped-kd KD] [--mujoco-timeconst T] [--mujoco-elliptic 0|1]
// (the extra dts are convergence checks, run once, never the reference; the last two are diagnostics
// that leave MuJoCo's contact defaults, flagged in the output).
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "bench_clock.hpp"
#include "../tests/mujoco_urdf.hpp"
#include "contact_models/coulomb_model.hpp"
#include "io/json_params.hpp"
#include "io/scene.hpp"
#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "multibody/urdf_loader.hpp"
#include "solver/integrator.hpp"
#include "terrain/terrain_factory.hpp"

using namespace nmdp;

namespace {

using bench::threadCpuSeconds;
using bench::wallSeconds;

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Stability bounds: torso (trunk origin) height within [0.5, 1.5] × its initial (standing) height,
// |roll|, |pitch| < 1 rad, everything finite; for ours also every step converged, for MuJoCo no
// bad-qacc warning (MuJoCo resets the state when the acceleration is not finite).
struct Bounds {
  double z_low = 0, z_high = 0;
  double tilt = 1.0;
};

struct Run {
  bool stable = true;
  std::string why;       // why it stopped, if it did
  double t_end = 0;      // simulated time reached
  double wall = 0, cpu = 0;  // whole run, s
  double forward = 0;    // torso x travelled
  double lateral = 0;    // torso y at the end
  double z_min = 1e9, z_max = -1e9, tilt_max = 0;
  long substeps = 0, outer = 0, steps = 0;  // ours: accepted sub-steps and outer iterations, steps taken
  std::vector<Vec3> position;  // torso position at k dt, k = 0..steps done
};

// Updates the per-step record and the stability check; false once unstable.
bool observe(Run& r, const Bounds& b, double t, const Vec3& p, const Vec3& rpy, const Vec3& p0) {
  r.t_end = t;
  r.position.push_back(p);
  if (!p.allFinite() || !rpy.allFinite()) {
    r.stable = false, r.why = "NaN";
    return false;
  }
  r.z_min = std::min(r.z_min, p.z());
  r.z_max = std::max(r.z_max, p.z());
  r.tilt_max = std::max({r.tilt_max, std::abs(rpy.x()), std::abs(rpy.y())});
  r.forward = p.x() - p0.x();
  r.lateral = p.y() - p0.y();
  char buf[96];
  if (p.z() < b.z_low || p.z() > b.z_high) {
    std::snprintf(buf, sizeof buf, "torso height %.3f m at t = %.3f s", p.z(), t);
    r.stable = false, r.why = buf;
    return false;
  }
  if (std::abs(rpy.x()) >= b.tilt || std::abs(rpy.y()) >= b.tilt) {
    std::snprintf(buf, sizeof buf, "tilt %.2f rad at t = %.3f s", std::max(std::abs(rpy.x()), std::abs(rpy.y())), t);
    r.stable = false, r.why = buf;
    return false;
  }
  return true;
}

// ---- ours -----------------------------------------------------------------------------------------

struct Ours {
  SceneConfig config;
  Model model;
  std::unique_ptr<ContactModel> contact_model;
  std::unique_ptr<Terrain> terrain;
  System system;
  std::unique_ptr<PdTargetSource> target;
  Eigen::VectorXd q0, qd0;
};

Run runOurs(const Ours& o, Method method, double dt, double duration, const Bounds& bounds) {
  IntegratorOptions options = o.config.integrator;
  options.method = method;
  StepWorkspace ws(o.system, options);
  SimulationState state = initialState(o.system, options, o.q0, o.qd0, dt);
  Data pose_data(o.model);
  Vec3 p, rpy;
  auto pose = [&] {
    pose_data.base_chart = state.base_chart;
    forwardKinematics(o.model, pose_data, state.q);
    basePose(o.model, pose_data, p, rpy);
  };
  Run r;
  const long steps = std::lround(duration / dt);
  r.position.reserve(steps + 1);
  pose();
  const Vec3 p0 = p;
  observe(r, bounds, 0.0, p, rpy, p0);
  double wall = 0, cpu = 0;
  for (long i = 1; i <= steps; ++i) {
    const double w0 = wallSeconds(), c0 = threadCpuSeconds();
    const StepStats s = advance(o.system, options, *o.target, state, dt, ws);
    cpu += threadCpuSeconds() - c0;
    wall += wallSeconds() - w0;
    r.substeps += s.substeps, r.outer += s.outer_iterations, ++r.steps;
    if (!s.converged) {
      r.stable = false;
      r.why = std::string("step failed (") + toString(s.status) + ") at t = " + std::to_string(i * dt);
      r.t_end = (i - 1) * dt;
      break;
    }
    pose();  // outside the timing: the simulation does not need it
    if (!observe(r, bounds, i * dt, p, rpy, p0)) break;
  }
  r.wall = wall, r.cpu = cpu;
  return r;
}

// ---- MuJoCo ---------------------------------------------------------------------------------------

struct Mujoco {
  test::MjModelPtr m;
  std::vector<int> coordinate;  // ours: actuated coordinate i
  std::vector<int> qposadr, dofadr;  // MuJoCo's addresses of that joint
  int free_qpos = 0, free_dof = 0, trunk = -1;  // trunk: the free body (A1: base + trunk fused)
  int feet = 0;
  double mu = 0;
};

std::string readFile(const std::string& path) { return test::readText(path); }

std::string readFileOr(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  std::getline(in, text);
  return text;
}

std::string mujocoVersion() {
  const int v = mj_version();  // e.g. 222 for 2.2.2
  return std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
}

// Our q0 in MuJoCo's coordinates (the base from the root-link pose our kinematics gives: the chart
// is the identity at t = 0), q̇0 = 0 (the scene's: asserted), and mj_forward.
void setInitialState(const Ours& o, const Mujoco& mj, mjData* d) {
  const mjModel* m = mj.m.get();
  if (o.qd0.cwiseAbs().maxCoeff() != 0) throw std::runtime_error("non-zero initial velocity is not mapped to MuJoCo");
  Data pose_data(o.model);
  forwardKinematics(o.model, pose_data, o.q0);
  Vec3 p0, rpy0;
  basePose(o.model, pose_data, p0, rpy0);
  const Eigen::Quaterniond q0(test::rpyMatrix(rpy0));
  mj_resetData(m, d);
  for (int k = 0; k < 3; ++k) d->qpos[mj.free_qpos + k] = p0[k];
  d->qpos[mj.free_qpos + 3] = q0.w(), d->qpos[mj.free_qpos + 4] = q0.x(), d->qpos[mj.free_qpos + 5] = q0.y();
  d->qpos[mj.free_qpos + 6] = q0.z();
  for (size_t k = 0; k < mj.coordinate.size(); ++k) d->qpos[mj.qposadr[k]] = o.q0[mj.coordinate[k]];
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
}

Mujoco buildMujoco(const Ours& o, double mu) {
  // The URDF MuJoCo is given: the oracle test's edits (visuals removed, MuJoCo's inertia
  // alterations off, principal-axes inertias; static links fused into their parents), plus a root
  // link "mj_world" holding the robot's root link by a floating joint (MuJoCo's free joint) and the
  // ground: a 200 m × 200 m × 1 m box whose top face is z = 0 (a URDF cannot hold a plane; for a
  // sphere on its top face the contact is a plane's). mj_world and the ground are static and fused
  // into MuJoCo's world body. Everything stays in memory: no lossy MJCF round trip (mj_saveLastXML
  // writes 6 significant digits).
  std::string root;  // the URDF's root link (A1: base, welded to trunk)
  for (const Link& l : o.model.links)
    if (l.parent_link < 0) root = l.name;
  std::string urdf = test::urdfForMujoco(readFile(o.config.urdf), /*fusestatic=*/true);
  const size_t close = urdf.rfind("</robot>");
  if (close == std::string::npos) throw std::runtime_error("no </robot> in " + o.config.urdf);
  urdf.insert(close,
              "  <link name=\"mj_world\"/>\n"
              "  <joint name=\"mj_free\" type=\"floating\"><parent link=\"mj_world\"/><child link=\"" + root +
                  "\"/></joint>\n"
              "  <link name=\"mj_ground\"><collision><origin xyz=\"0 0 -0.5\" rpy=\"0 0 0\"/><geometry>"
              "<box size=\"200 200 1\"/></geometry></collision></link>\n"
              "  <joint name=\"mj_ground_fixed\" type=\"fixed\"><parent link=\"mj_world\"/><child link=\"mj_ground\"/>"
              "<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/></joint>\n");
  std::string error;
  test::MjModelPtr m = test::loadMujocoFromMemory(urdf, "a1_floating.urdf", error);
  if (!m) throw std::runtime_error(error);
  if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());

  Mujoco mj;
  mj.mu = mu;
  for (int k = 0; k < 3; ++k) m->opt.gravity[k] = o.model.gravity[k];
  for (int i = 0; i < m->nv; ++i)
    if (m->dof_armature[i] != 0 || m->dof_damping[i] != 0 || m->dof_frictionloss[i] != 0)
      throw std::runtime_error("MuJoCo model has armature/damping/friction loss on dof " + std::to_string(i));
  for (int j = 0; j < m->njnt; ++j) m->jnt_limited[j] = 0;  // ours enforces no joint limits
  int free_joint = -1;
  for (int j = 0; j < m->njnt; ++j)
    if (m->jnt_type[j] == mjJNT_FREE) free_joint = j;
  if (free_joint < 0) throw std::runtime_error("MuJoCo made no free joint of the floating joint");
  if (m->body_parentid[m->jnt_bodyid[free_joint]] != 0) throw std::runtime_error("the free joint's body is not top-level");
  mj.trunk = m->jnt_bodyid[free_joint];
  mj.free_qpos = m->jnt_qposadr[free_joint];
  mj.free_dof = m->jnt_dofadr[free_joint];
  if (std::abs(m->body_subtreemass[mj.trunk] - o.model.total_mass) > 1e-9 * o.model.total_mass)
    throw std::runtime_error("MuJoCo's robot mass " + std::to_string(m->body_subtreemass[mj.trunk]) + " differs from ours");
  // Actuated joints by name.
  for (int i = 0; i < o.model.nq; ++i) {
    if (o.model.bodies[i].is_base) continue;
    const int j = mj_name2id(m.get(), mjOBJ_JOINT, o.model.dof_names[i].c_str());
    if (j < 0) throw std::runtime_error("MuJoCo has no joint " + o.model.dof_names[i]);
    mj.coordinate.push_back(i);
    mj.qposadr.push_back(m->jnt_qposadr[j]);
    mj.dofadr.push_back(m->jnt_dofadr[j]);
  }
  if (m->nv != o.model.nq) throw std::runtime_error("MuJoCo and nmdp disagree on the number of degrees of freedom");

  // Contacts: the foot spheres (matched to our contact points by their world centres at the
  // initial pose, and by radius) against the ground only.
  mj.m = std::move(m);
  m.reset();
  mjModel* mm = mj.m.get();
  test::MjDataPtr d(mj_makeData(mm));
  setInitialState(o, mj, d.get());
  Data data(o.model);
  forwardKinematics(o.model, data, o.q0);
  int ground = -1;
  for (int g = 0; g < mm->ngeom; ++g) {
    mm->geom_contype[g] = 0;
    mm->geom_conaffinity[g] = 0;
    if (mm->geom_bodyid[g] == 0 && mm->geom_type[g] == mjGEOM_BOX) ground = g;
  }
  if (ground < 0) throw std::runtime_error("no ground box in MuJoCo's world body");
  mm->geom_conaffinity[ground] = 1;
  mm->geom_friction[3 * ground] = mu;
  mm->geom_condim[ground] = 3;
  for (const ContactPoint& c : o.system.contacts) {
    const Vec3 centre = linkPoint(o.model, data, c.link, c.offset);
    int found = -1;
    for (int g = 0; g < mm->ngeom; ++g)
      if (mm->geom_type[g] == mjGEOM_SPHERE && std::abs(mm->geom_size[3 * g] - c.radius) < 1e-12 &&
          (Eigen::Map<const Eigen::Vector3d>(d->geom_xpos + 3 * g) - centre).norm() < 1e-9)
        found = g;
    if (found < 0) throw std::runtime_error("no MuJoCo foot sphere matches our contact point " + c.name);
    mm->geom_contype[found] = 1;
    mm->geom_friction[3 * found] = mu;
    mm->geom_condim[found] = 3;
    ++mj.feet;
  }
  // The defaults the report states.
  if (mm->opt.integrator != mjINT_EULER || mm->opt.solver != mjSOL_NEWTON || mm->opt.cone != mjCONE_PYRAMIDAL)
    throw std::runtime_error("MuJoCo's options are not the defaults this benchmark reports");
  for (int g = 0; g < mm->ngeom; ++g)
    if (mm->geom_contype[g] || mm->geom_conaffinity[g])
      if (mm->geom_solref[mjNREF * g] != 0.02 || mm->geom_solref[mjNREF * g + 1] != 1 || mm->geom_solimp[mjNIMP * g] != 0.9 ||
          mm->geom_solimp[mjNIMP * g + 1] != 0.95 || mm->geom_solimp[mjNIMP * g + 2] != 0.001)
        throw std::runtime_error("MuJoCo's contact solref/solimp are not the defaults this benchmark reports");
  return mj;
}

Vec3 rpyOfQuaternion(const double* quat) {
  const Eigen::Quaterniond q(quat[0], quat[1], quat[2], quat[3]);
  return test::rpyOf(q.normalized().toRotationMatrix());
}

constexpr const char* kMujoco = "MuJoCo";
constexpr const char* kMujocoImplicitKd = "MuJoCo, implicit kd";
bool isMujoco(const std::string& engine) { return engine == kMujoco || engine == kMujocoImplicitKd; }

// implicit_kd: −kd q̇ as dof_damping (integrated implicitly by MuJoCo's Euler integrator), the rest
// of the PD torque explicit; otherwise the whole PD torque explicit.
Run runMujoco(const Ours& o, Mujoco& mj, double dt, double duration, const Bounds& bounds, bool implicit_kd) {
  mjModel* m = mj.m.get();
  m->opt.timestep = dt;
  for (size_t k = 0; k < mj.coordinate.size(); ++k) m->dof_damping[mj.dofadr[k]] = implicit_kd ? o.system.gains.kd[mj.coordinate[k]] : 0.0;
  test::MjDataPtr d(mj_makeData(m));
  setInitialState(o, mj, d.get());
  Vec3 p0 = Eigen::Map<const Vec3>(d->qpos + mj.free_qpos);

  PdTarget target;
  target.position = Eigen::VectorXd::Zero(o.model.nq);
  target.velocity = Eigen::VectorXd::Zero(o.model.nq);
  const PdGains& g = o.system.gains;
  Run r;
  const long steps = std::lround(duration / dt);
  r.position.reserve(steps + 1);
  auto pose = [&](Vec3& p, Vec3& rpy) {
    for (int k = 0; k < 3; ++k) p[k] = d->qpos[mj.free_qpos + k];
    rpy = rpyOfQuaternion(d->qpos + mj.free_qpos + 3);
  };
  Vec3 p, rpy;
  pose(p, rpy);
  observe(r, bounds, 0.0, p, rpy, p0);
  const double w0 = wallSeconds(), c0 = threadCpuSeconds();
  double pose_wall = 0, pose_cpu = 0;
  for (long i = 1; i <= steps; ++i) {
    o.target->evaluate((i - 1) * dt, target);  // explicit: the target and the state at the step's start
    for (size_t k = 0; k < mj.coordinate.size(); ++k) {
      const int c = mj.coordinate[k];
      d->qfrc_applied[mj.dofadr[k]] = g.kp[c] * (target.position[c] - d->qpos[mj.qposadr[k]]) +
                                      g.kd[c] * (target.velocity[c] - (implicit_kd ? 0.0 : d->qvel[mj.dofadr[k]])) +
                                      g.tau_ff[c];
    }
    mj_step(m, d.get());
    const double w1 = wallSeconds(), c1 = threadCpuSeconds();
    pose(p, rpy);
    bool ok = observe(r, bounds, i * dt, p, rpy, p0);
    if (ok && d->warning[mjWARN_BADQACC].number > 0) {
      r.stable = false, r.why = "bad qacc (MuJoCo reset) at t = " + std::to_string(i * dt);
      ok = false;
    }
    pose_wall += wallSeconds() - w1, pose_cpu += threadCpuSeconds() - c1;
    if (!ok) break;
  }
  r.wall = wallSeconds() - w0 - pose_wall;
  r.cpu = threadCpuSeconds() - c0 - pose_cpu;
  return r;
}

// ---- comparison -----------------------------------------------------------------------------------

struct Row {
  std::string engine;  // kMujoco, kMujocoImplicitKd, "ne-pgm", "pbd-pgm"
  double dt = 0;
  std::vector<Run> runs;  // repeats
  // filled in later
  double wall_per_s = NAN, cpu_per_s = NAN;
  double rms = NAN;  // m
  bool has_rms = false;
  bool extra = false;  // a convergence check: one run, never the reference
};

std::vector<double> parseList(const std::string& text) {  // "0.001,0.002"
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stod(item));
  return out;
}

Row makeRow(const std::string& engine, double dt, bool extra = false) {
  Row row;
  row.extra = extra;
  row.engine = engine;
  row.dt = dt;
  return row;
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
  // Convergence checks: run once each, shown, never the reference.
  std::vector<double> mujoco_extra_dts = {0.0005}, ours_extra_dts = {0.001};
  std::string out_path = std::string(NMDP_SOURCE_DIR) + "/docs/results/mujoco_a1.md";
  std::string scene_path = std::string(NMDP_SOURCE_DIR) + "/models/scenes/a1_trot_flat.json";
  std::vector<std::string> overrides;  // --set key.path=value, as for nmdp simulate
  std::vector<double> mujoco_dts = {0.001, 0.002, 0.005, 0.01, 0.02, 0.05};
  std::vector<double> ours_dts = {0.005, 0.01, 0.02, 0.03, 0.04, 0.05};
  double damped_kd = 0.0;  // the second scenario's controller.kd (0: no second scenario)
  double mujoco_timeconst = 0;  // > 0: MuJoCo contact solref time constant (diagnostics; default 0.02)
  bool mujoco_elliptic = false;  // diagnostics: elliptic friction cone
};

// The smallest entry of a gain vector over the actuated coordinates (base coordinates hold zeros).
double actuatedMin(const Model& model, const Eigen::VectorXd& gain) {
  double out = INFINITY;
  for (int i = 0; i < model.nq; ++i)
    if (!model.bodies[i].is_base) out = std::min(out, gain[i]);
  return out;
}

// One scenario: every run, the table and the ratios, as markdown.
std::string scenario(const Args& a, const std::vector<std::string>& overrides, const std::string& title) {
  const std::string& scene_path = a.scene_path;
  const int repeats = a.repeats;
  const double duration = a.duration;
  const std::vector<double>&mujoco_dts = a.mujoco_dts, &ours_dts = a.ours_dts, &mujoco_extra_dts = a.mujoco_extra_dts,
                            &ours_extra_dts = a.ours_extra_dts;
  // Ours, built as `nmdp simulate` builds the scene.
  Ours o;
  nlohmann::json scene_json = loadSceneJson(scene_path);
  for (const std::string& assignment : overrides) applyOverride(scene_json, assignment, scene_path + ": --set");
  o.config = parseScene(scene_json, scene_path);
  o.model = loadUrdf(o.config.urdf, urdfOptionsFor(o.config));
  validateAgainstModel(o.config, o.model);
  if (o.config.contact_model.value("type", "") != "coulomb") throw std::runtime_error("the scene's contact model must be coulomb");
  o.contact_model = makeCoulombModel(o.config.contact_model, ConfigContext{scene_path + ": contacts.model", o.config.base_dir});
  const double mu = dynamic_cast<const CoulombModel&>(*o.contact_model).parameters().mu;
  o.terrain = makeTerrain(o.config.terrain, ConfigContext{scene_path + ": terrain", o.config.base_dir});
  o.system.model = &o.model;
  o.system.contacts = contactPointsFor(o.config, o.model);
  o.system.contact_model = o.contact_model.get();
  o.system.terrain = o.terrain.get();
  o.system.gains = gainsFor(o.config, o.model);
  o.target = gaitFor(o.config, o.model);
  o.q0 = initialConfiguration(o.config, o.model);
  o.qd0 = initialVelocity(o.config, o.model);
  validateSystem(o.system, o.config.integrator);

  Mujoco mj = buildMujoco(o, mu);
  // Diagnostics only (the tables are with MuJoCo's defaults): stiffer contacts, elliptic cone.
  if (a.mujoco_timeconst > 0)
    for (int g = 0; g < mj.m->ngeom; ++g) mj.m->geom_solref[mjNREF * g] = a.mujoco_timeconst;
  if (a.mujoco_elliptic) mj.m->opt.cone = mjCONE_ELLIPTIC;

  Bounds bounds;
  {
    Data pose_data(o.model);
    forwardKinematics(o.model, pose_data, o.q0);
    Vec3 p, rpy;
    basePose(o.model, pose_data, p, rpy);
    bounds.z_low = 0.5 * p.z();
    bounds.z_high = 1.5 * p.z();
  }

  std::vector<Row> rows;
  for (const char* engine : {kMujoco, kMujocoImplicitKd}) {
    for (double dt : mujoco_extra_dts) rows.push_back(makeRow(engine, dt, true));
    for (double dt : mujoco_dts) rows.push_back(makeRow(engine, dt));
  }
  for (const char* method : {"ne-pgm", "pbd-pgm"}) {
    for (double dt : ours_extra_dts) rows.push_back(makeRow(method, dt, true));
    for (double dt : ours_dts) rows.push_back(makeRow(method, dt));
  }
  auto methodOf = [](const std::string& name) { return name == "ne-pgm" ? Method::NePgm : Method::PbdPgm; };

  // Interleaved repeats; a reference run finer than the benchmarked grid is run once.
  for (int rep = 0; rep < repeats; ++rep)
    for (Row& row : rows) {
      if (row.extra && rep > 0) continue;
      std::fprintf(stderr, "repeat %d: %s dt = %g ...", rep + 1, row.engine.c_str(), row.dt);
      row.runs.push_back(isMujoco(row.engine)
                             ? runMujoco(o, mj, row.dt, duration, bounds, row.engine == kMujocoImplicitKd)
                             : runOurs(o, methodOf(row.engine), row.dt, duration, bounds));
      const Run& r = row.runs.back();
      std::fprintf(stderr, " %.3f s wall, forward %.3f m%s%s\n", r.wall, r.forward, r.stable ? "" : ", unstable: ",
                   r.why.c_str());
    }

  // Per row: medians; deviation from the finest run of the same engine/method (its first repeat:
  // every repeat is bit-identical).
  std::map<std::string, const Row*> finest;
  for (const Row& row : rows)
    if (!row.extra && (!finest.count(row.engine) || row.dt < finest[row.engine]->dt)) finest[row.engine] = &row;
  for (Row& row : rows) {
    std::vector<double> wall, cpu;
    for (const Run& r : row.runs)
      if (r.t_end > 0) wall.push_back(r.wall / r.t_end), cpu.push_back(r.cpu / r.t_end);
    row.wall_per_s = median(wall);
    row.cpu_per_s = median(cpu);
    const Row& ref = *finest[row.engine];
    row.has_rms = rmsDeviation(row.runs.front(), row.dt, ref.runs.front(), ref.dt, row.rms);
  }

  // Which MuJoCo runs stay within 5 % of the same configuration's 1 ms run.
  auto within5 = [&](const Row& row, const Row& ref) {
    const Run& r = row.runs.front();
    const double f = ref.runs.front().forward;
    return r.stable && ref.runs.front().stable && std::abs(r.forward - f) <= 0.05 * std::abs(f) && row.has_rms &&
           row.rms <= 0.05 * std::abs(f);
  };

  double target_cost = 0;  // s per evaluation of our gait target
  {
    PdTarget t;
    t.position = Eigen::VectorXd::Zero(o.model.nq);
    t.velocity = Eigen::VectorXd::Zero(o.model.nq);
    const int n = 20000;
    const double c0 = threadCpuSeconds();
    for (int i = 0; i < n; ++i) o.target->evaluate(1e-3 * i, t);
    target_cost = (threadCpuSeconds() - c0) / n;
  }
  std::string md = "### " + title + "\n\n";
  char line[1024];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    md += line;
  };
  add("A1 (%d DOF, %.2f kg) trotting on flat ground for %g s (`models/scenes/a1_trot_flat.json`: floating base, "
      "Coulomb μ = %g, the built-in trot, gains kp %.4g–%.4g, kd %.4g–%.4g over the joints), ours vs MuJoCo %s (Euler, Newton solver, pyramidal cone; PD explicit via qfrc_applied, "
      "or, as \"MuJoCo, implicit kd\", its kd part as implicit joint damping) on the same "
      "robot, PD targets, gains and initial standing pose; one core, %d interleaved repeats (medians), "
      "`bench/bench_mujoco.cpp`.\n\n",
      o.model.nq, o.model.total_mass, duration, mu, actuatedMin(o.model, o.system.gains.kp), o.system.gains.kp.maxCoeff(),
      actuatedMin(o.model, o.system.gains.kd), o.system.gains.kd.maxCoeff(),
      mujocoVersion().c_str(), repeats);
  add("| engine / method | dt | wall / simulated s | CPU / simulated s | real-time factor | stable? | forward in %g s | "
      "RMS deviation from own finest run | same, / distance walked | torso height | sub-steps, outer it. / step |\n",
      duration);
  add("|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n");
  for (const Row& row : rows) {
    const Run& r = row.runs.front();
    const Row& ref = *finest[row.engine];
    const bool is_ref = &ref == &row;
    std::string stable = r.stable ? "yes" : "no: " + r.why;
    char rb[64] = "—", rel[64] = "—";
    if (is_ref) std::snprintf(rb, sizeof rb, "(reference)"), std::snprintf(rel, sizeof rel, "—");
    else if (row.has_rms) {
      std::snprintf(rb, sizeof rb, "%.4f m%s", row.rms, r.stable ? "" : " (until it stopped)");
      if (ref.runs.front().stable)
        std::snprintf(rel, sizeof rel, "%.1f %%", 100 * row.rms / std::max(1e-9, std::abs(ref.runs.front().forward)));
      else
        std::snprintf(rel, sizeof rel, "— (reference fell)");
    }
    char fwd[64];
    if (r.stable) std::snprintf(fwd, sizeof fwd, "%.3f m", r.forward);
    else std::snprintf(fwd, sizeof fwd, "(%.3f m by t = %.2f s)", r.forward, r.t_end);
    char it[64] = "—";
    if (!isMujoco(row.engine) && r.steps > 0)
      std::snprintf(it, sizeof it, "%.2f, %.1f", double(r.substeps) / r.steps, double(r.outer) / r.steps);
    char z[64];
    std::snprintf(z, sizeof z, "%.3f–%.3f m", r.z_min, r.z_max);
    add("| %s%s | %s | %s | %s | %.1f× | %s | %s | %s | %s | %s | %s |\n", row.engine.c_str(), row.extra ? " (check, 1 run)" : "",
        fmtDt(row.dt).c_str(), fmtTime(row.wall_per_s).c_str(), fmtTime(row.cpu_per_s).c_str(), 1.0 / row.wall_per_s,
        stable.c_str(), fwd, rb, rel, z, it);
  }
  add("\nStable: no NaN, torso height within [%.3f, %.3f] m (0.5–1.5× the initial %.3f m), |roll|, |pitch| < 1 rad, "
      "every step of ours converged, no MuJoCo bad-qacc reset; an unstable run stops there (its time per simulated "
      "second is over the time it ran). Deviation: RMS over the run's own time grid of the 3-D torso-position "
      "difference from the same engine's finest run, in metres and relative to that finest run's forward distance. "
      "Real-time factor: simulated / wall time. MuJoCo's times include evaluating our gait target and the PD torque "
      "every step (the target alone: %.2f µs per evaluation, measured here), as ours include its target per sub-step.\n\n",
      bounds.z_low, bounds.z_high, bounds.z_low * 2, 1e6 * target_cost);

  const Row* ne50 = nullptr;
  for (const Row& row : rows)
    if (row.engine == "ne-pgm" && std::abs(row.dt - 0.05) < 1e-12) ne50 = &row;
  add("Within 5 %%: the run and the same engine's finest run are stable, the run's forward distance is within 5 %% of "
      "the finest run's, and its RMS torso deviation is below 5 %% of the finest run's forward distance.\n\n");
  // Per MuJoCo configuration: its largest dt within 5 % of its own 1 ms run, and ne-pgm at 50 ms
  // against it. The goal is met only against both (the faster of the two is the one to beat).
  int compared = 0, beaten = 0;
  for (const char* engine : {kMujoco, kMujocoImplicitKd}) {
    if (!finest.count(engine)) continue;
    const Row& mj_ref = *finest[engine];
    const Row* mj_best = nullptr;
    for (const Row& row : rows)
      if (row.engine == engine && within5(row, mj_ref) && (!mj_best || row.dt > mj_best->dt)) mj_best = &row;
    if (mj_best && ne50) {
      const double ratio_wall = ne50->wall_per_s / mj_best->wall_per_s, ratio_cpu = ne50->cpu_per_s / mj_best->cpu_per_s;
      ++compared;
      if (ratio_wall < 1) ++beaten;
      add("- %s: largest dt within 5 %% of its %s run **%s** (%s wall per simulated second, forward %.3f m vs %.3f m); "
          "ne-pgm @ 50 ms / %s @ %s: **%.2f×** wall time (%.2f× CPU time).\n",
          engine, fmtDt(mj_ref.dt).c_str(), fmtDt(mj_best->dt).c_str(), fmtTime(mj_best->wall_per_s).c_str(),
          mj_best->runs.front().forward, mj_ref.runs.front().forward, engine, fmtDt(mj_best->dt).c_str(), ratio_wall,
          ratio_cpu);
    } else if (!mj_ref.runs.front().stable) {
      add("- %s: its finest run (%s) is itself not stable (%s): no run of it is a trot to compare with.\n", engine,
          fmtDt(mj_ref.dt).c_str(), mj_ref.runs.front().why.c_str());
    } else {
      add("- %s: no run within 5 %% of its finest run, or ne-pgm at 50 ms was not run.\n", engine);
    }
  }
  if (ne50) {
    add("- ne-pgm at 50 ms: %s wall per simulated second (%s; forward %.3f m).\n", fmtTime(ne50->wall_per_s).c_str(),
        ne50->runs.front().stable ? "stable" : "UNSTABLE", ne50->runs.front().forward);
    if (compared == 0)
      add("- Speed goal: undefined (no MuJoCo configuration has a stable 1 ms run with a coarser run within 5 %% of it).\n");
    else
      add("- Speed goal: %s (ne-pgm at 50 ms faster than %d of the %d MuJoCo configurations' largest dt within 5 %%).\n",
          beaten == compared ? "**met**" : "**NOT met**", beaten, compared);
    const Row* ne_ref = finest["ne-pgm"];
    const bool ne_ok = within5(*ne50, *ne_ref);
    add("- ne-pgm at 50 ms against its own finest run (%s): %s (forward %.3f m vs %.3f m, RMS %.4f m).\n",
        fmtDt(ne_ref->dt).c_str(), ne_ok ? "within 5 %" : "NOT within 5 %", ne50->runs.front().forward,
        ne_ref->runs.front().forward, ne50->rms);
  }
  if (ne50) {
    std::string raw;
    for (const Row& row : rows)
      if (isMujoco(row.engine) && !row.extra) {
        char b[200];
        std::snprintf(b, sizeof b, "%s%s %s: %.2f× wall, %.2f× CPU", raw.empty() ? "" : "; ", row.engine.c_str(), fmtDt(row.dt).c_str(),
                      ne50->wall_per_s / row.wall_per_s, ne50->cpu_per_s / row.cpu_per_s);
        raw += b;
        if (!row.runs.front().stable) raw += " (MuJoCo unstable)";
      }
    add("- Speed alone, accuracy aside: ne-pgm at 50 ms (%s, %s wall / %s CPU per simulated second) over MuJoCo at "
        "each dt: %s.\n",
        ne50->runs.front().stable ? "stable" : "unstable", fmtTime(ne50->wall_per_s).c_str(),
        fmtTime(ne50->cpu_per_s).c_str(), raw.c_str());
  }
  {
    std::string fine;
    for (const Row& row : rows)
      if (row.extra || &row == finest[row.engine]) {
        const Run& r = row.runs.front();
        char b[200];
        if (r.stable) std::snprintf(b, sizeof b, "%s%s at %s %.3f m", fine.empty() ? "" : "; ", row.engine.c_str(), fmtDt(row.dt).c_str(), r.forward);
        else std::snprintf(b, sizeof b, "%s%s at %s falls (%s)", fine.empty() ? "" : "; ", row.engine.c_str(), fmtDt(row.dt).c_str(), r.why.c_str());
        fine += b;
      }
    add("- Forward distance in %g s at the finest dt of each: %s.\n", duration, fine.c_str());
  }

  return md;
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
    else if (!std::strcmp(argv[i], "--mujoco-dts")) a.mujoco_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--ours-dts")) a.ours_dts = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--damped-kd")) a.damped_kd = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--mujoco-timeconst")) a.mujoco_timeconst = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--mujoco-elliptic")) a.mujoco_elliptic = std::atoi(argv[i + 1]) != 0;
    else {
      std::fprintf(stderr,
                   "usage: bench_mujoco [--repeats N] [--duration S] [--out FILE] [--scene SCENE.json] [--set key.path=value]...\n"
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
          "(tests/mujoco_urdf.hpp: visuals removed, no inertia alterations, principal-axes inertias, static links "
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
