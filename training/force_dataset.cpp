#include "training/force_dataset.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <utility>

#include "common/input_error.hpp"
#include "common/input_file.hpp"
#include "common/limits.hpp"
#include "contact_models/file_attributes.hpp"
#include "contact_models/planar_wrench_model.hpp"
#include "io/hdf5_file.hpp"
#include "common/text.hpp"

namespace nmdp {

namespace {

constexpr int kFormatVersion = 1;
constexpr const char* kKind = "force_samples";

// Shortest readable form of a number for messages (-0.01, not -0.010000).
std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}


// A text field as messages show it: at most 60 characters.
std::string shown(const std::string& text) { return text.size() <= 60 ? text : text.substr(0, 60) + "..."; }

void checkFinite(const Eigen::MatrixXd& m, const std::string& where, const std::string& dataset) {
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      if (!std::isfinite(m(r, c)))
        throw InputError(where + ": dataset '" + dataset + "' has a non-finite value (" + num(m(r, c)) + ") at row " +
                         std::to_string(r) + ", column " + std::to_string(c));
}

void checkNames(const std::vector<std::string>& names, Eigen::Index count, const std::string& where,
                const std::string& dataset, const std::string& attribute) {
  if (static_cast<Eigen::Index>(names.size()) != count)
    throw InputError(where + ": attribute '" + attribute + "' of '" + dataset + "' lists " +
                     std::to_string(names.size()) + " entries (\"" + joinNames(names) + "\"), the dataset has " +
                     std::to_string(count) + " columns");
  for (const std::string& n : names)
    if (n.empty())
      throw InputError(where + ": attribute '" + attribute + "' of '" + dataset + "' has an empty entry (\"" +
                       joinNames(names) + "\")");
}

}  // namespace

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::vector<std::string> splitNames(const std::string& text) {
  std::vector<std::string> out;
  if (text.find_first_not_of(" \t") == std::string::npos) return out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  if (!text.empty() && text.back() == ',') out.emplace_back();
  return out;
}

void validateForceDataset(const ForceDataset& d, const std::string& where) {
  const Eigen::Index N = d.features.rows();
  if (N < 1 || d.features.cols() < 1)
    throw InputError(where + ": dataset '/features' must be N x F with N >= 1 samples and F >= 1 features, got " +
                     shapeText(N, d.features.cols()));
  if (N > limits::kMaxForceSamples)
    throw InputError(where + ": " + std::to_string(N) + " samples, more than the " + std::to_string(limits::kMaxForceSamples) +
                     " a dataset may have");
  if (d.vertex.size() != N)
    throw InputError(where + ": dataset '/vertex' has " + std::to_string(d.vertex.size()) +
                     " entries, dataset '/features' has " + std::to_string(N) + " rows: one vertex index per sample");
  if (d.wrench.rows() != N || (d.wrench.cols() != 3 && d.wrench.cols() != 6))
    throw InputError(where + ": dataset '/wrench' must be N x 3 (F_x, F_z, tau_y) or N x 6 with N = " +
                     std::to_string(N) + " (the rows of '/features'), got " + shapeText(d.wrench.rows(), d.wrench.cols()));
  checkFinite(d.features, where, "/features");
  checkFinite(d.wrench, where, "/wrench");
  for (Eigen::Index i = 0; i < N; ++i)
    if (d.vertex[i] < 0 || d.vertex[i] >= limits::kMaxVertices)
      throw InputError(where + ": dataset '/vertex' has the index " + std::to_string(d.vertex[i]) + " at row " + std::to_string(i) +
                       ", outside [0, " + std::to_string(limits::kMaxVertices - 1) + "] (a wrench space has at most " +
                       std::to_string(limits::kMaxVertices) + " vertices)");
  checkNames(d.feature_names, d.features.cols(), where, "/features", "names");
  checkNames(d.feature_units, d.features.cols(), where, "/features", "units");
  checkNames(d.wrench_names, d.wrench.cols(), where, "/wrench", "names");
  checkNames(d.wrench_units, d.wrench.cols(), where, "/wrench", "units");
  if (d.torque_centre && !(std::abs(*d.torque_centre) <= kMaxGeometryLength))
    throw InputError(where + ": attribute 'torque_centre' of '/' must be a finite length of at most " +
                     num(kMaxGeometryLength) + " m, got " + num(*d.torque_centre));
}

