#include "multibody/model.hpp"

#include "common/named_enum.hpp"

namespace nmdp {

const char* baseTypeName(BaseType b) { return nameOf(kBaseTypes, b); }

int Model::linkIndex(const std::string& name) const {
  for (size_t i = 0; i < links.size(); ++i)
    if (links[i].name == name) return static_cast<int>(i);
  return -1;
}

int Model::dofIndex(const std::string& name) const {
  for (size_t i = 0; i < dof_names.size(); ++i)
    if (dof_names[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace nmdp
