#include "sim/state_vector.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace nmdp {

namespace {

// The parts in the order of the layout (sim/state_vector.hpp) and what each entry must be.
enum class Entry { Number, Positive, NonNegative, Flag, TouchdownCount, Chart };

struct PartSpec {
  const char* name;
  int length;
  Entry entry;
};

std::vector<PartSpec> partSpecs(const StateLayout& l) {
  return {{"time", 1, Entry::Number},
          {"q", l.nq, Entry::Number},
          {"qdot", l.nq, Entry::Number},
          {"q_prev", l.nq, Entry::Number},
          {"qdot_prev", l.nq, Entry::Number},
          {"h_prev", 1, Entry::Positive},
          {"second_order_history", 1, Entry::Flag},
          {"contact_active", l.contacts, Entry::Flag},
          {"substeps_since_touchdown", 1, Entry::TouchdownCount},
          {"base_chart", 9, Entry::Chart},
          {"beta", 1, Entry::Positive},
          {"beta_start", 1, Entry::Positive},
          {"w", l.weights, Entry::Number},
          {"h_next", 1, Entry::NonNegative},
          {"qp_warm_valid", 1, Entry::Flag},
          {"qp_warm_at_bound", l.weights, Entry::Flag},
          {"qp_warm_cap", l.contacts, Entry::Flag}};
}

// How far a 3×3 matrix may be from a rotation: ‖RᵀR − I‖∞ and |det R − 1|.
constexpr double kRotationTolerance = 1e-9;

// "flat state entry 7 (q[6])": the entry in the whole vector and in its part.
std::string entryName(const StateLayout::Part& part, int i) {
  std::string name = "flat state entry " + std::to_string(part.offset + i) + " (" + part.name;
  if (part.length > 1) name += "[" + std::to_string(i) + "]";
  return name + ")";
}

std::string valueText(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

void checkEntry(const StateLayout::Part& part, Entry kind, int i, double v) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument(entryName(part, i) + " is " + valueText(v) + ": " + what);
  };
  if (!std::isfinite(v)) fail("expected a finite number");
  switch (kind) {
    case Entry::Number:
    case Entry::Chart:
      return;
    case Entry::Positive:
      if (!(v > 0)) fail("expected a positive number");
      return;
    case Entry::NonNegative:
      if (!(v >= 0)) fail("expected a number ≥ 0");
      return;
    case Entry::Flag:
      if (v != 0.0 && v != 1.0) fail("expected 0 or 1");
      return;
    case Entry::TouchdownCount:
      if (v != std::floor(v) || v < 0 || v > kTouchdownRestartSubsteps)
        fail("expected an integer from 0 to " + std::to_string(kTouchdownRestartSubsteps));
      return;
  }
}

void checkRotation(const StateLayout::Part& part, const Eigen::Ref<const Eigen::VectorXd>& x) {
  const Mat3 R = Eigen::Map<const Mat3>(x.data() + part.offset);
  const double orthogonality = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  if (orthogonality <= kRotationTolerance && std::abs(det - 1.0) <= kRotationTolerance) return;
  throw std::invalid_argument("flat state entries " + std::to_string(part.offset) + " to " +
                              std::to_string(part.offset + 8) + " (base_chart) are not a rotation matrix (|RᵀR − I| = " +
                              valueText(orthogonality) + ", det R = " + valueText(det) + ")");
}

void checkFlat(const StateLayout& layout, const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (x.size() != layout.size())
    throw std::invalid_argument("flat state has " + std::to_string(x.size()) + " entries, expected " +
                                std::to_string(layout.size()) + " (nq = " + std::to_string(layout.nq) + ", " +
                                std::to_string(layout.contacts) + " contacts, " + std::to_string(layout.weights) +
                                " contact weights)");
  const std::vector<PartSpec> specs = partSpecs(layout);
  const std::vector<StateLayout::Part> parts = layout.parts();
  for (size_t k = 0; k < parts.size(); ++k) {
    for (int i = 0; i < parts[k].length; ++i) checkEntry(parts[k], specs[k].entry, i, x[parts[k].offset + i]);
    if (specs[k].entry == Entry::Chart) checkRotation(parts[k], x);
  }
}

// Writes and reads the parts in order; a cursor keeps the layout in one place (partSpecs).
struct Cursor {
  int at = 0;
  int take(int length) {
    const int start = at;
    at += length;
    return start;
  }
};

template <class Flags>
void writeFlags(const Flags& flags, double* out) {
  for (size_t i = 0; i < flags.size(); ++i) out[i] = flags[i] ? 1.0 : 0.0;
}