ForceDataset readForceDataset(const std::string& path) {
  const h5::File file = h5::File::openRead(path);
  const FileAttributes root(file, path, "/");
  const auto fail = [&](const std::string& what) { root.fail(what); };
  if (!file.hasAttribute("/", "nmdp_dataset") || file.readStringAttribute("/", "nmdp_dataset") != kKind)
    fail(std::string("not an nmdp force dataset: root attribute 'nmdp_dataset' must be \"") + kKind +
         "\" (write one with 'nmdp fit --import-csv FOLDER --out DATA.h5')");
  root.checkFormatVersion(kFormatVersion);
  ForceDataset d;
  // /vertex first: its length (one per sample) bounds what the other datasets may hold.
  const Eigen::MatrixXd vertex = file.readMatrix("/vertex", limits::kMaxForceSamples);
  if (vertex.cols() != 1)
    fail("dataset '/vertex' must be 1-D (one index per sample), got " + shapeText(vertex.rows(), vertex.cols()));
  d.vertex.resize(vertex.rows());
  for (Eigen::Index i = 0; i < vertex.rows(); ++i) {
    const double v = vertex(i, 0);
    if (!std::isfinite(v) || v != std::round(v) || v < 0 || v >= limits::kMaxVertices)
      fail("dataset '/vertex' must hold integers in [0, " + std::to_string(limits::kMaxVertices - 1) + "], got " + num(v) +
           " at row " + std::to_string(i));
    d.vertex[i] = static_cast<int>(v);
  }
  constexpr Eigen::Index kMostColumns = 64;  // real datasets have 2-4 feature and 3 wrench columns
  d.features = file.readMatrix("/features", std::max<Eigen::Index>(vertex.size() * kMostColumns, kMostColumns));
  d.wrench = file.readMatrix("/wrench", std::max<Eigen::Index>(vertex.size() * kMostColumns, kMostColumns));
  for (const char* dataset : {"/features", "/wrench"})
    for (const char* attribute : {"names", "units"})
      if (!file.hasAttribute(dataset, attribute))
        fail(std::string("attribute '") + attribute + "' of '" + dataset +
             "' is missing (a comma-separated string, one entry per column)");
  d.feature_names = splitNames(file.readStringAttribute("/features", "names"));
  d.feature_units = splitNames(file.readStringAttribute("/features", "units"));
  d.wrench_names = splitNames(file.readStringAttribute("/wrench", "names"));
  d.wrench_units = splitNames(file.readStringAttribute("/wrench", "units"));
  if (file.hasAttribute("/", "source")) d.source = file.readStringAttribute("/", "source");
  if (file.hasAttribute("/", "torque_centre")) d.torque_centre = file.readDoubleAttribute("/", "torque_centre");
  validateForceDataset(d, path);
  return d;
}

void writeForceDataset(const std::string& path, const ForceDataset& d) {
  validateForceDataset(d, path);
  h5::File file = h5::File::createAtomic(path);
  file.writeStringAttribute("/", "nmdp_dataset", kKind);
  file.writeDoubleAttribute("/", "format_version", kFormatVersion);
  file.writeStringAttribute("/", "source", d.source);
  if (d.torque_centre) file.writeDoubleAttribute("/", "torque_centre", *d.torque_centre);
  file.writeMatrix("/features", d.features);
  file.writeStringAttribute("/features", "names", joinNames(d.feature_names));
  file.writeStringAttribute("/features", "units", joinNames(d.feature_units));
  file.writeIntegerVector("/vertex", d.vertex);
  file.writeMatrix("/wrench", d.wrench);
  file.writeStringAttribute("/wrench", "names", joinNames(d.wrench_names));
  file.writeStringAttribute("/wrench", "units", joinNames(d.wrench_units));
  file.commit();
}

// ----- the sand_samples CSV layout ------------------------------------------------------------

