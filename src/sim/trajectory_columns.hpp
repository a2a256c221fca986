// The per-row datasets of a run file: one table, so that every dataset has its shape, units,
// description and frame in one place (README "Usage" shows the same table). Internal to the
// trajectory writer (sim/trajectory_writer.cpp).
#pragma once
#include <string>
#include <vector>

#include "sim/trajectory_writer.hpp"

namespace nmdp::trajectory_columns {

enum class ColumnType { kF64, kI32, kU8 };
enum class Shape { kScalar, kDof, kThree, kFour, kContacts, kContacts3, kContacts6, kContactsF, kLinks3, kLinks4 };
// How the units are found: one string for every column, or per column from the layout.
enum class UnitKind { kFixed, kCoordinate, kRate, kForce, kWrench, kFeatures };

struct ColumnSpec {
  const char* path;
  ColumnType type;
  Shape shape;
  UnitKind unit_kind;
  const char* units;  // kFixed
  const char* frame;  // "" when the dataset has none
  const char* description;
  const void* (*source)(const TrajectoryRow&);
};

// Rank and the dimensions after the rows.
struct ColumnDims {
  int rank;
  unsigned long long d1, d2;
};

extern const ColumnSpec kColumns[];
extern const int kColumnCount;

ColumnDims columnDims(Shape shape, int n, int C, int F, int L);
size_t elementBytes(ColumnType type);
// Per column units where they differ (empty: `units` alone).
std::vector<std::string> columnUnits(const ColumnSpec& spec, const TrajectoryLayout& layout, int n);
// The summary `units`: the parts joined by ", " ("1" when there are none).
std::string joined(const std::vector<std::string>& parts);

}  // namespace nmdp::trajectory_columns
