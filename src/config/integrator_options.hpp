// The integrator's configuration (DESIGN.md 2-6): the method and every option of a time step, as a
// scene's "integrator" object sets them.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/fields.hpp"

namespace nmdp {

// The five methods of the toolkit, by their scene names.
enum class Method { NePgm, NeZopgm, PbdPgm, PbdZopgm, NeMdp };

const char* methodName(Method method);               // "ne-pgm", ...
std::optional<Method> parseMethod(const std::string& name);
const std::vector<std::string>& methodNames();       // every valid name, for messages
inline bool isPositionBased(Method m) { return m == Method::PbdPgm || m == Method::PbdZopgm; }
inline bool isZeroOrder(Method m) { return m == Method::NeZopgm || m == Method::PbdZopgm; }
// Whether the method evaluates the contact model's derivative dV/dξ.
inline bool needsContactDerivative(Method m) { return m == Method::NePgm || m == Method::PbdPgm; }

// The kinetic energy K that maximal dissipation minimizes (DESIGN.md 2); full-body-pd gives each
// contact the rigid Coulomb law at any step (docs/INTEGRATOR.md, "Which friction law K stands for").
enum class KineticEnergyMeasure { FullBody, ContactPoints, FullBodyPd };
const char* kineticEnergyName(KineticEnergyMeasure k);  // "full-body", "contact-points", "full-body-pd"
std::optional<KineticEnergyMeasure> parseKineticEnergy(const std::string& name);

// How the zeroth-order methods account for the vertices' change with the pose without the model's
// derivative: central differences of V (the first-order step), or the paper's dropped term.
enum class ZerothOrderJacobian { FiniteDifference, Dropped };
const char* zerothOrderJacobianName(ZerothOrderJacobian z);  // "finite-difference", "dropped"
std::optional<ZerothOrderJacobian> parseZerothOrderJacobian(const std::string& name);

// The options of a time step. Each is declared once, with its range and one line of documentation,
// in integratorFields() (`nmdp simulate --schema` prints them); docs/INTEGRATOR.md says why the
// defaults are what they are.
struct IntegratorOptions {
  Method method = Method::NePgm;
  int order = 1;
  KineticEnergyMeasure kinetic_energy = KineticEnergyMeasure::FullBodyPd;
  bool adaptive = true;
  double min_substep = 1e-5;
  double epsilon = 1e-6;
  double tol_w = 1e-8;
  double eta = 5.0;
  double eta_reject = 10.0;
  double eta_limited = 5.0;
  double beta_min = 1e-4;
  double beta_max = 1e6;
  double beta_initial = 1e-4;
  bool adapt_start_penalty = true;
  int max_outer_iterations = 100;
  double projection_tolerance = 1e-9;
  int projection_max_iterations = 30;
  int projection_backtracking = 10;
  ZerothOrderJacobian zeroth_order_jacobian = ZerothOrderJacobian::FiniteDifference;
  bool predict_first_iterate = false;
  bool warm_start_weights = true;
  double energy_tolerance = 0.5;
  double accuracy = 0.01;
};

// A scene's "integrator" object: the output step dt and the options.
struct IntegratorSettings {
  double dt = 0.05;  // s
  IntegratorOptions options;
};

// The declaration of every key of the "integrator" object (energy_tolerance is set by programs only).
const Fields<IntegratorSettings>& integratorFields();

// Reads a scene's "integrator" object over the defaults; InputError "<w>.<key>: ..." on a bad key.
IntegratorSettings readIntegratorSettings(const nlohmann::json& object, const KeyPath& w);

// Throws std::invalid_argument "integrator: ..." if an option is outside its declared range, the
// order is not 1 or 2, or ne-mdp is asked for order 2 (the checks a program's options get).
void validateIntegratorOptions(const IntegratorOptions& options);

}  // namespace nmdp
