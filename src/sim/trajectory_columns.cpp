#include "sim/trajectory_columns.hpp"

namespace nmdp::trajectory_columns {

const ColumnSpec kColumns[] = {
    {"/time", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "s", "",
     "Simulated time of the row.", [](const TrajectoryRow& r) -> const void* { return &r.time; }},
    {"/q", ColumnType::kF64, Shape::kDof, UnitKind::kCoordinate, "", "",
     "Generalized coordinates (/joint_names): a floating base's x, y, z (world) and its chart angles "
     "base_chart_x/y/z (orientation C·Rx(a)·Ry(b)·Rz(c), C in /base/chart; not /base/rpy), then the joints.",
     [](const TrajectoryRow& r) -> const void* { return r.q.data(); }},
    {"/qdot", ColumnType::kF64, Shape::kDof, UnitKind::kRate, "", "",
     "Generalized velocities: the time derivatives of /q's columns (the base's angle rates in the row's chart).",
     [](const TrajectoryRow& r) -> const void* { return r.qdot.data(); }},
    {"/base/position", ColumnType::kF64, Shape::kThree, UnitKind::kFixed, "m", "world",
     "Position of the root link's frame (the trunk).",
     [](const TrajectoryRow& r) -> const void* { return r.base_position.data(); }},
    {"/base/rpy", ColumnType::kF64, Shape::kThree, UnitKind::kFixed, "rad", "world",
     "Roll, pitch, yaw of the root link's orientation, R = Rz(yaw)·Ry(pitch)·Rx(roll) (ZYX); not /q's chart angles.",
     [](const TrajectoryRow& r) -> const void* { return r.base_rpy.data(); }},
    {"/base/quaternion", ColumnType::kF64, Shape::kFour, UnitKind::kFixed, "1", "world",
     "Unit quaternion (x, y, z, w) of the root link's orientation, the rotation /base/rpy describes.",
     [](const TrajectoryRow& r) -> const void* { return r.base_quaternion.data(); }},
    {"/base/chart", ColumnType::kF64, Shape::kFour, UnitKind::kFixed, "1", "world",
     "Unit quaternion (x, y, z, w) of the floating base's chart C: the base body's orientation is "
     "C·Rx(a)·Ry(b)·Rz(c) with (a, b, c) the base_chart_x/y/z columns of /q (identity for other bases).",
     [](const TrajectoryRow& r) -> const void* { return r.base_chart.data(); }},
    {"/contacts/wrench", ColumnType::kF64, Shape::kContacts6, UnitKind::kWrench, "", "world",
     "[torque about the foot sphere's centre (/contacts/foot_point); force] each contact applied to the robot, "
     "averaged over the sub-steps of the step that ended at the row (0 in the first row).",
     [](const TrajectoryRow& r) -> const void* { return r.wrench.data(); }},
    {"/contacts/foot_point", ColumnType::kF64, Shape::kContacts3, UnitKind::kFixed, "m", "world",
     "Centre of each contact's foot sphere: the point the wrench's torque is about.",
     [](const TrajectoryRow& r) -> const void* { return r.foot_point.data(); }},
    {"/contacts/signed_distance", ColumnType::kF64, Shape::kContacts, UnitKind::kFixed, "m", "",
     "Signed distance of each foot sphere to the terrain, phi(centre) - radius (negative: below the surface).",
     [](const TrajectoryRow& r) -> const void* { return r.signed_distance.data(); }},
    {"/contacts/features", ColumnType::kF64, Shape::kContactsF, UnitKind::kFeatures, "", "",
     "What the contact model reads at each contact (ContactModel::features), one column per attribute "
     "`names` entry, in the units of `column_units`.",
     [](const TrajectoryRow& r) -> const void* { return r.features.data(); }},
    {"/joints/torque", ColumnType::kF64, Shape::kDof, UnitKind::kForce, "", "",
     "Generalized force the actuators applied, torque_pd + torque_feedforward (0 on base coordinates).",
     [](const TrajectoryRow& r) -> const void* { return r.torque.data(); }},
    {"/joints/torque_pd", ColumnType::kF64, Shape::kDof, UnitKind::kForce, "", "",
     "Stable PD torque -Kp (q - q_target) - Kd (qdot - qdot_target) at the row's q, qdot and targets with the "
     "config's gains: what the solver applied in the step's last sub-step (the whole step when it took one).",
     [](const TrajectoryRow& r) -> const void* { return r.torque_pd.data(); }},
    {"/joints/torque_feedforward", ColumnType::kF64, Shape::kDof, UnitKind::kForce, "", "",
     "Feed-forward torque of the PD law (controller.tau_ff, or set from Python; 0 on base coordinates).",
     [](const TrajectoryRow& r) -> const void* { return r.torque_feedforward.data(); }},
    {"/joints/q_target", ColumnType::kF64, Shape::kDof, UnitKind::kCoordinate, "", "",
     "PD position target at the row's time (NaN on unactuated coordinates).",
     [](const TrajectoryRow& r) -> const void* { return r.q_target.data(); }},
    {"/joints/qdot_target", ColumnType::kF64, Shape::kDof, UnitKind::kRate, "", "",
     "PD velocity target at the row's time (NaN on unactuated coordinates).",
     [](const TrajectoryRow& r) -> const void* { return r.qdot_target.data(); }},
    {"/energy/kinetic", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "J", "",
     "Kinetic energy of the robot, 1/2 qdot' M(q) qdot.",
     [](const TrajectoryRow& r) -> const void* { return &r.kinetic_energy; }},
    {"/energy/potential", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "J", "",
     "Gravitational potential energy -sum m g.c over the robot's bodies (c their centres of mass): zero when "
     "every centre of mass is at z = 0.",
     [](const TrajectoryRow& r) -> const void* { return &r.potential_energy; }},
    {"/links/position", ColumnType::kF64, Shape::kLinks3, UnitKind::kFixed, "m", "world",
     "Origin of every URDF link's frame (/links/names).",
     [](const TrajectoryRow& r) -> const void* { return r.link_position.data(); }},
    {"/links/quaternion", ColumnType::kF64, Shape::kLinks4, UnitKind::kFixed, "1", "world",
     "Unit quaternion (x, y, z, w) of every URDF link frame's orientation (/links/names).",
     [](const TrajectoryRow& r) -> const void* { return r.link_quaternion.data(); }},
    {"/stats/outer_iterations", ColumnType::kI32, Shape::kScalar, UnitKind::kFixed, "1", "",
     "Outer iterations of the step's solver, summed over its sub-steps and failed attempts.",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.outer_iterations; }},
    {"/stats/g_evaluations", ColumnType::kI32, Shape::kScalar, UnitKind::kFixed, "1", "",
     "Evaluations of the step's residual G (with its Jacobian counting as another).",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.g_evaluations; }},
    {"/stats/substeps", ColumnType::kI32, Shape::kScalar, UnitKind::kFixed, "1", "",
     "Accepted sub-steps of the step (1: no split).",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.substeps; }},
    {"/stats/min_substep", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "s", "",
     "Smallest accepted sub-step of the step.",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.min_substep; }},
    {"/stats/wall_time", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "s", "",
     "Wall-clock time the step took.", [](const TrajectoryRow& r) -> const void* { return &r.stats.wall_time; }},
    {"/stats/error_estimate", ColumnType::kF64, Shape::kScalar, UnitKind::kFixed, "1", "",
     "Error control's largest normalized local error of the step's sub-steps (0 with integrator.accuracy off).",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.error_estimate; }},
    {"/stats/converged", ColumnType::kU8, Shape::kScalar, UnitKind::kFixed, "1", "",
     "1 if the step converged (every stored step did), else 0.",
     [](const TrajectoryRow& r) -> const void* { return &r.stats.converged; }},
};
const int kColumnCount = static_cast<int>(sizeof kColumns / sizeof kColumns[0]);
static_assert(sizeof(bool) == 1, "/stats/converged stores StepStats::converged's byte");

