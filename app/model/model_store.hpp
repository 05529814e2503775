#pragma once
// A model held by the console: the shape (a shared/model.hpp Model without
// its pointer) plus the parameter vector it owns. Reading and writing go
// through shared/model_file.hpp only, so the console, firmware upload and
// the image build all see the same bytes.
#include <cstdint>
#include <string>
#include <vector>

#include "shared/capacity.hpp"
#include "shared/model.hpp"

namespace nlsoft::model {

constexpr uint8_t kNoPlatform = 255;

struct ModelFile {
  Model<HostCapacity> shape;  // params pointer unused; see view()
  std::vector<float> params;
  uint8_t platform = kNoPlatform;
  // The fit train measured (app/model/model_fit.hpp, JSON), kept in a
  // section after the model (app/model/model_section.hpp); empty: none.
  std::string fit;

  // The Model the controller and forward() take, pointing into params.
  // Valid while this object lives and params is not resized.
  Model<HostCapacity> view() const {
    Model<HostCapacity> m = shape;
    m.params = params.data();
    m.param_count = static_cast<uint32_t>(params.size());
    return m;
  }
};

// Lays out offsets, checks capacity and finiteness (finalize_model). Throws
// PipelineError with the reason.
void finalize(ModelFile& f);

// The model's bytes, what a firmware gets (also sets f.shape.hash to the
// CRC they end with); the file adds the fit section after them.
std::vector<uint8_t> encode_model(ModelFile& f);
std::vector<uint8_t> encode_model_file(ModelFile& f);
// A file's bytes: the model, and the fit section if it has one.
ModelFile decode_model(const std::vector<uint8_t>& bytes, const std::string& name);

ModelFile load_model_file(const std::string& path);
// Atomic: the old file survives any failure.
void save_model_file(const std::string& path, ModelFile& f);

const char* layer_kind_name(LayerKind k);
using ::nlsoft::activation_name;  // shared/activation.hpp
// Parses the Keras spelling ("relu", "hard_sigmoid", ...); false if unknown.
bool activation_from_name(const std::string& name, Activation* out);

}  // namespace nlsoft::model