template <class Flags>
void readFlags(const double* in, Flags& flags) {
  for (size_t i = 0; i < flags.size(); ++i) flags[i] = in[i] != 0.0 ? 1 : 0;
}

}  // namespace

int StateLayout::size() const { return 4 * nq + 2 * weights + 2 * contacts + 17; }

std::vector<StateLayout::Part> StateLayout::parts() const {
  std::vector<Part> out;
  int offset = 0;
  for (const PartSpec& spec : partSpecs(*this)) {
    out.push_back({spec.name, offset, spec.length});
    offset += spec.length;
  }
  return out;
}

StateLayout stateLayout(const System& system) {
  StateLayout layout;
  layout.nq = system.model->nq;
  layout.contacts = static_cast<int>(system.contacts.size());
  const int K = (system.contacts.empty() || !system.contact_model) ? 0 : system.contact_model->vertexCount();
  layout.weights = layout.contacts * K;
  return layout;
}

void flattenState(const StateLayout& layout, const SimulationState& s, Eigen::VectorXd& out) {
  const int n = layout.nq, C = layout.contacts, m = layout.weights;
  if (s.q.size() != n || s.qd.size() != n || s.q_prev.size() != n || s.qd_prev.size() != n ||
      static_cast<int>(s.contact_active.size()) != C || s.w.size() != m ||
      static_cast<int>(s.qp_warm.at_bound.size()) != m || static_cast<int>(s.qp_warm.cap.size()) != C)
    throw std::invalid_argument("flattenState: the state's sizes do not match the layout (nq = " + std::to_string(n) +
                                ", " + std::to_string(C) + " contacts, " + std::to_string(m) + " contact weights)");
  if (out.size() != layout.size()) out.resize(layout.size());
  double* x = out.data();
  Cursor c;
  x[c.take(1)] = s.time;
  Eigen::Map<Eigen::VectorXd>(x + c.take(n), n) = s.q;
  Eigen::Map<Eigen::VectorXd>(x + c.take(n), n) = s.qd;
  Eigen::Map<Eigen::VectorXd>(x + c.take(n), n) = s.q_prev;
  Eigen::Map<Eigen::VectorXd>(x + c.take(n), n) = s.qd_prev;
  x[c.take(1)] = s.h_prev;
  x[c.take(1)] = s.second_order_history ? 1.0 : 0.0;
  writeFlags(s.contact_active, x + c.take(C));
  x[c.take(1)] = s.substeps_since_touchdown;
  Eigen::Map<Mat3>(x + c.take(9)) = s.base_chart;
  x[c.take(1)] = s.beta;
  x[c.take(1)] = s.beta_start;
  Eigen::Map<Eigen::VectorXd>(x + c.take(m), m) = s.w;
  x[c.take(1)] = s.h_next;
  x[c.take(1)] = s.qp_warm_valid ? 1.0 : 0.0;
  writeFlags(s.qp_warm.at_bound, x + c.take(m));
  writeFlags(s.qp_warm.cap, x + c.take(C));
}

void unflattenState(const StateLayout& layout, const Eigen::Ref<const Eigen::VectorXd>& x, SimulationState& s) {
  checkFlat(layout, x);  // before anything is written: a refused vector leaves `s` as it was
  const int n = layout.nq, C = layout.contacts, m = layout.weights;
  const double* in = x.data();
  Cursor c;
  s.time = in[c.take(1)];
  s.q = Eigen::Map<const Eigen::VectorXd>(in + c.take(n), n);
  s.qd = Eigen::Map<const Eigen::VectorXd>(in + c.take(n), n);
  s.q_prev = Eigen::Map<const Eigen::VectorXd>(in + c.take(n), n);
  s.qd_prev = Eigen::Map<const Eigen::VectorXd>(in + c.take(n), n);
  s.h_prev = in[c.take(1)];
  s.second_order_history = in[c.take(1)] != 0.0;
  s.contact_active.resize(static_cast<size_t>(C));
  readFlags(in + c.take(C), s.contact_active);
  s.substeps_since_touchdown = static_cast<int>(in[c.take(1)]);
  s.base_chart = Eigen::Map<const Mat3>(in + c.take(9));
  s.beta = in[c.take(1)];
  s.beta_start = in[c.take(1)];
  s.w = Eigen::Map<const Eigen::VectorXd>(in + c.take(m), m);
  s.h_next = in[c.take(1)];
  s.qp_warm_valid = in[c.take(1)] != 0.0;
  s.qp_warm.at_bound.resize(static_cast<size_t>(m));
  readFlags(in + c.take(m), s.qp_warm.at_bound);
  s.qp_warm.cap.resize(static_cast<size_t>(C));
  readFlags(in + c.take(C), s.qp_warm.cap);
}

}  // namespace nmdp
