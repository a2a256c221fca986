#include "contact_models/contact_model.hpp"

namespace nmdp {

const char* derivativeSupportName(DerivativeSupport d) {
  switch (d) {
    case DerivativeSupport::Analytic: return "analytic";
    case DerivativeSupport::Autograd: return "autograd";
    case DerivativeSupport::None: return "none";
  }
  return "?";
}

}  // namespace nmdp
