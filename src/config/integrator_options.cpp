#include "config/integrator_options.hpp"

#include <limits>
#include <stdexcept>

#include "common/named_enum.hpp"

namespace nmdp {

namespace {

constexpr EnumName<Method> kMethods[] = {{Method::NePgm, "ne-pgm"},
                                         {Method::NeZopgm, "ne-zopgm"},
                                         {Method::PbdPgm, "pbd-pgm"},
                                         {Method::PbdZopgm, "pbd-zopgm"},
                                         {Method::NeMdp, "ne-mdp"}};
constexpr EnumName<KineticEnergyMeasure> kKineticEnergies[] = {{KineticEnergyMeasure::FullBody, "full-body"},
                                                               {KineticEnergyMeasure::ContactPoints, "contact-points"},
                                                               {KineticEnergyMeasure::FullBodyPd, "full-body-pd"}};
constexpr EnumName<ZerothOrderJacobian> kZerothOrderJacobians[] = {
    {ZerothOrderJacobian::FiniteDifference, "finite-difference"}, {ZerothOrderJacobian::Dropped, "dropped"}};

}  // namespace

const char* methodName(Method method) { return nameOf(kMethods, method); }
std::optional<Method> parseMethod(const std::string& name) { return enumFromName(kMethods, name); }
const std::vector<std::string>& methodNames() {
  static const std::vector<std::string> names = namesOf(kMethods);
  return names;
}

const char* kineticEnergyName(KineticEnergyMeasure k) { return nameOf(kKineticEnergies, k); }
std::optional<KineticEnergyMeasure> parseKineticEnergy(const std::string& name) {
  return enumFromName(kKineticEnergies, name);
}

const char* zerothOrderJacobianName(ZerothOrderJacobian z) { return nameOf(kZerothOrderJacobians, z); }
std::optional<ZerothOrderJacobian> parseZerothOrderJacobian(const std::string& name) {
  return enumFromName(kZerothOrderJacobians, name);
}


namespace {

using S = IntegratorSettings;

// A field of the options inside the settings.
#define NMDP_OPTION(member) [](S& s) -> auto& { return s.options.member; }

Fields<S> declareIntegratorFields() {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // dt from 1 µs (a step that small no longer advances the clock of a long run) to 1 s.
  const Limit<S> dt(false, [](const S& s) { return s.dt; }, "dt");
  const Limit<S> beta_min_open(true, [](const S& s) { return s.options.beta_min; }, "beta_min");
  const Limit<S> beta_min(false, [](const S& s) { return s.options.beta_min; }, "beta_min");
  const Limit<S> beta_max(false, [](const S& s) { return s.options.beta_max; }, "beta_max");
  Fields<S> f;
  f.choice("method", NMDP_OPTION(method), kMethods, "method", "the time-stepping method (DESIGN.md 2-6)")
      .integer("order", NMDP_OPTION(order), 1, 2, "",
               "time discretization of the NMDP methods: 1 backward Euler, 2 variable-step BDF2 (solver/bdf2.hpp)",
               "1 (backward Euler, the paper's) or 2 (BDF2)")
      .choice("kinetic_energy", NMDP_OPTION(kinetic_energy), kKineticEnergies, "value",
              "the kinetic energy maximal dissipation minimizes (full-body-pd: the rigid Coulomb law at any step)")
      .number("dt", &S::dt, atLeast(1e-6), atMost(1), "s", "the step, and the output interval")
      .boolean("adaptive", NMDP_OPTION(adaptive), "halve a failed step down to min_substep (Algorithm 2)")
      .number("min_substep", NMDP_OPTION(min_substep), above(0), dt, "s", "the shortest sub-step a failed step splits to")
      .number("epsilon", NMDP_OPTION(epsilon), above(0), atMost(1), "J",
              "accept-and-stop threshold on the K decrease and on the largest change of a coordinate")
      .number("tol_w", NMDP_OPTION(tol_w), above(0), atMost(1), "",
              "stop when the weights' change as a generalized force is below tol_w times the robot's weight")
      .number("eta", NMDP_OPTION(eta), above(1), atMost(1e3), "", "trust-region relaxation: beta / eta after an accepted move")
      .number("eta_reject", NMDP_OPTION(eta_reject), above(1), atMost(1e3), "", "beta x eta_reject after a rejected move")
      .number("eta_limited", NMDP_OPTION(eta_limited), above(1), atMost(1e3), "",
              "beta / eta_limited after an accepted move the penalty, not the QP's model, limited")
      .number("beta_min", NMDP_OPTION(beta_min), above(0), atMost(1e6), "", "the smallest trust-region penalty")
      .number("beta_max", NMDP_OPTION(beta_max), beta_min_open, atMost(1e12), "", "the largest trust-region penalty")
      .number("beta_initial", NMDP_OPTION(beta_initial), beta_min, beta_max, "",
              "the penalty of the first step; later steps inherit theirs")
      .boolean("adapt_start_penalty", NMDP_OPTION(adapt_start_penalty),
               "start a step from the penalty its predecessor's first move called for")
      .integer("max_outer_iterations", NMDP_OPTION(max_outer_iterations), 1, 100000, "",
               "projected-gradient iterations of one step before it fails")
      .number("projection_tolerance", NMDP_OPTION(projection_tolerance), above(0), atMost(1), "",
              "manifold projection's tolerance on |G|, relative to the robot's weight")
      .integer("projection_max_iterations", NMDP_OPTION(projection_max_iterations), 1, 10000, "",
               "Newton iterations of one projection")
      .integer("projection_backtracking", NMDP_OPTION(projection_backtracking), 0, 60, "",
               "halvings of a Newton step that does not decrease |G| (0: full steps only, the paper's)")
      .boolean("warm_start_weights", NMDP_OPTION(warm_start_weights),
               "start each step from the previous step's contact weights instead of w = 0")
      .boolean("predict_first_iterate", NMDP_OPTION(predict_first_iterate),
               "start Newton from q_n + h qdot_n instead of q_n")
      .choice("zeroth_order_jacobian", NMDP_OPTION(zeroth_order_jacobian), kZerothOrderJacobians, "value",
              "the zeroth-order methods' stand-in for dV/dxi: central differences or the paper's dropped term")
      .number("accuracy", NMDP_OPTION(accuracy), atLeast(0), atMost(1), "",
              "error control's relative tolerance on a sub-step's local position error (0: off)")
      .number("energy_tolerance", NMDP_OPTION(energy_tolerance), atLeast(0), atMost(kInf), "",
              "share of a step's energy turnover it may gain before it is refused as diverged (inf: no check)")
      .programOnly();
  return f;
}

#undef NMDP_OPTION

// A step splits at most this many times, so one step is at most 2^20 sub-steps of work.
constexpr int kMaxSplits = 20;

}  // namespace

const Fields<IntegratorSettings>& integratorFields() {
  static const Fields<IntegratorSettings> fields = declareIntegratorFields();
  return fields;
}

IntegratorSettings readIntegratorSettings(const nlohmann::json& object, const KeyPath& w) {
  IntegratorSettings s;
  integratorFields().readInto(object, s, w);
  const IntegratorOptions& o = s.options;
  if (o.order == 2 && o.method == Method::NeMdp)
    (w / "order").fail("ne-mdp is first order only; order 2 needs ne-pgm, ne-zopgm, pbd-pgm or pbd-zopgm");
  if (o.min_substep < s.dt / (1 << kMaxSplits))
    (w / "min_substep").fail("must be at least dt / 2^" + std::to_string(kMaxSplits) + " = " +
                             numberText(s.dt / (1 << kMaxSplits)) + " s (a step splits at most " +
                             std::to_string(kMaxSplits) + " times), got " + numberText(o.min_substep));
  return s;
}

void validateIntegratorOptions(const IntegratorOptions& options) {
  if (options.order != 1 && options.order != 2)
    throw std::invalid_argument("integrator: order " + std::to_string(options.order) +
                                " is not available; use 1 (backward Euler) or 2 (BDF2)");
  if (options.order == 2 && options.method == Method::NeMdp)
    throw std::invalid_argument("integrator: ne-mdp is first order only (order 1); order 2 needs an NMDP method "
                                "(ne-pgm, ne-zopgm, pbd-pgm, pbd-zopgm)");
  // A program's options have no dt: min_substep is bounded by nothing above.
  IntegratorSettings s{std::numeric_limits<double>::infinity(), options};
  for (const Field<IntegratorSettings>& f : integratorFields().list) {
    if (f.name == "dt" || !f.check) continue;
    if (const std::string what = f.check(s); !what.empty())
      throw std::invalid_argument("integrator: options out of range: " + f.name + " " + what);
  }
}

}  // namespace nmdp