ColumnDims columnDims(Shape shape, int n, int C, int F, int L) {
  const auto u = [](int v) { return static_cast<unsigned long long>(v); };
  switch (shape) {
    case Shape::kScalar: return {1, 0, 0};
    case Shape::kDof: return {2, u(n), 0};
    case Shape::kThree: return {2, 3, 0};
    case Shape::kFour: return {2, 4, 0};
    case Shape::kContacts: return {2, u(C), 0};
    case Shape::kContacts3: return {3, u(C), 3};
    case Shape::kContacts6: return {3, u(C), 6};
    case Shape::kContactsF: return {3, u(C), u(F)};
    case Shape::kLinks3: return {3, u(L), 3};
    case Shape::kLinks4: return {3, u(L), 4};
  }
  return {1, 0, 0};
}
size_t elementBytes(ColumnType type) { return type == ColumnType::kF64 ? 8 : type == ColumnType::kI32 ? 4 : 1; }

std::vector<std::string> columnUnits(const ColumnSpec& spec, const TrajectoryLayout& layout, int n) {
  std::vector<std::string> units;
  auto coordinate = [&](int j) {
    return layout.coordinate_units.empty() ? std::string("1") : layout.coordinate_units[static_cast<size_t>(j)];
  };
  switch (spec.unit_kind) {
    case UnitKind::kFixed: break;
    case UnitKind::kCoordinate:
      for (int j = 0; j < n; ++j) units.push_back(coordinate(j));
      break;
    case UnitKind::kRate:
      for (int j = 0; j < n; ++j) units.push_back(coordinate(j) + "/s");
      break;
    case UnitKind::kForce:
      for (int j = 0; j < n; ++j) units.push_back(coordinate(j) == "m" ? "N" : coordinate(j) == "rad" ? "N m" : "1");
      break;
    case UnitKind::kWrench: units = {"N m", "N m", "N m", "N", "N", "N"}; break;
    case UnitKind::kFeatures: units = layout.feature_units; break;
  }
  return units;
}
std::string joined(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out.empty() ? "1" : out;
}

}  // namespace nmdp::trajectory_columns
