// nmdp.ContactModel: a contact model built by the registry from the JSON object a scene's
// contacts.model takes, probed for one foot on the flat ground z = 0 (contact_models/foot_frame.hpp):
// its wrench-polytope vertices (and dV/dξ) at a depth and leg angle, and their planar projection
// with its convex hull for plotting. Errors are ValueError with the CLI's message (nmdp wrench --model).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "common/input_error.hpp"
#include "common/limits.hpp"
#include "contact_model_handle.hpp"
#include "contact_models/foot_frame.hpp"
#include "contact_models/registry.hpp"
#include "py_json.hpp"
#include "terrain/plane.hpp"

namespace nmdp::python {

namespace py = pybind11;

namespace {

// The rows of V: torque about the sphere centre, then force, world frame.
const std::vector<std::string> kRowNames = {"tx", "ty", "tz", "fx", "fy", "fz"};
// The foot radius of nmdp wrench (m): the quadruped's foot spheres.
constexpr double kDefaultRadius = 0.02;
constexpr double kMaxRadius = 10.0;  // m, as nmdp wrench --radius

std::shared_ptr<ContactModelHandle> fromConfig(const py::handle& config, const py::object& base_dir) {
  if (!py::isinstance<py::dict>(config))
    throw InputError("--model: expected a dict such as {\"type\": \"coulomb\", \"mu\": 0.7}");
  ConfigContext ctx{"--model", py::str(py::module_::import("os").attr("fspath")(base_dir)).cast<std::string>()};
  if (ctx.base_dir == ".") ctx.base_dir = "";  // relative paths stay as given
  const nlohmann::json json = toJson(config, "--model");
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  return std::make_shared<ContactModelHandle>(registry.build(json, ctx));
}

// Every entry finite and of magnitude at most `most`; `name` names the argument in the message.
void checkValues(const double* v, py::ssize_t n, const char* name, double most, const char* unit) {
  for (py::ssize_t i = 0; i < n; ++i) {
    const std::string entry = n > 1 ? std::string(name) + "[" + std::to_string(i) + "]" : std::string(name);
    if (!std::isfinite(v[i])) throw InputError(entry + ": " + std::to_string(v[i]) + " is not a finite number");
    if (std::abs(v[i]) > most)
      throw InputError(entry + ": " + std::to_string(v[i]) + " is beyond " + std::to_string(most) + " " + unit);
  }
}

struct Evaluation {
  std::vector<py::ssize_t> shape;  // the broadcast shape of depth and angle
  std::vector<ContactWrenches> out;
};

// The model at every (depth, angle) pair (numpy broadcasting), the GIL released while it runs.
Evaluation evaluate(ContactModelHandle& h, const py::object& depth, const py::object& angle, double radius,
                    bool with_derivatives) {
  using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const Doubles given_depth = Doubles::ensure(depth), given_angle = Doubles::ensure(angle);
  if (!given_depth) throw InputError("depth: expected a number or an array of numbers (m)");
  if (!given_angle) throw InputError("angle: expected a number or an array of numbers (rad)");
  const py::tuple both = py::module_::import("numpy").attr("broadcast_arrays")(given_depth, given_angle);
  const Doubles d = Doubles::ensure(both[0]), a = Doubles::ensure(both[1]);
  const py::ssize_t n = d.size();
  const int K = h.model->vertexCount();
  if (n * 6 * K * (with_derivatives ? 7 : 1) > limits::kMaxArrayEntries)
    throw InputError("depth, angle: " + std::to_string(n) + " points give more than " +
                     std::to_string(limits::kMaxArrayEntries) + " numbers");
  checkValues(d.data(), n, "depth", limits::kMaxModelFeature, "m");
  checkValues(a.data(), n, "angle", limits::kMaxModelFeature, "rad");
  checkValues(&radius, 1, "radius", kMaxRadius, "m");
  if (radius < 0) throw InputError("radius: must be >= 0");
  if (with_derivatives && h.model->derivative() == DerivativeSupport::None)
    throw InputError("--derivatives: this " + h.model->describe() + " model has no derivative (zeroth-order methods only)");

  Evaluation e;
  e.shape.assign(d.shape(), d.shape() + d.ndim());
  const PlaneTerrain ground;
  std::vector<ContactFrame> frames(static_cast<size_t>(n));
  for (py::ssize_t i = 0; i < n; ++i) frames[i] = footFrameAt(ground, 0.0, 0.0, d.data()[i], a.data()[i], radius);
  e.out.resize(frames.size());
  py::gil_scoped_release release;
  for (ContactWrenches& w : e.out) w.resize(K);
  std::lock_guard<std::mutex> lock(h.mutex);
  h.model->evaluate(frames, ground, e.out, with_derivatives);
  return e;
}

// V as an array of shape [..., 6, K]; with derivatives also dV/dξ as [..., 6 (ξ), 6, K].
py::object vertices(ContactModelHandle& h, const py::object& depth, const py::object& angle, double radius,
                    bool with_derivatives) {
  const Evaluation e = evaluate(h, depth, angle, radius, with_derivatives);
  const py::ssize_t K = h.model->vertexCount();
  std::vector<py::ssize_t> shape = e.shape;
  shape.insert(shape.end(), {6, K});
  py::array_t<double> V(shape);
  double* v = V.mutable_data();
  for (const ContactWrenches& w : e.out)
    for (int r = 0; r < 6; ++r)
      for (py::ssize_t k = 0; k < K; ++k) *v++ = w.V(r, k);
  if (!with_derivatives) return std::move(V);
  shape.insert(shape.end() - 2, 6);
  py::array_t<double> dV(shape);
  double* dv = dV.mutable_data();
  for (const ContactWrenches& w : e.out)
    for (int i = 0; i < 6; ++i)
      for (int r = 0; r < 6; ++r)
        for (py::ssize_t k = 0; k < K; ++k) *dv++ = w.dV[i](r, k);
  return py::make_tuple(V, dV);
}

int rowIndex(const std::string& name) {
  const auto it = std::find(kRowNames.begin(), kRowNames.end(), name);
  if (it == kRowNames.end())
    throw InputError("axes: '" + name + "' is not a row of V; expected two of tx, ty, tz, fx, fy, fz");
  return static_cast<int>(it - kRowNames.begin());
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// The convex hull's corners (indices into `p`), counter-clockwise from the point with the smallest
// (x, y); collinear points on an edge are left out (Andrew's monotone chain). One
// index when all points coincide, two when they are collinear.
std::vector<int> convexHull(const std::vector<Eigen::Vector2d>& p) {
  std::vector<int> order(p.size());
  for (size_t i = 0; i < p.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y());
  });
  order.erase(std::unique(order.begin(), order.end(), [&](int a, int b) { return p[a] == p[b]; }), order.end());
  if (order.size() < 3) return order;
  std::vector<int> hull(2 * order.size());
  size_t k = 0;
  for (size_t i = 0; i < order.size(); ++i) {  // lower chain
    while (k >= 2 && cross(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0) --k;
    hull[k++] = order[i];
  }
  for (size_t i = order.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(p[hull[k - 2]], p[hull[k - 1]], p[order[i]]) <= 0) --k;
    hull[k++] = order[i];
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

py::dict wrenchSpace(ContactModelHandle& h, double depth, double angle, const std::vector<std::string>& axes,
                     double radius) {
  if (axes.size() != 2) throw InputError("axes: expected two row names such as (\"fx\", \"fz\")");
  const int r0 = rowIndex(axes[0]), r1 = rowIndex(axes[1]);
  const Evaluation e = evaluate(h, py::float_(depth), py::float_(angle), radius, false);
  const Mat6X& V = e.out[0].V;
  std::vector<Eigen::Vector2d> points(static_cast<size_t>(V.cols()));
  py::array_t<double> projected({static_cast<py::ssize_t>(V.cols()), py::ssize_t{2}});
  for (Eigen::Index k = 0; k < V.cols(); ++k) {
    points[k] = Eigen::Vector2d(V(r0, k), V(r1, k));
    projected.mutable_at(k, 0) = V(r0, k);
    projected.mutable_at(k, 1) = V(r1, k);
  }
  const std::vector<int> corners = convexHull(points);
  py::array_t<double> hull({static_cast<py::ssize_t>(corners.size()), py::ssize_t{2}});
  py::array_t<std::int64_t> indices(static_cast<py::ssize_t>(corners.size()));
  for (size_t i = 0; i < corners.size(); ++i) {
    hull.mutable_at(i, 0) = points[corners[i]].x();
    hull.mutable_at(i, 1) = points[corners[i]].y();
    indices.mutable_at(i) = corners[i];
  }
  py::array_t<double> vertices({py::ssize_t{6}, static_cast<py::ssize_t>(V.cols())});
  for (int r = 0; r < 6; ++r)
    for (Eigen::Index k = 0; k < V.cols(); ++k) vertices.mutable_at(r, k) = V(r, k);
  py::dict result;
  result["axes"] = py::make_tuple(axes[0], axes[1]);
  result["points"] = projected;
  result["hull"] = hull;
  result["hull_indices"] = indices;
  result["vertices"] = vertices;
  return result;
}

}  // namespace

void bindContactModel(py::module_& m) {
  py::class_<ContactModelHandle, std::shared_ptr<ContactModelHandle>> c(m, "ContactModel", R"doc(
A contact model: the wrench polytope of one foot as a function of its state (contact_models/).
Build one with ContactModel.from_config({...}) or nmdp.fit(...). Probed on the flat ground z = 0 with
the leg in the x-z plane: depth = the signed distance of the foot sphere's lowest point to the
ground (m, negative below), angle = the leg's tilt from the vertical toward +x (rad). These are the
planar models' features (phi, beta); the Coulomb cone's penetration is max(0, -depth).
V has rows ROWS = (tx, ty, tz, fx, fy, fz): torque about the sphere centre, then force, world frame.)doc");
  c.attr("ROWS") = py::tuple(py::cast(kRowNames));
  c.def_static("from_config", &fromConfig, py::arg("config"), py::arg("base_dir") = ".", R"doc(
The model a scene's contacts.model builds from `config` ({"type": "coulomb", "mu": 0.8},
{"type": "rbf", "file": "x.h5"}, {"type": "mlp", "file": "m.h5"}, ...); relative files against
base_dir. ValueError with the registry's message (as nmdp wrench --model) on a bad key or value.)doc");
  c.def("describe", [](const ContactModelHandle& h) { return h.model->describe(); }, "Type and parameters, one line.");
  c.def_property_readonly("vertex_count", [](const ContactModelHandle& h) { return h.model->vertexCount(); });
  c.def_property_readonly("derivative",
                          [](const ContactModelHandle& h) { return derivativeSupportName(h.model->derivative()); },
                          "\"analytic\", \"autograd\" or \"none\": how dV/dxi is computed.");
  c.def("configuration", [](const ContactModelHandle& h) { return toPython(h.model->configuration()); },
        "The complete configuration (every key with the value in use) from_config rebuilds the model from; "
        "None for a model fitted without out=.");
  c.def("vertices", &vertices, py::arg("depth"), py::arg("angle"), py::arg("radius") = kDefaultRadius,
        py::arg("with_derivatives") = false, R"doc(
The polytope's vertices V for a foot sphere of `radius` (m, default 0.02, as nmdp wrench) at `depth`
(m) and leg `angle` (rad): shape (6, K) for numbers, (..., 6, K) for arrays (numpy broadcasting).
With with_derivatives=True returns (V, dV), dV[..., i, :, :] = dV/dxi_i (shape (..., 6, 6, K)) for
xi = [rotation about the sphere centre; translation] of the foot. The GIL is released.)doc");
  c.def("wrench_space", &wrenchSpace, py::arg("depth"), py::arg("angle"),
        py::arg("axes") = std::vector<std::string>{"fx", "fz"}, py::arg("radius") = kDefaultRadius, R"doc(
The polytope seen in the plane of two rows of V (default the sagittal forces fx, fz) for plotting:
a dict with "axes" (the two row names), "points" (K x 2: every vertex projected), "hull" (H x 2: the
corners of their convex hull, counter-clockwise, the first not repeated, so that
plt.fill(*ws["hull"].T) draws it), "hull_indices" (H: the vertex of each corner) and "vertices"
(6 x K: V). H is 1 when all vertices project to one point (e.g. zero above the surface), 2 when
they are collinear.)doc");
  c.def("__repr__", [](const ContactModelHandle& h) { return "<nmdp.ContactModel " + h.model->describe() + ">"; });
}

}  // namespace nmdp::python
