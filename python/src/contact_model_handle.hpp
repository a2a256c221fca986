// What a Python nmdp.ContactModel holds: the model and the lock that serializes its evaluations (a
// model keeps scratch between calls, planar_wrench_model.hpp, and the bindings release the GIL).
#pragma once
#include <memory>
#include <mutex>

#include "contact_models/contact_model.hpp"

namespace nmdp::python {

struct ContactModelHandle {
  explicit ContactModelHandle(std::unique_ptr<ContactModel> m) : model(std::move(m)) {}
  std::unique_ptr<ContactModel> model;
  std::mutex mutex;
};

}  // namespace nmdp::python
