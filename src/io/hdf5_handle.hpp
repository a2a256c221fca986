// Internal to src/io: what the HDF5 writers and readers share on top of the C API. Included by .cpp
// files only, so hdf5.h stays out of the public headers.
#pragma once
#include <hdf5.h>

namespace nmdp::h5 {

// HDF5 prints its own error stack by default; our messages replace it.
inline void silenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

struct Handle {  // closes any HDF5 identifier
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace nmdp::h5
