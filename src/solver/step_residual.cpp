#include "solver/step_residual.hpp"

#include "multibody/crba.hpp"
#include "multibody/kinematics.hpp"
#include "solver/ne_residual.hpp"

namespace nmdp {

namespace {
// M w for a 6×K vertex matrix: K inline 6-wide axpys (Eigen's general matrix-vector product costs
// more in dispatch than in flops at K ≈ 6).
inline Vec6 combine(const Mat6X& M, const double* w) {
  Vec6 r = M.col(0) * w[0];
  for (Eigen::Index k = 1; k < M.cols(); ++k) r += M.col(k) * w[k];
  return r;
}
}  // namespace

StepResidual::StepResidual(const System& system)
    : data(*system.model),
      mass_llt_(system.model->nq),
      data_prev_(*system.model),
      finite_difference_(static_cast<int>(system.contacts.size()),
                         system.contact_model ? system.contact_model->vertexCount() : 0) {
  const Model& model = *system.model;
  n_ = model.nq;
  const int C = static_cast<int>(system.contacts.size());
  K_vertices_ = (C > 0 && system.contact_model) ? system.contact_model->vertexCount() : 0;
  m_ = C * K_vertices_;
  G.setZero(n_);
  dG_dtheta.setZero(n_, n_);
  B.setZero(n_, m_);
  grad_K.setZero(n_);
  hess_K.setZero(n_, n_);
  frames.resize(C);
  wrenches.resize(C);
  for (ContactWrenches& cw : wrenches) cw.resize(K_vertices_);
  jacobians.assign(C, Mat6X::Zero(6, n_));
  contact_points_n_.assign(C, Vec3::Zero());
  contact_points_prev_.assign(C, Vec3::Zero());
  for (const ContactPoint& cp : system.contacts) {
    const int body = model.links[cp.link].body;
    contact_bodies_.push_back(body);
    std::vector<int> chain;  // J_c's nonzero columns: the body and its ancestors
    for (int j = body; j >= 0; j = model.bodies[j].parent) chain.push_back(j);
    contact_chains_.push_back(std::move(chain));
  }
  q_n_.setZero(n_);
  qd_n_.setZero(n_);
  target_.position.setZero(n_);
  target_.velocity.setZero(n_);
  pd_hessian_.setZero(n_);
  work_.setZero(n_);
  work2_.setZero(n_);
  hess_work_.setZero(n_, n_);
  chain_jacobian_transpose_.setZero(n_, 6);
  chain_column_.setZero(n_);
  kinetic_targets_.resize(n_);
  transforms_n_.resize(n_);
  transforms_prev_.resize(n_);
  inertial_targets_.resize(n_);
  rates_n_.resize(n_);
  rates_prev_.resize(n_);
  armature_target_.setZero(n_);
}

void StepResidual::prepareStep(const System& system, Form form, double h, const PdTarget& target,
                               const Mat3& base_chart, KineticEnergyMeasure kinetic_energy) {
  form_ = form;
  kinetic_energy_ = kinetic_energy;
  h_ = h;
  target_.position = target.position;
  target_.velocity = target.velocity;
  data.base_chart = base_chart;
  data_prev_.base_chart = base_chart;
  pdPotentialHessianDiagonal(system.gains, h, pd_hessian_);
}

void StepResidual::prepare(const System& system, Form form, double h, const Eigen::VectorXd& q_n,
                           const Eigen::VectorXd& qd_n, const Eigen::VectorXd& q_prev, double h_prev,
                           const PdTarget& target, const Mat3& base_chart, KineticEnergyMeasure kinetic_energy) {
  const Model& model = *system.model;
  prepareStep(system, form, h, target, base_chart, kinetic_energy);
  second_order_ = false;
  q_n_ = q_n;
  qd_n_ = qd_n;
  if (form != Form::PositionBased) return;
  const double alpha = h / h_prev;
  forwardKinematics(model, data_prev_, q_n);
  bodyTransforms(model, data_prev_, kinetic_targets_);
  if (kinetic_energy == KineticEnergyMeasure::ContactPoints)  // PBD's u_c needs p_c(q_n)
    for (size_t c = 0; c < system.contacts.size(); ++c)
      contact_points_n_[c] = linkPoint(model, data_prev_, system.contacts[c].link, system.contacts[c].offset);
  forwardKinematics(model, data_prev_, q_prev);
  bodyTransforms(model, data_prev_, transforms_prev_);
  inertialTargets(kinetic_targets_, transforms_prev_, alpha, inertial_targets_);
  armature_target_ = (1.0 + alpha) * q_n - alpha * q_prev;
}

void StepResidual::prepareSecondOrder(const System& system, Form form, const Bdf2Coefficients& bdf2,
                                      const Eigen::VectorXd& q_n, const Eigen::VectorXd& qd_n,
                                      const Eigen::VectorXd& q_prev, const Eigen::VectorXd& qd_prev,
                                      const PdTarget& target, const Mat3& base_chart,
                                      KineticEnergyMeasure kinetic_energy) {
  const Model& model = *system.model;
  const double c = bdf2.extrapolation;
  prepareStep(system, form, bdf2.h_hat, target, base_chart, kinetic_energy);
  second_order_ = true;
  q_n_ = q_n + c * (q_n - q_prev);
  qd_n_ = qd_n + c * (qd_n - qd_prev);
  if (form != Form::PositionBased) return;
  // BDF2 on each body's transform (not on q, whose Coriolis part would keep an O(h) error).
  const bool points = kinetic_energy == KineticEnergyMeasure::ContactPoints;
  forwardKinematics(model, data_prev_, q_n);
  bodyTransforms(model, data_prev_, transforms_n_);
  bodyTransformRates(model, data_prev_, qd_n, rates_n_);
  if (points)
    for (size_t k = 0; k < system.contacts.size(); ++k)
      contact_points_n_[k] = linkPoint(model, data_prev_, system.contacts[k].link, system.contacts[k].offset);
  forwardKinematics(model, data_prev_, q_prev);
  bodyTransforms(model, data_prev_, transforms_prev_);
  bodyTransformRates(model, data_prev_, qd_prev, rates_prev_);
  if (points)
    for (size_t k = 0; k < system.contacts.size(); ++k) {
      contact_points_prev_[k] = linkPoint(model, data_prev_, system.contacts[k].link, system.contacts[k].offset);
      contact_points_n_[k] += c * (contact_points_n_[k] - contact_points_prev_[k]);
    }
  secondOrderTargets(transforms_n_, rates_n_, transforms_prev_, rates_prev_, c, bdf2.h_hat, kinetic_targets_,
                     inertial_targets_);
  armature_target_ = q_n_ + bdf2.h_hat * qd_n_;
}

void StepResidual::velocity(const System& system, const Eigen::VectorXd& theta, Eigen::VectorXd& out) {
  if (!second_order_ || form_ != Form::PositionBased) {
    out = (theta - q_n_) / h_;
    return;
  }
  // PBD at second order: the bodies' BDF2 rates Ṫ_k = (T_k(θ) − T̂_k)/ĥ (and the armature's
  // (θ − q̂)/ĥ) are not the rates of any joint velocity; the next step's V̂ is built from the joint
  // velocity whose rates are closest in the bodies' mass metric, q̇ = H⁻¹ Σ_k J_kᵀ M̄_k Ṫ_k = ĥ H⁻¹ ∇K_body.
  // Their difference is then orthogonal to every J_kᵀ M̄_k, so the next step's generalized inertial
  // force misses only O(h²); the joint-space (θ − q̂)/ĥ misses Σ J_kᵀ M̄_k (T⃛_k − J_k q⃛)·O(h),
  // first order.
  const Model& model = *system.model;
  forwardKinematics(model, data, theta);
  transformEnergy(model, data, kinetic_targets_, h_, &out, nullptr);
  const double inv_h2 = 1.0 / (h_ * h_);
  for (int j = 0; j < n_; ++j) out[j] += model.bodies[j].armature * (theta[j] - q_n_[j]) * inv_h2;
  crbaFromKinematics(model, data);
  mass_llt_.compute(data.H);
  mass_llt_.solveInPlace(out);
  out *= h_;
}

void StepResidual::evaluate(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w,
                            ContactDerivative derivative) {
  if (form_ == Form::NewtonEuler) {
    evaluateValue(system, theta, w);
    addDerivatives(system, theta, w, derivative);
    return;
  }
  positionBasedTerms(system, theta, true);
  if (m_ > 0) {
    frameGeometry(system);
    addContactDerivatives(system, w, derivative);
    addContactForces(system, w);
  }
  if (kinetic_energy_ == KineticEnergyMeasure::ContactPoints) contactPointEnergy(*system.model, true);
}

void StepResidual::addDerivatives(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w,
                                  ContactDerivative derivative) {
  if (form_ != Form::NewtonEuler) return evaluate(system, theta, w, derivative);
  // The value evaluation at θ left RNEA's velocities, accelerations and forces in data, and the
  // contact frames.
  const Model& model = *system.model;
  neInertialJacobian(model, data, h_, dG_dtheta);
  dG_dtheta.diagonal() += pd_hessian_;
  if (kinetic_energy_ != KineticEnergyMeasure::ContactPoints) {
    work_.noalias() = data.H * data.qd_work;
    grad_K = work_ / h_;
    addKineticEnergyConfigurationGradient(model);
    hess_K = data.H * (1.0 / (h_ * h_));
    if (kinetic_energy_ == KineticEnergyMeasure::FullBodyPd) {
      grad_K.array() += h_ * pd_hessian_.array() * data.qd_work.array();
      hess_K.diagonal() += pd_hessian_;
    }
  }
  if (m_ > 0) addContactDerivatives(system, w, derivative);
  if (kinetic_energy_ == KineticEnergyMeasure::ContactPoints) contactPointEnergy(model, true);
}

void StepResidual::evaluateValue(const System& system, const Eigen::VectorXd& theta, const Eigen::VectorXd& w) {
  const Model& model = *system.model;
  if (form_ == Form::NewtonEuler) {
    neInertialResidual(model, data, theta, q_n_, qd_n_, h_, G, nullptr);
    pdTorque(system.gains, target_, theta, q_n_, h_, work_);
    G -= work_;
    if (system.external_force.size() != 0) G -= system.external_force;
    // (The contact-point K is computed below, from the same RNEA velocities.)
    if (kinetic_energy_ != KineticEnergyMeasure::ContactPoints) K = bodyKineticEnergy(model) + pdMetricEnergy(theta);
  } else {
    positionBasedTerms(system, theta, false);
  }
  if (m_ > 0) {
    // No J_c: the contact forces enter G through the joints' motion axes, and the contact points'
    // K through the bodies' velocities.
    frameGeometry(system);
    system.contact_model->evaluate(frames, *system.terrain, wrenches, false);
    addContactForces(system, w);
  }
  if (kinetic_energy_ == KineticEnergyMeasure::ContactPoints) contactPointEnergy(model, false);
}

void StepResidual::positionBasedTerms(const System& system, const Eigen::VectorXd& theta, bool derivatives) {
  const Model& model = *system.model;
  const double inv_h2 = 1.0 / (h_ * h_);
  forwardKinematics(model, data, theta);
  transformEnergy(model, data, inertial_targets_, h_, &G, derivatives ? &dG_dtheta : nullptr);
  gravityPotential(model, data, &work_, derivatives ? &hess_work_ : nullptr);
  G += work_;
  if (derivatives) dG_dtheta += hess_work_;
  pdPotentialGradient(system.gains, target_, theta, q_n_, h_, work_);
  G += work_;
  if (system.external_force.size() != 0) G -= system.external_force;
  if (derivatives) dG_dtheta.diagonal() += pd_hessian_;
  K = derivatives ? transformEnergy(model, data, kinetic_targets_, h_, &grad_K, &hess_K)
                  : transformEnergy(model, data, kinetic_targets_, h_, nullptr, nullptr);
  K += pdMetricEnergy(theta);
  if (derivatives && kinetic_energy_ == KineticEnergyMeasure::FullBodyPd) {
    grad_K.array() += pd_hessian_.array() * (theta - q_n_).array();
    hess_K.diagonal() += pd_hessian_;
  }
  for (int j = 0; j < n_; ++j) {
    const double a = model.bodies[j].armature;
    if (a == 0.0) continue;
    const double inertial = theta[j] - armature_target_[j], kinetic = theta[j] - q_n_[j];
    G[j] += a * inertial * inv_h2;
    K += 0.5 * a * kinetic * kinetic * inv_h2;
    if (!derivatives) continue;
    dG_dtheta(j, j) += a * inv_h2;
    grad_K[j] += a * kinetic * inv_h2;
    hess_K(j, j) += a * inv_h2;
  }
}

double StepResidual::pdMetricEnergy(const Eigen::VectorXd& theta) const {
  if (kinetic_energy_ != KineticEnergyMeasure::FullBodyPd) return 0.0;
  double E = 0.0;
  for (int j = 0; j < n_; ++j) {
    const double d = theta[j] - q_n_[j];
    E += pd_hessian_[j] * d * d;
  }
  return 0.5 * E;
}

double StepResidual::bodyKineticEnergy(const Model& model) const {
  double T = 0.0;
  for (int k = 0; k < model.nq; ++k) {
    const double a = model.bodies[k].armature, qd = data.qd_work[k];
    const double body = model.bodies[k].hasInertia() ? data.v[k].dot(data.Iw[k] * data.v[k]) : 0.0;  // Iw = 0 otherwise
    T += body + a * qd * qd;
  }
  return 0.5 * T;
}

void StepResidual::addKineticEnergyConfigurationGradient(const Model& model) {
  // ∂T/∂q at fixed q̇ = θ̇, world-frame composite form: moving q_j turns its subtree about S_j. Each
  // body's inertia turns with it (−(S_j × v_k)ᵀ h_k) and its velocity changes by S_j × (v_k − v_λ(j)),
  // h_k = I_k v_k; the two leave  ∂T/∂q_j = −S_jᵀ (v_λ(j) ×* Σ_{k ⪰ j} h_k).
  // data.v and data.hc (composite momenta) are those of rneaDerivatives at (θ, θ̇).
  for (int j = 0; j < model.nq; ++j) {
    const int parent = model.bodies[j].parent;
    if (parent >= 0) grad_K[j] -= data.S[j].dot(crossForce(data.v[parent], data.hc[j]));
  }
}

void StepResidual::contactPointEnergy(const Model& model, bool derivatives) {
  // After addContactDerivatives: jacobians at θ; NE: data.v holds the bodies' world velocities at θ̇.
  K = 0.0;
  if (derivatives) {
    grad_K.setZero();
    hess_K.setZero();
  }
  const double inv_h = 1.0 / h_;
  for (size_t c = 0; c < jacobians.size(); ++c) {
    // NE: u = J_c θ̇, the velocity of the point on its body (RNEA's world velocity at the origin,
    // moved to the point), which needs no J_c: the value-only evaluation does not build it.
    Vec3 u = Vec3::Zero();
    if (form_ != Form::NewtonEuler)
      u = (frames[c].position - contact_points_n_[c]) * inv_h;
    else if (contact_bodies_[c] >= 0) {
      const Vec6& v = data.v[contact_bodies_[c]];
      u = v.tail<3>() + v.head<3>().cross(frames[c].position);
    }
    K += 0.5 * u.squaredNorm();
    if (!derivatives) continue;
    const auto J = jacobians[c].bottomRows<3>();
    const double inv_h2 = inv_h * inv_h;
    const std::vector<int>& chain = contact_chains_[c];
    for (size_t a = 0; a < chain.size(); ++a) {
      const int j = chain[a];
      grad_K[j] += J.col(j).dot(u) * inv_h;
      // J_cᵀJ_c is symmetric: each pair once (the same products, so the same bits).
      for (size_t b = 0; b < a; ++b) {
        const int l = chain[b];
        const double entry = inv_h2 * J.col(j).dot(J.col(l));
        hess_K(j, l) += entry;
        hess_K(l, j) += entry;
      }
      hess_K(j, j) += inv_h2 * J.col(j).dot(J.col(j));
    }
    if (form_ != Form::NewtonEuler || contact_bodies_[c] < 0) continue;
    // NE: u = J(θ) θ̇ also moves with θ at fixed θ̇. For q_l ⪯ body k the body's world velocity
    // changes by S_l × (v_k − v_λ(l)) and the point by J_l, so ∂u/∂q_l = b + a × p + ω_k × J_l.
    const int k = contact_bodies_[c];
    const Vec3& p = frames[c].position;
    const Vec3 omega = data.v[k].head<3>();
    for (int l = k; l >= 0; l = model.bodies[l].parent) {
      const int parent = model.bodies[l].parent;
      const Vec6 relative = parent >= 0 ? Vec6(data.v[k] - data.v[parent]) : data.v[k];
      const Vec6 d = crossMotion(data.S[l], relative);
      const Vec3 du = d.tail<3>() + d.head<3>().cross(p) + omega.cross(J.col(l));
      grad_K[l] += u.dot(du);
    }
  }
}

void StepResidual::evaluateContacts(const System& system, const Eigen::VectorXd& q) {
  forwardKinematics(*system.model, data, q);
  if (m_ == 0) return;
  frameGeometry(system);
  contactGeometry(system, ContactDerivative::Dropped);
}

void StepResidual::frameGeometry(const System& system) {
  for (size_t c = 0; c < system.contacts.size(); ++c) contactFrame(*system.model, data, system.contacts[c], frames[c]);
}

void StepResidual::addContactForces(const System& system, const Eigen::VectorXd& w) {
  // J_cᵀ f = S_jᵀ f_O on the chain, with f_O = [τ + p × F; F] the wrench moved from the sphere
  // centre p to the world origin, where the motion axes S_j are expressed.
  for (size_t c = 0; c < system.contacts.size(); ++c) {
    const Vec6 f = combine(wrenches[c].V, w.data() + c * K_vertices_);
    Vec6 f_origin = f;
    f_origin.head<3>() += frames[c].position.cross(Vec3(f.tail<3>()));
    for (int j : contact_chains_[c]) G[j] -= data.S[j].dot(f_origin);
  }
}

void StepResidual::contactGeometry(const System& system, ContactDerivative derivative) {
  const int C = static_cast<int>(system.contacts.size());
  for (int c = 0; c < C; ++c) contactJacobian(*system.model, data, system.contacts[c], jacobians[c]);
  system.contact_model->evaluate(frames, *system.terrain, wrenches, derivative == ContactDerivative::Model);
  if (derivative == ContactDerivative::FiniteDifference)
    finite_difference_.evaluate(*system.contact_model, frames, *system.terrain, wrenches);
  // B's block of contact c is J_cᵀ V_c; rows off the contact's chain stay zero.
  for (int c = 0; c < C; ++c)
    for (int j : contact_chains_[c])
      B.row(j).segment(c * K_vertices_, K_vertices_).noalias() = jacobians[c].col(j).transpose() * wrenches[c].V;
}

void StepResidual::addContactDerivatives(const System& system, const Eigen::VectorXd& w, ContactDerivative derivative) {
  const Model& model = *system.model;
  contactGeometry(system, derivative);
  const int C = static_cast<int>(system.contacts.size());
  for (int c = 0; c < C; ++c) {
    const Mat6X& J = jacobians[c];
    const std::vector<int>& chain = contact_chains_[c];
    const auto w_c = w.segment(c * K_vertices_, K_vertices_);
    const Vec6 f = combine(wrenches[c].V, w_c.data());
    const int body = model.links[system.contacts[c].link].body;
    if (body < 0) continue;  // welded to the world: J = 0
    addJacobianTransposeWrenchDerivative(model, data, body, frames[c].position, -f, dG_dtheta);
    if (derivative == ContactDerivative::Dropped) continue;
    // ∂(V_c w_c)/∂θ = [dV/dξ_0 w_c, …, dV/dξ_5 w_c] J_c, nonzero on the chain's columns only.
    // Each column of J_cᵀ(∂(V_c w_c)/∂θ) is one 6-term combination of J_cᵀ's gathered chain rows
    // (contiguous, vectorized) instead of a 6-D dot product per entry.
    Mat6 df_dxi;
    for (int i = 0; i < 6; ++i) df_dxi.col(i) = combine(wrenches[c].dV[i], w_c.data());
    const int L = static_cast<int>(chain.size());
    for (int a = 0; a < L; ++a) chain_jacobian_transpose_.row(a) = J.col(chain[a]).transpose();
    const auto JT = chain_jacobian_transpose_.topRows(L);
    auto column = chain_column_.head(L);
    for (int b = 0; b < L; ++b) {
      const Vec6 v = df_dxi * J.col(chain[b]);
      column = JT.col(0) * v[0] + JT.col(1) * v[1] + JT.col(2) * v[2] + JT.col(3) * v[3] + JT.col(4) * v[4] +
               JT.col(5) * v[5];
      for (int a = 0; a < L; ++a) dG_dtheta(chain[a], chain[b]) -= column[a];
    }
  }
}

}  // namespace nmdp
