#pragma once
// Test support: writes Keras-layout HDF5 files with the HDF5 C library, the
// way h5py does it (fixed-length or variable-length string attributes,
// float32 weight arrays, optionally nested under a cell group).
#include <hdf5.h>

#include <algorithm>
#include <string>
#include <vector>

namespace nlsoft::test {

class H5Writer {
 public:
  explicit H5Writer(const std::string& path) {
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    weights_ = H5Gcreate2(file_, "model_weights", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  }
  ~H5Writer() {
    H5Gclose(weights_);
    H5Fclose(file_);
  }
  bool ok() const { return file_ >= 0 && weights_ >= 0; }

  void config(const std::string& json, bool variable_length) {
    string_attribute(file_, "model_config", {json}, variable_length, false);
    string_attribute(file_, "keras_version", {"2.4.0"}, variable_length, false);
  }

  // weight_names as h5py writes them: an array of fixed-length strings.
  void layer(const std::string& name, const std::vector<std::string>& weight_names) {
    const hid_t g = H5Gcreate2(weights_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    string_attribute(g, "weight_names", weight_names, false, true);
    H5Gclose(g);
  }

  void array(const std::string& layer_name, const std::string& path, const std::vector<hsize_t>& dims,
             const std::vector<float>& values) {
    const hid_t g = H5Gopen2(weights_, layer_name.c_str(), H5P_DEFAULT);
    const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    const hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
    const hid_t ds = H5Dcreate2(g, path.c_str(), H5T_IEEE_F32LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Dclose(ds);
    H5Sclose(space);
    H5Pclose(lcpl);
    H5Gclose(g);
  }

 private:
  static void string_attribute(hid_t obj, const char* name, const std::vector<std::string>& v, bool vlen, bool array) {
    const hid_t type = H5Tcopy(H5T_C_S1);
    size_t longest = 1;
    for (const std::string& s : v) longest = std::max(longest, s.size());
    H5Tset_size(type, vlen ? H5T_VARIABLE : longest);
    const hsize_t n = v.size();
    const hid_t space = array ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_SCALAR);
    const hid_t attr = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    if (vlen) {
      std::vector<const char*> ptrs;
      for (const std::string& s : v) ptrs.push_back(s.c_str());
      H5Awrite(attr, type, ptrs.data());
    } else {
      std::vector<char> buf(longest * v.size(), '\0');
      for (size_t i = 0; i < v.size(); ++i) std::copy(v[i].begin(), v[i].end(), buf.begin() + long(i * longest));
      H5Awrite(attr, type, buf.data());
    }
    H5Aclose(attr);
    H5Sclose(space);
    H5Tclose(type);
  }

  hid_t file_ = -1, weights_ = -1;
};

}  // namespace nlsoft::test
