#include "contact_models/contact_model.hpp"

#include "common/named_enum.hpp"

namespace nmdp {

namespace {
constexpr EnumName<DerivativeSupport> kDerivativeSupports[] = {
    {DerivativeSupport::Analytic, "analytic"}, {DerivativeSupport::Autograd, "autograd"}, {DerivativeSupport::None, "none"}};
}  // namespace

const char* derivativeSupportName(DerivativeSupport d) { return nameOf(kDerivativeSupports, d); }

}  // namespace nmdp
