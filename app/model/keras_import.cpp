#include "app/model/keras_import.hpp"

#include <hdf5.h>

#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "app/h5_handle.hpp"
#include "host/files/input_file.hpp"
#include "app/model/error.hpp"
#include "app/model/model_store.hpp"

namespace nlsoft::model {
namespace {

using nlohmann::json;

using Handle = console::H5Handle;

std::vector<std::string> read_string_attribute(hid_t obj, const char* name, const std::string& where) {
  if (H5Aexists(obj, name) <= 0) throw PipelineError(where + ": no '" + name + "' attribute");
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (!attr.ok() || !type.ok() || !space.ok() || H5Tget_class(type.get()) != H5T_STRING)
    throw PipelineError(where + ": attribute '" + name + "' is not a string");
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  std::vector<std::string> out;
  if (count <= 0) return out;
  if (H5Tis_variable_str(type.get()) > 0) {
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
    std::vector<char*> ptrs(static_cast<size_t>(count), nullptr);
    if (H5Aread(attr.get(), mem.get(), ptrs.data()) < 0)
      throw PipelineError(where + ": cannot read attribute '" + name + "'");
    for (char* p : ptrs) {
      out.emplace_back(p ? p : "");
      H5free_memory(p);
    }
  } else {
    const size_t size = H5Tget_size(type.get());
    Handle mem(H5Tcopy(type.get()), H5Tclose);
    std::vector<char> buf(size * static_cast<size_t>(count) + 1, '\0');
    if (H5Aread(attr.get(), mem.get(), buf.data()) < 0)
      throw PipelineError(where + ": cannot read attribute '" + name + "'");
    for (hssize_t i = 0; i < count; ++i) {
      const char* s = buf.data() + size * static_cast<size_t>(i);
      size_t len = 0;
      while (len < size && s[len] != '\0') ++len;
      out.emplace_back(s, len);
    }
  }
  return out;
}

// A dataset as floats, with its shape.
std::vector<float> read_array(hid_t group, const std::string& path, std::vector<hsize_t>& dims,
                              const std::string& where) {
  Handle ds(H5Dopen2(group, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.ok()) throw PipelineError(where + ": missing weight array '" + path + "'");
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 4) throw PipelineError(where + ": bad shape of '" + path + "'");
  dims.assign(size_t(rank), 0);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  size_t count = 1;
  for (hsize_t d : dims) count *= size_t(d);
  std::vector<float> v(count);
  if (count > 0 && H5Dread(ds.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw PipelineError(where + ": cannot read '" + path + "' as numbers");
  return v;
}

// "gru/gru_cell/recurrent_kernel:0" -> "recurrent_kernel"
std::string weight_role(const std::string& full) {
  std::string s = full;
  const size_t colon = s.rfind(':');
  if (colon != std::string::npos) s = s.substr(0, colon);
  const size_t slash = s.rfind('/');
  return slash == std::string::npos ? s : s.substr(slash + 1);
}

std::string describe(const std::string& name, const std::string& cls) { return "layer '" + name + "' (" + cls + ")"; }

Activation activation_of(const json& cfg, const char* key, const char* fallback, const std::string& who) {
  std::string name = fallback;
  if (cfg.contains(key)) {
    if (!cfg[key].is_string()) throw PipelineError(who + ": " + key + " is not a plain activation name");
    name = cfg[key].get<std::string>();
  }
  Activation a;
  if (!activation_from_name(name, &a))
    throw PipelineError(who + ": activation '" + name + "' is not supported (linear, relu, tanh, sigmoid, hard_sigmoid)");
  return a;
}

// Last entry of a Keras shape list such as [null, 1, 36].
int last_dim(const json& shape) {
  if (!shape.is_array() || shape.empty() || !shape.back().is_number_integer()) return 0;
  return shape.back().get<int>();
}

int input_size(const json& config, const json& layers) {
  for (const json& l : layers) {
    const json& c = l.value("config", json::object());
    for (const char* key : {"batch_input_shape", "batch_shape"})
      if (c.contains(key) && last_dim(c[key]) > 0) return last_dim(c[key]);
  }
  if (config.is_object() && config.contains("build_input_shape")) return last_dim(config["build_input_shape"]);
  return 0;
}

bool flag(const json& cfg, const char* key, bool fallback) {
  return cfg.contains(key) && cfg[key].is_boolean() ? cfg[key].get<bool>() : fallback;
}

// The file's model_config: a Keras Sequential model's, parsed.
json sequential_config(hid_t file, const std::string& path) {
  const std::vector<std::string> cfg_text = read_string_attribute(file, "model_config", path);
  if (cfg_text.size() != 1) throw PipelineError(path + ": 'model_config' is not a single string");
  json model;
  try {
    model = json::parse(cfg_text[0]);
  } catch (const std::exception& e) {
    throw PipelineError(path + ": model_config is not valid JSON: " + e.what());
  }
  const std::string cls = model.value("class_name", "");
  if (cls != "Sequential")
    throw PipelineError(path + ": only Keras Sequential models are supported, this is a '" + cls + "' model");
  return model;
}

// A layer's weights by their role, with their shapes.
struct LayerWeights {
  std::vector<float> kernel, recurrent, bias;
  std::vector<hsize_t> kd, rd, bd;
};

LayerWeights read_layer_weights(hid_t root, const std::string& name, const std::string& who, const std::string& path) {
  Handle group(H5Gopen2(root, name.c_str(), H5P_DEFAULT), H5Gclose);
  if (!group.ok()) throw PipelineError(who + ": no weights group '" + name + "' in " + path);
  LayerWeights w;
  for (const std::string& wn : read_string_attribute(group.get(), "weight_names", who)) {
    const std::string role = weight_role(wn);
    if (role == "kernel") w.kernel = read_array(group.get(), wn, w.kd, who);
    else if (role == "recurrent_kernel") w.recurrent = read_array(group.get(), wn, w.rd, who);
    else if (role == "bias") w.bias = read_array(group.get(), wn, w.bd, who);
    else throw PipelineError(who + ": unexpected weight '" + wn + "'");
  }
  return w;
}

// A Dense or GRU layer of `width` inputs appended to net, its weights in the
// order the firmware reads them; the layer's units.
int add_layer(KerasNetwork& net, const std::string& lcls, const json& cfg, const std::string& who, int width,
              LayerWeights w) {
  const int units = cfg.value("units", 0);
  if (units <= 0) throw PipelineError(who + ": missing 'units'");
  const bool use_bias = flag(cfg, "use_bias", true);
  Layer L;
  L.in = static_cast<uint16_t>(width);
  L.out = static_cast<uint16_t>(units);
  L.offset = static_cast<uint32_t>(net.weights.size());
  const int cols = layer_columns(layer_kind_named(lcls.c_str())->kind, units);  // a Dense or GRU class
  if (w.kd.size() != 2 || w.kd[0] != hsize_t(width) || w.kd[1] != hsize_t(cols))
    throw PipelineError(who + ": kernel shape does not match " + std::to_string(width) + " x " + std::to_string(cols));
  if (lcls == "Dense") {
    L.kind = LayerKind::Dense;
    L.act = activation_of(cfg, "activation", "linear", who);
    net.weights.insert(net.weights.end(), w.kernel.begin(), w.kernel.end());
    if (use_bias && w.bias.size() != size_t(units)) throw PipelineError(who + ": bias shape does not match units");
    if (!use_bias) w.bias.assign(size_t(units), 0.0f);
    net.weights.insert(net.weights.end(), w.bias.begin(), w.bias.end());
  } else {
    L.kind = LayerKind::Gru;
    L.act = activation_of(cfg, "activation", "tanh", who);
    L.rec_act = activation_of(cfg, "recurrent_activation", "hard_sigmoid", who);
    L.reset_after = flag(cfg, "reset_after", false);  // Keras 2.2 had no such option: false
    if (flag(cfg, "return_sequences", false) || flag(cfg, "return_state", false))
      throw PipelineError(who + ": return_sequences / return_state are not supported (one output step only)");
    if (w.rd.size() != 2 || w.rd[0] != hsize_t(units) || w.rd[1] != hsize_t(cols))
      throw PipelineError(who + ": recurrent_kernel shape does not match " + std::to_string(units) + " x " +
                          std::to_string(cols));
    const size_t nb = size_t(L.reset_after ? 2 : 1) * size_t(cols);
    if (use_bias && w.bias.size() != nb)
      throw PipelineError(who + ": bias has " + std::to_string(w.bias.size()) + " values, expected " +
                          std::to_string(nb) + (L.reset_after ? " (reset_after: 2 x 3 units)" : ""));
    if (!use_bias) w.bias.assign(nb, 0.0f);
    net.weights.insert(net.weights.end(), w.kernel.begin(), w.kernel.end());
    net.weights.insert(net.weights.end(), w.recurrent.begin(), w.recurrent.end());
    net.weights.insert(net.weights.end(), w.bias.begin(), w.bias.end());
  }
  net.layers.push_back(L);
  return units;
}

}  // namespace

KerasNetwork read_keras_h5(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // our messages, not HDF5's stack dumps
  try {
    host::check_input_file(path, {"Keras HDF5 file", uint64_t(4) << 30});
  } catch (const host::CliError& e) {
    throw PipelineError(e.what());
  }
  if (H5Fis_hdf5(path.c_str()) <= 0) throw PipelineError("'" + path + "' is not an HDF5 file (or cannot be read)");
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw PipelineError("cannot open '" + path + "'");
  const json model = sequential_config(file.get(), path);
  const json& config = model["config"];
  // Keras 2.2 stores the layer list directly, later versions under "layers".
  const json layers = config.is_array() ? config : config.value("layers", json::array());
  if (!layers.is_array() || layers.empty()) throw PipelineError(path + ": the model has no layers");

  const bool nested = H5Lexists(file.get(), "model_weights", H5P_DEFAULT) > 0;
  Handle weights_root(nested ? H5Gopen2(file.get(), "model_weights", H5P_DEFAULT) : -1, H5Gclose);
  const hid_t root = nested ? weights_root.get() : file.get();

  KerasNetwork net;
  net.inputs = input_size(config, layers);
  if (net.inputs <= 0) throw PipelineError(path + ": cannot find the input shape (batch_input_shape)");
  int width = net.inputs;
  for (const json& l : layers) {
    const std::string lcls = l.value("class_name", "?");
    const json cfg = l.value("config", json::object());
    const std::string name = cfg.value("name", "?");
    const std::string who = describe(name, lcls);
    if (lcls == "InputLayer" || lcls == "Dropout") continue;
    if (lcls == "Flatten") continue;  // (1, p) -> p: same numbers in the same order
    if (lcls != "Dense" && lcls != "GRU")
      throw PipelineError(who + " is not supported; supported layers: InputLayer, Flatten, Dense, GRU, Dropout");
    width = add_layer(net, lcls, cfg, who, width, read_layer_weights(root, name, who, path));
    net.names.push_back(name);
  }
  if (net.layers.empty()) throw PipelineError(path + ": the model has no Dense or GRU layer");
  return net;
}
}  // namespace nlsoft::model
