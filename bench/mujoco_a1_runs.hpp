// bench_mujoco's runs: A1's trot in ours (the scene built by buildSimulation, as `nmdp simulate` builds it) and in
// MuJoCo (A1's URDF through MuJoCo's importer, the same targets, gains and initial state), each
// recorded as the torso's path with a stability check. bench/bench_mujoco.cpp describes the set-up
// and compares the runs.
#pragma once
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_clock.hpp"
#include "tests/support/mujoco_urdf.hpp"
#include "contact_models/coulomb_model.hpp"
#include "multibody/data.hpp"
#include "multibody/kinematics.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"

namespace nmdp::bench {

inline double median(std::vector<double> v) {
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
  double yaw = 0;        // heading at the end from the start, unwrapped
  double yaw_raw = 0;    // the last step's yaw in (−π, π], to unwrap the next
  double z_min = 1e9, z_max = -1e9, tilt_max = 0;
  long substeps = 0, outer = 0, steps = 0;  // ours: accepted sub-steps and outer iterations, steps taken
  std::vector<Vec3> position;  // torso position at k dt, k = 0..steps done
};

// Updates the per-step record and the stability check; false once unstable.
inline bool observe(Run& r, const Bounds& b, double t, const Vec3& p, const Vec3& rpy, const Vec3& p0) {
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
  if (r.position.size() > 1) r.yaw += std::remainder(rpy.z() - r.yaw_raw, 2 * M_PI);
  r.yaw_raw = rpy.z();
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

// The scene with the --set overrides, and its simulation at the scene's dt: the robot, contact points,
// gains, targets and initial state MuJoCo is given.
struct Ours {
  std::string scene_path;
  nlohmann::json scene_json;
  Simulation sim;
};

// The contact models this benchmark runs: Coulomb only (MuJoCo has no granular model; no libtorch).
inline ContactModelRegistry coulombOnly() {
  ContactModelRegistry models;
  models.add("coulomb", kCoulombParameters, makeCoulombModel);
  return models;
}

// Ours, built by buildSimulation as `nmdp simulate` builds the scene, with integrator.dt = dt.
inline Simulation simulationAt(const Ours& o, double dt) {
  nlohmann::json scene = o.scene_json;
  char assignment[64];
  std::snprintf(assignment, sizeof assignment, "integrator.dt=%.17g", dt);
  applyOverride(scene, assignment, o.scene_path + ": --set");
  return buildSimulation(parseScene(scene, o.scene_path), coulombOnly());
}

// One run at dt with the configuration's own integrator settings (the scene's, with its --ours-config).
inline Run runOurs(const Ours& o, double dt, double duration, const Bounds& bounds) {
  Simulation sim = simulationAt(o, dt);
  Vec3 p, rpy;
  Run r;
  const long steps = std::lround(duration / dt);
  r.position.reserve(steps + 1);
  sim.basePose(p, rpy);
  const Vec3 p0 = p;
  observe(r, bounds, 0.0, p, rpy, p0);
  double wall = 0, cpu = 0;
  for (long i = 1; i <= steps; ++i) {
    const double w0 = wallSeconds(), c0 = threadCpuSeconds();
    const StepStats s = sim.step();
    cpu += threadCpuSeconds() - c0;
    wall += wallSeconds() - w0;
    r.substeps += s.substeps, r.outer += s.outer_iterations, ++r.steps;
    if (!s.converged) {
      r.stable = false;
      r.why = std::string("step failed (") + toString(s.status) + ") at t = " + std::to_string(i * dt);
      r.t_end = (i - 1) * dt;
      break;
    }
    sim.basePose(p, rpy);  // outside the timing: the simulation does not need it
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

inline std::string readFile(const std::string& path) { return test::readText(path); }

inline std::string readFileOr(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  std::getline(in, text);
  return text;
}

inline std::string mujocoVersion() {
  const int v = mj_version();  // e.g. 222 for 2.2.2
  return std::to_string(v / 100) + "." + std::to_string(v / 10 % 10) + "." + std::to_string(v % 10);
}

// Our q0 in MuJoCo's coordinates (the base from the root-link pose our kinematics gives: the chart
// is the identity at t = 0), q̇0 = 0 (the scene's: asserted), and mj_forward.
inline void setInitialState(const Ours& o, const Mujoco& mj, mjData* d) {
  const mjModel* m = mj.m.get();
  if (o.sim.initialVelocity().cwiseAbs().maxCoeff() != 0) throw std::runtime_error("non-zero initial velocity is not mapped to MuJoCo");
  Data pose_data(o.sim.model());
  forwardKinematics(o.sim.model(), pose_data, o.sim.initialConfiguration());
  Vec3 p0, rpy0;
  basePose(o.sim.model(), pose_data, p0, rpy0);
  const Eigen::Quaterniond q0(test::rpyMatrix(rpy0));
  mj_resetData(m, d);
  for (int k = 0; k < 3; ++k) d->qpos[mj.free_qpos + k] = p0[k];
  d->qpos[mj.free_qpos + 3] = q0.w(), d->qpos[mj.free_qpos + 4] = q0.x(), d->qpos[mj.free_qpos + 5] = q0.y();
  d->qpos[mj.free_qpos + 6] = q0.z();
  for (size_t k = 0; k < mj.coordinate.size(); ++k) d->qpos[mj.qposadr[k]] = o.sim.initialConfiguration()[mj.coordinate[k]];
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
}

inline std::string floatingUrdfForMujoco(const Ours& o) {
  // The URDF MuJoCo is given: the oracle test's edits (visuals removed, MuJoCo's inertia
  // alterations off, principal-axes inertias; static links fused into their parents), plus a root
  // link "mj_world" holding the robot's root link by a floating joint (MuJoCo's free joint) and the
  // ground: a 200 m × 200 m × 1 m box whose top face is z = 0 (a URDF cannot hold a plane; for a
  // sphere on its top face the contact is a plane's). mj_world and the ground are static and fused
  // into MuJoCo's world body. Everything stays in memory: no lossy MJCF round trip (mj_saveLastXML
  // writes 6 significant digits).
  std::string root;  // the URDF's root link (A1: base, welded to trunk)
  for (const Link& l : o.sim.model().links)
    if (l.parent_link < 0) root = l.name;
  std::string urdf = test::urdfForMujoco(readFile(o.sim.scene().urdf), /*fusestatic=*/true);
  const size_t close = urdf.rfind("</robot>");
  if (close == std::string::npos) throw std::runtime_error("no </robot> in " + o.sim.scene().urdf);
  urdf.insert(close,
              "  <link name=\"mj_world\"/>\n"
              "  <joint name=\"mj_free\" type=\"floating\"><parent link=\"mj_world\"/><child link=\"" + root +
                  "\"/></joint>\n"
              "  <link name=\"mj_ground\"><collision><origin xyz=\"0 0 -0.5\" rpy=\"0 0 0\"/><geometry>"
              "<box size=\"200 200 1\"/></geometry></collision></link>\n"
              "  <joint name=\"mj_ground_fixed\" type=\"fixed\"><parent link=\"mj_world\"/><child link=\"mj_ground\"/>"
              "<origin xyz=\"0 0 0\" rpy=\"0 0 0\"/></joint>\n");
  return urdf;
}

// MuJoCo's model of the robot: gravity ours, joint limits off, the free joint and the actuated
// joints mapped to our coordinates; no contact set up yet.
inline Mujoco loadMujoco(const Ours& o, double mu) {
  const std::string urdf = floatingUrdfForMujoco(o);
  std::string error;
  test::MjModelPtr m = test::loadMujocoFromMemory(urdf, "a1_floating.urdf", error);
  if (!m) throw std::runtime_error(error);
  if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());

  Mujoco mj;
  mj.mu = mu;
  for (int k = 0; k < 3; ++k) m->opt.gravity[k] = o.sim.model().gravity[k];
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
  if (std::abs(m->body_subtreemass[mj.trunk] - o.sim.model().total_mass) > 1e-9 * o.sim.model().total_mass)
    throw std::runtime_error("MuJoCo's robot mass " + std::to_string(m->body_subtreemass[mj.trunk]) + " differs from ours");
  // Actuated joints by name.
  for (int i = 0; i < o.sim.model().nq; ++i) {
    if (o.sim.model().bodies[i].is_base) continue;
    const int j = mj_name2id(m.get(), mjOBJ_JOINT, o.sim.model().dof_names[i].c_str());
    if (j < 0) throw std::runtime_error("MuJoCo has no joint " + o.sim.model().dof_names[i]);
    mj.coordinate.push_back(i);
    mj.qposadr.push_back(m->jnt_qposadr[j]);
    mj.dofadr.push_back(m->jnt_dofadr[j]);
  }
  if (m->nv != o.sim.model().nq) throw std::runtime_error("MuJoCo and nmdp disagree on the number of degrees of freedom");
  mj.m = std::move(m);
  return mj;
}

// Contacts: the foot spheres (matched to our contact points by their world centres at the initial
// pose, and by radius) against the ground only, with friction mu.
inline void enableFootContacts(const Ours& o, Mujoco& mj) {
  const double mu = mj.mu;
  mjModel* mm = mj.m.get();
  test::MjDataPtr d(mj_makeData(mm));
  setInitialState(o, mj, d.get());
  Data data(o.sim.model());
  forwardKinematics(o.sim.model(), data, o.sim.initialConfiguration());
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
  for (const ContactPoint& c : o.sim.system().contacts) {
    const Vec3 centre = linkPoint(o.sim.model(), data, c.link, c.offset);
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
}

// The defaults the report states.
inline void checkMujocoDefaults(const mjModel* mm) {
  if (mm->opt.integrator != mjINT_EULER || mm->opt.solver != mjSOL_NEWTON || mm->opt.cone != mjCONE_PYRAMIDAL)
    throw std::runtime_error("MuJoCo's options are not the defaults this benchmark reports");
  for (int g = 0; g < mm->ngeom; ++g)
    if (mm->geom_contype[g] || mm->geom_conaffinity[g])
      if (mm->geom_solref[mjNREF * g] != 0.02 || mm->geom_solref[mjNREF * g + 1] != 1 || mm->geom_solimp[mjNIMP * g] != 0.9 ||
          mm->geom_solimp[mjNIMP * g + 1] != 0.95 || mm->geom_solimp[mjNIMP * g + 2] != 0.001)
        throw std::runtime_error("MuJoCo's contact solref/solimp are not the defaults this benchmark reports");
}

inline Mujoco buildMujoco(const Ours& o, double mu) {
  Mujoco mj = loadMujoco(o, mu);
  enableFootContacts(o, mj);
  checkMujocoDefaults(mj.m.get());
  return mj;
}

inline Vec3 rpyOfQuaternion(const double* quat) {
  const Eigen::Quaterniond q(quat[0], quat[1], quat[2], quat[3]);
  return test::rpyOf(q.normalized().toRotationMatrix());
}

inline constexpr const char* kMujoco = "MuJoCo";
inline constexpr const char* kMujocoImplicitKd = "MuJoCo, implicit kd";
inline bool isMujoco(const std::string& engine) { return engine == kMujoco || engine == kMujocoImplicitKd; }

// implicit_kd: −kd q̇ as dof_damping (integrated implicitly by MuJoCo's Euler integrator), the rest
// of the PD torque explicit; otherwise the whole PD torque explicit.
inline Run runMujoco(const Ours& o, Mujoco& mj, double dt, double duration, const Bounds& bounds, bool implicit_kd) {
  mjModel* m = mj.m.get();
  m->opt.timestep = dt;
  for (size_t k = 0; k < mj.coordinate.size(); ++k) m->dof_damping[mj.dofadr[k]] = implicit_kd ? o.sim.system().gains.kd[mj.coordinate[k]] : 0.0;
  test::MjDataPtr d(mj_makeData(m));
  setInitialState(o, mj, d.get());
  Vec3 p0 = Eigen::Map<const Vec3>(d->qpos + mj.free_qpos);

  PdTarget target;
  target.position = Eigen::VectorXd::Zero(o.sim.model().nq);
  target.velocity = Eigen::VectorXd::Zero(o.sim.model().nq);
  const PdGains& g = o.sim.system().gains;
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
    o.sim.targets().evaluate((i - 1) * dt, target);  // explicit: the target and the state at the step's start
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

// Ours, built as `nmdp simulate` builds the scene with these --set overrides.
inline std::unique_ptr<Ours> buildOurs(const std::string& scene_path, const std::vector<std::string>& overrides) {
  nlohmann::json scene_json = loadSceneJson(scene_path);
  for (const std::string& assignment : overrides) applyOverride(scene_json, assignment, scene_path + ": --set");
  const SceneConfig config = parseScene(scene_json, scene_path);
  if (config.contact_model.value("type", "") != "coulomb") throw std::runtime_error("the scene's contact model must be coulomb");
  return std::make_unique<Ours>(Ours{scene_path, std::move(scene_json), buildSimulation(config, coulombOnly())});
}

}  // namespace nmdp::bench