namespace {

struct CsvTable {
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;  // 1-based line of each row
};

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

bool parseDouble(const std::string& token, double* x) {
  const char* begin = token.data();
  const char* end = token.data() + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto r = std::from_chars(begin, end, *x);
  return begin != end && r.ec == std::errc() && r.ptr == end;
}

// A CSV file whose first line is exactly `header` (after trimming each field) and whose other
// non-blank lines hold as many finite numbers.
CsvTable readCsv(const std::string& path, const std::vector<std::string>& header) {
  std::istringstream in(readInputFile(path, "CSV file"));
  CsvTable t;
  std::string line;
  int number = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    std::vector<std::string> fields;
    std::string field;
    std::istringstream s(line);
    while (std::getline(s, field, ',')) fields.push_back(trim(field));
    if (!line.empty() && trim(line).back() == ',') fields.emplace_back();
    if (!have_header) {
      if (fields != header)
        throw InputError(path + ":" + std::to_string(number) + ": the header must be \"" + joinNames(header) +
                         "\" (comma-separated), got \"" + shown(trim(line)) + "\"");
      have_header = true;
      continue;
    }
    if (fields.size() != header.size())
      throw InputError(path + ":" + std::to_string(number) + ": expected " + std::to_string(header.size()) +
                       " comma-separated numbers (" + joinNames(header) + "), got " + std::to_string(fields.size()));
    std::vector<double> row(fields.size());
    for (size_t c = 0; c < fields.size(); ++c) {
      if (!parseDouble(fields[c], &row[c]))
        throw InputError(path + ":" + std::to_string(number) + ": column '" + header[c] + "': '" + shown(fields[c]) +
                         "' is not a number");
      if (!std::isfinite(row[c]))
        throw InputError(path + ":" + std::to_string(number) + ": column '" + header[c] + "': non-finite value '" +
                         shown(fields[c]) + "'");
    }
    if (static_cast<std::int64_t>(t.rows.size()) >= limits::kMaxForceSamples)
      throw InputError(path + ":" + std::to_string(number) + ": more than " + std::to_string(limits::kMaxForceSamples) +
                       " rows, more than a dataset may have");
    t.rows.push_back(std::move(row));
    t.lines.push_back(number);
  }
  if (!have_header) throw InputError(path + ": empty file (expected the header \"" + joinNames(header) + "\")");
  if (t.rows.empty()) throw InputError(path + ": no data rows after the header");
  return t;
}

// scalars.txt: "name value" lines.
std::map<std::string, double> readScalars(const std::string& path) {
  std::istringstream in(readInputFile(path, "scalars file"));
  std::map<std::string, double> out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    std::istringstream s(line);
    std::string name, value, extra;
    s >> name >> value;
    double x = 0;
    if (value.empty() || (s >> extra) || !parseDouble(value, &x) || !std::isfinite(x))
      throw InputError(path + ":" + std::to_string(number) + ": expected 'name value', got \"" + shown(trim(line)) + "\"");
    out[name] = x;
  }
  return out;
}

int countScalar(const std::map<std::string, double>& scalars, const std::string& name, const std::string& path,
                int most) {
  const auto it = scalars.find(name);
  if (it == scalars.end()) throw InputError(path + ": '" + name + "' is missing");
  if (it->second != std::round(it->second) || it->second < 1 || it->second > most)
    throw InputError(path + ": '" + name + "' must be an integer in [1, " + std::to_string(most) + "], got " + num(it->second));
  return static_cast<int>(it->second);
}

}  // namespace

