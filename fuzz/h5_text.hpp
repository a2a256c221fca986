// HDF5 files described as text, so that libFuzzer mutates what nmdp's model and dataset readers
// interpret (names, shapes, types, values, attributes) rather than the container's bytes, whose
// robustness is libhdf5's own (and fuzzed upstream). One line per object, in the order created:
//
//   group <path>
//   attr <object> <name> <type> <values...>     scalar with one value, a 1-D array with several
//   dset <path> <type> <dims> [<values...>]     dims "3" or "64x3"; values fill the dataset row-major
//                                               and repeat when fewer are given; a dataset of more
//                                               than 10^5 values is chunked and left unwritten
//                                               (the fill value), so its extent costs no storage
//
// <type>: f64, f32, i64, i32, u8, str (variable-length UTF-8; values are separated by '|' to the end
// of the line), fstr (fixed-length strings, likewise). Lines that do not parse are skipped: the
// writer never fails on its own input, so every finding is the reader's.
#pragma once
#include <string>

namespace nmdp::fuzz {

// Writes the file `path` described by `text` (replacing it). HDF5 errors are silenced and ignored.
void writeHdf5FromText(const std::string& text, const std::string& path);

// The text that writeHdf5FromText turns back into an equivalent file (groups, numeric and string
// datasets and attributes); for the seed corpora. Empty if the file cannot be read.
std::string hdf5ToText(const std::string& path);

}  // namespace nmdp::fuzz
