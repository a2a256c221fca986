#include "fuzz/h5_text.hpp"

#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

namespace nmdp::fuzz {

namespace {

constexpr double kMaxWritten = 1e5;      // values written per dataset; larger ones stay unwritten
constexpr hsize_t kMaxDimension = hsize_t{1} << 40;

struct Type {
  hid_t file = -1;       // the stored type
  bool text = false;     // a string type
  bool fixed = false;    // fixed-length strings
};

Type typeNamed(const std::string& name) {
  if (name == "f64") return {H5T_IEEE_F64LE};
  if (name == "f32") return {H5T_IEEE_F32LE};
  if (name == "i64") return {H5T_STD_I64LE};
  if (name == "i32") return {H5T_STD_I32LE};
  if (name == "u8") return {H5T_STD_U8LE};
  if (name == "str") return {-1, true, false};
  if (name == "fstr") return {-1, true, true};
  return {};
}

// A string type for `values`: variable length, or fixed to the longest plus a NUL.
hid_t stringType(bool fixed, const std::vector<std::string>& values) {
  const hid_t t = H5Tcopy(H5T_C_S1);
  size_t longest = 1;
  for (const std::string& v : values) longest = std::max(longest, v.size() + 1);
  H5Tset_size(t, fixed ? longest : H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

// Writes strings through a type made by stringType().
herr_t writeStrings(hid_t target, bool attribute, hid_t type, bool fixed, const std::vector<std::string>& values) {
  if (fixed) {
    const size_t width = H5Tget_size(type);
    std::vector<char> buffer(width * std::max<size_t>(values.size(), 1), '\0');
    for (size_t i = 0; i < values.size(); ++i) std::memcpy(&buffer[i * width], values[i].data(), std::min(width - 1, values[i].size()));
    return attribute ? H5Awrite(target, type, buffer.data()) : H5Dwrite(target, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data());
  }
  std::vector<const char*> raw;
  for (const std::string& v : values) raw.push_back(v.c_str());
  if (raw.empty()) raw.push_back("");
  return attribute ? H5Awrite(target, type, raw.data()) : H5Dwrite(target, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
}

std::vector<std::string> splitBars(const std::string& rest) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(rest);
  while (std::getline(in, item, '|')) out.push_back(item);
  return out;
}

std::vector<double> numbers(std::istringstream& in) {
  std::vector<double> out;
  std::string token;
  while (in >> token && out.size() < kMaxWritten) out.push_back(std::strtod(token.c_str(), nullptr));
  return out;
}

std::string restOfLine(std::istringstream& in) {
  std::string rest;
  std::getline(in, rest);
  const size_t first = rest.find_first_not_of(' ');
  return first == std::string::npos ? std::string() : rest.substr(first);
}

hid_t linkCreation() {
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  return lcpl;
}

void attribute(hid_t file, std::istringstream& in) {
  std::string object, name, type_name;
  if (!(in >> object >> name >> type_name)) return;
  const Type type = typeNamed(type_name);
  if (type.file < 0 && !type.text) return;
  const hid_t target = H5Oopen(file, object.c_str(), H5P_DEFAULT);
  if (target < 0) return;
  if (H5Aexists(target, name.c_str()) > 0) H5Adelete(target, name.c_str());
  if (type.text) {
    const std::vector<std::string> values = splitBars(restOfLine(in));
    const hsize_t n = values.size();
    const hid_t space = n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr);
    const hid_t t = stringType(type.fixed, values);
    const hid_t a = H5Acreate2(target, name.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      writeStrings(a, true, t, type.fixed, values);
      H5Aclose(a);
    }
    H5Tclose(t);
    H5Sclose(space);
  } else {
    std::vector<double> values = numbers(in);
    if (values.empty()) values.push_back(0.0);
    const hsize_t n = values.size();
    const hid_t space = n == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr);
    const hid_t a = H5Acreate2(target, name.c_str(), type.file, space, H5P_DEFAULT, H5P_DEFAULT);
    if (a >= 0) {
      H5Awrite(a, H5T_NATIVE_DOUBLE, values.data());
      H5Aclose(a);
    }
    H5Sclose(space);
  }
  H5Oclose(target);
}

void dataset(hid_t file, std::istringstream& in) {
  std::string path, type_name, dims_text;
  if (!(in >> path >> type_name >> dims_text)) return;
  const Type type = typeNamed(type_name);
  if (type.file < 0 && !type.text) return;
  std::vector<hsize_t> dims;
  std::istringstream d(dims_text);
  std::string item;
  double count = 1.0;
  while (std::getline(d, item, 'x') && dims.size() < 4) {
    const double v = std::strtod(item.c_str(), nullptr);
    const hsize_t n = std::isfinite(v) && v > 0 ? static_cast<hsize_t>(std::min<double>(v, kMaxDimension)) : 0;
    dims.push_back(n);
    count *= static_cast<double>(n);
  }
  if (dims.empty()) return;
  const hid_t lcpl = linkCreation();
  if (type.text) {
    const std::vector<std::string> values = splitBars(restOfLine(in));
    const hsize_t n = values.size();
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t t = stringType(type.fixed, values);
    const hid_t ds = H5Dcreate2(file, path.c_str(), t, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    if (ds >= 0) {
      if (n > 0) writeStrings(ds, false, t, type.fixed, values);
      H5Dclose(ds);
    }
    H5Tclose(t);
    H5Sclose(space);
    H5Pclose(lcpl);
    return;
  }
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const bool written = count <= kMaxWritten;
  if (!written) {  // an extent that costs nothing: chunked, never allocated
    std::vector<hsize_t> chunk(dims.size());
    for (size_t i = 0; i < dims.size(); ++i) chunk[i] = std::max<hsize_t>(1, std::min<hsize_t>(dims[i], 64));
    H5Pset_chunk(dcpl, static_cast<int>(chunk.size()), chunk.data());
  }
  const hid_t ds = H5Dcreate2(file, path.c_str(), type.file, space, lcpl, dcpl, H5P_DEFAULT);
  if (ds >= 0) {
    if (written && count > 0) {
      std::vector<double> values = numbers(in);
      if (values.empty()) values.push_back(0.0);
      std::vector<double> filled(static_cast<size_t>(count));
      for (size_t i = 0; i < filled.size(); ++i) filled[i] = values[i % values.size()];
      H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, filled.data());
    }
    H5Dclose(ds);
  }
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Pclose(lcpl);
}

// ----- dumping ------------------------------------------------------------------------------------

std::string typeText(hid_t type) {
  const H5T_class_t c = H5Tget_class(type);
  const size_t size = H5Tget_size(type);
  if (c == H5T_FLOAT) return size == 4 ? "f32" : "f64";
  if (c == H5T_INTEGER) return size == 1 ? "u8" : size == 4 ? "i32" : "i64";
  if (c == H5T_STRING) return H5Tis_variable_str(type) > 0 ? "str" : "fstr";
  return "";
}

std::string numberText(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

// The values of a dataset or attribute as the text after its type (numbers, or '|'-separated strings).
std::string valuesText(hid_t target, bool attribute, hid_t stored, hssize_t n) {
  std::ostringstream out;
  if (n <= 0) return "";
  if (H5Tget_class(stored) == H5T_STRING) {
    const bool variable = H5Tis_variable_str(stored) > 0;
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_cset(t, H5Tget_cset(stored));
    std::vector<std::string> values;
    if (variable) {
      H5Tset_size(t, H5T_VARIABLE);
      std::vector<char*> raw(static_cast<size_t>(n), nullptr);
      const herr_t ok = attribute ? H5Aread(target, t, raw.data()) : H5Dread(target, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
      for (char* s : raw) {
        values.emplace_back(ok >= 0 && s ? s : "");
        if (s) H5free_memory(s);
      }
    } else {
      const size_t width = H5Tget_size(stored);
      H5Tset_size(t, width);
      std::vector<char> raw(width * static_cast<size_t>(n), '\0');
      if ((attribute ? H5Aread(target, t, raw.data()) : H5Dread(target, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data())) >= 0)
        for (hssize_t i = 0; i < n; ++i) values.emplace_back(std::string(&raw[static_cast<size_t>(i) * width], width).c_str());
    }
    H5Tclose(t);
    for (size_t i = 0; i < values.size(); ++i) out << (i ? "|" : " ") << values[i];
    return out.str();
  }
  std::vector<double> values(static_cast<size_t>(n));
  const herr_t ok = attribute ? H5Aread(target, H5T_NATIVE_DOUBLE, values.data())
                              : H5Dread(target, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  if (ok < 0) return "";
  for (double v : values) out << ' ' << numberText(v);
  return out.str();
}

struct Dump {
  std::ostringstream text;
};

herr_t dumpAttribute(hid_t object, const char* name, const H5A_info_t*, void* data) {
  Dump& dump = *static_cast<Dump*>(data);
  const hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  if (a < 0) return 0;
  const hid_t stored = H5Aget_type(a);
  const hid_t space = H5Aget_space(a);
  const std::string type = typeText(stored);
  char object_name[1024] = "/";
  H5Iget_name(object, object_name, sizeof object_name);
  if (!type.empty())
    dump.text << "attr " << object_name << ' ' << name << ' ' << type
              << valuesText(a, true, stored, H5Sget_simple_extent_npoints(space)) << '\n';
  H5Sclose(space);
  H5Tclose(stored);
  H5Aclose(a);
  return 0;
}

herr_t dumpObject(hid_t file, const char* name, const H5O_info_t* info, void* data) {
  Dump& dump = *static_cast<Dump*>(data);
  const std::string path = std::string(name) == "." ? "/" : "/" + std::string(name);
  const hid_t object = H5Oopen(file, path.c_str(), H5P_DEFAULT);
  if (object < 0) return 0;
  if (info->type == H5O_TYPE_GROUP && path != "/") dump.text << "group " << path << '\n';
  if (info->type == H5O_TYPE_DATASET) {
    const hid_t stored = H5Dget_type(object);
    const hid_t space = H5Dget_space(object);
    const std::string type = typeText(stored);
    const int rank = H5Sget_simple_extent_ndims(space);
    if (!type.empty() && rank >= 1 && rank <= 4) {
      hsize_t dims[4] = {0, 0, 0, 0};
      H5Sget_simple_extent_dims(space, dims, nullptr);
      dump.text << "dset " << path << ' ' << type << ' ';
      for (int i = 0; i < rank; ++i) dump.text << (i ? "x" : "") << dims[i];
      dump.text << valuesText(object, false, stored, H5Sget_simple_extent_npoints(space)) << '\n';
    }
    H5Sclose(space);
    H5Tclose(stored);
  }
  H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, dumpAttribute, &dump);
  H5Oclose(object);
  return 0;
}

}  // namespace

void writeHdf5FromText(const std::string& text, const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) return;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string verb;
    if (!(in >> verb)) continue;
    if (verb == "group") {
      std::string group;
      if (!(in >> group)) continue;
      const hid_t lcpl = linkCreation();
      const hid_t g = H5Gcreate2(file, group.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT);
      if (g >= 0) H5Gclose(g);
      H5Pclose(lcpl);
    } else if (verb == "attr") {
      attribute(file, in);
    } else if (verb == "dset") {
      dataset(file, in);
    }
  }
  H5Fclose(file);
}

std::string hdf5ToText(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return "";
  Dump dump;
  H5Ovisit(file, H5_INDEX_NAME, H5_ITER_INC, dumpObject, &dump);
  H5Fclose(file);
  return dump.text.str();
}

}  // namespace nmdp::fuzz