ForceDataset importSandSamplesCsv(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError(displayPath(folder) + ": not a folder (expected features.csv, wrench_samples.csv and scalars.txt)");
  const std::string features_path = (fs::path(folder) / "features.csv").string();
  const std::string samples_path = (fs::path(folder) / "wrench_samples.csv").string();
  const std::string scalars_path = (fs::path(folder) / "scalars.txt").string();
  const CsvTable points = readCsv(features_path, {"depth", "theta"});
  const CsvTable samples = readCsv(samples_path, {"depth", "theta", "vel_index", "fx", "fz", "wy"});
  const std::map<std::string, double> scalars = readScalars(scalars_path);
  const int K = countScalar(scalars, "Nvel", scalars_path, limits::kMaxVertices);
  const int P = countScalar(scalars, "Ntheta", scalars_path, static_cast<int>(limits::kMaxForceSamples));
  if (static_cast<int>(points.rows.size()) != P)
    throw InputError(features_path + ": " + std::to_string(points.rows.size()) + " feature points, " + scalars_path +
                     " says Ntheta " + std::to_string(P));

  std::map<std::pair<double, double>, int> index;  // (depth, theta) → point
  for (size_t p = 0; p < points.rows.size(); ++p) {
    const auto key = std::make_pair(points.rows[p][0], points.rows[p][1]);
    if (!index.emplace(key, static_cast<int>(p)).second)
      throw InputError(features_path + ":" + std::to_string(points.lines[p]) + ": the point (" + num(key.first) + ", " +
                       num(key.second) + ") is listed twice");
  }
  // seen[p][v] = line of the sample of vertex v at point p (0 = none yet).
  std::vector<std::vector<int>> seen(P, std::vector<int>(K, 0));
  ForceDataset d;
  const Eigen::Index N = static_cast<Eigen::Index>(samples.rows.size());
  d.features.resize(N, 2);
  d.vertex.resize(N);
  d.wrench.resize(N, 3);
  for (Eigen::Index i = 0; i < N; ++i) {
    const std::vector<double>& r = samples.rows[i];
    const std::string at = samples_path + ":" + std::to_string(samples.lines[i]) + ": ";
    const auto it = index.find({r[0], r[1]});
    if (it == index.end())
      throw InputError(at + "the point (depth " + num(r[0]) + ", theta " + num(r[1]) + ") is not listed in " +
                       features_path);
    if (r[2] != std::round(r[2]) || r[2] < 0 || r[2] >= K)
      throw InputError(at + "column 'vel_index' must be an integer in [0, " + std::to_string(K - 1) + "] (Nvel " +
                       std::to_string(K) + " in " + scalars_path + "), got " + num(r[2]));
    const int v = static_cast<int>(r[2]);
    int& line = seen[it->second][v];
    if (line != 0)
      throw InputError(at + "duplicate sample: vel_index " + num(v) + " at this point is also on line " +
                       std::to_string(line));
    line = samples.lines[i];
    d.features.row(i) << r[0], r[1];
    d.vertex[i] = v;
    d.wrench.row(i) << r[3], r[4], r[5];
  }
  for (int p = 0; p < P; ++p)
    for (int v = 0; v < K; ++v)
      if (seen[p][v] == 0)
        throw InputError(samples_path + ": no sample of vel_index " + num(v) + " at the point (depth " +
                         num(points.rows[p][0]) + ", theta " + num(points.rows[p][1]) + ") of " + features_path + ":" +
                         std::to_string(points.lines[p]) + " (every point needs Nvel = " + std::to_string(K) +
                         " samples)");
  applySampleLayout(d, planarSampleLayout());
  d.source = "imported from " + folder + " (depth -> phi, theta -> beta, vel_index -> vertex, fx, fz, wy)";
  if (const auto it = scalars.find("cT"); it != scalars.end()) d.torque_centre = it->second;
  validateForceDataset(d, samples_path);
  return d;
}

const SampleLayout& planarSampleLayout() {
  static const SampleLayout layout{{"phi", "beta"}, {"m", "rad"}, {"F_x", "F_z", "tau_y"}, {"N", "N", "N m"}};
  return layout;
}

const SampleLayout& spatialSampleLayout() {
  static const SampleLayout layout{{"phi", "beta", "gamma"},
                                   {"m", "rad", "rad"},
                                   {"tau_x", "tau_y", "tau_z", "F_x", "F_y", "F_z"},
                                   {"N m", "N m", "N m", "N", "N", "N"}};
  return layout;
}

void applySampleLayout(ForceDataset& data, const SampleLayout& layout) {
  data.feature_names = layout.feature_names;
  data.feature_units = layout.feature_units;
  data.wrench_names = layout.wrench_names;
  data.wrench_units = layout.wrench_units;
}

}  // namespace nmdp
