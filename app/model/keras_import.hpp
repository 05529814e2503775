#pragma once
// Keras HDF5 Sequential models (Keras 2.2 .. 2.x, `model.save("x.h5")`),
// read with the HDF5 C library: the `model_config` JSON attribute gives the
// layer list, `model_weights/<layer>` (or the root, for save_weights files)
// the arrays, located through each layer group's `weight_names` attribute.
//
// Layers: InputLayer, Flatten and Dropout (identity at inference), Dense,
// GRU (reset_after true/false, recurrent_activation sigmoid/hard_sigmoid,
// one timestep). Anything else - another layer class, an unsupported
// activation or option - is refused with a message naming the layer; a
// model is never silently mis-read.
#include <string>
#include <vector>

#include "shared/model.hpp"

namespace nlsoft::model {

struct KerasNetwork {
  int inputs = 0;               // p, from the input shape
  std::vector<Layer> layers;    // offsets relative to `weights`
  std::vector<float> weights;   // shared/model.hpp weight layout
  std::vector<std::string> names;  // Keras layer name of each entry of `layers`
};

// Throws PipelineError.
KerasNetwork read_keras_h5(const std::string& path);

}  // namespace nlsoft::model
