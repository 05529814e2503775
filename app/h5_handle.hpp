#pragma once
// One HDF5 handle (file, group, dataset, dataspace, type, attribute),
// closed by the function that matches its kind. HDF5's C API is what
// Debian ships for every HDF5 reader we meet (h5py, MATLAB, Keras files);
// this is the only wrapping it needs here.
#include <hdf5.h>

namespace nlsoft::console {

class H5Handle {
 public:
  H5Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~H5Handle() {
    if (id_ >= 0) close_(id_);
  }
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  H5Handle(H5Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = -1; }
  H5Handle& operator=(H5Handle&&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

}  // namespace nlsoft::console
