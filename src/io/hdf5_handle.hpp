// Internal to src/io: what the HDF5 writers and readers share on top of the C API. Included by .cpp
// files only, so hdf5.h stays out of the public headers.
#pragma once
#include <hdf5.h>

#include <string>

namespace nmdp::h5 {

// HDF5 prints its own error stack by default; our messages replace it.
inline void silenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// Opens an HDF5 file read-only; -1 if it cannot be opened. A trajectory whose writer was killed is
// still marked open for writing by its SWMR writer (sim/trajectory_writer.hpp): plain opening refuses
// it ("file is already open for write") and SWMR reading (H5F_ACC_SWMR_READ, h5py's swmr=True) opens
// it, so that is tried second. A SWMR reader retries a metadata block whose checksum fails, as one
// the writer may be rewriting, with a sleep that doubles each time; 100 tries by default (hours):
// 12 here (about 4 ms), so a damaged file is an error, not a hang.
inline hid_t openReadOnly(const std::string& path) {
  silenceHdf5();
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id >= 0) return id;
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_metadata_read_attempts(fapl, 12);
  const hid_t swmr = H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
  H5Pclose(fapl);
  return swmr;
}

struct Handle {  // closes any HDF5 identifier
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace nmdp::h5
