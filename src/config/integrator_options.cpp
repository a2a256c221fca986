#include "config/integrator_options.hpp"

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

}  // namespace nmdp
