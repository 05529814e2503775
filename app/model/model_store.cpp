#include "app/model/model_store.hpp"

#include <fmt/format.h>

#include <cmath>

#include "app/model/atomic_file.hpp"
#include "app/model/error.hpp"
#include "app/model/model_section.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::model {

void finalize(ModelFile& f) {
  Model<HostCapacity> m = f.view();
  const Status s = finalize_model(m);
  if (s != Status::Ok) throw PipelineError(std::string("model rejected: ") + status_name(s));
  const uint32_t hash = f.shape.hash;
  f.shape = m;
  f.shape.params = nullptr;
  f.shape.hash = hash;
}

std::vector<uint8_t> encode_model(ModelFile& f) {
  finalize(f);
  const Model<HostCapacity> m = f.view();
  std::vector<uint8_t> bytes(model_file_size(m.layer_count, m.param_count));
  if (write_model(m, f.platform, bytes.data(), bytes.size()) != bytes.size())
    throw PipelineError("model does not fit the file buffer");
  f.shape.hash = detail::rd32(bytes.data() + bytes.size() - 4);
  return bytes;
}

std::vector<uint8_t> encode_model_file(ModelFile& f) {
  std::vector<uint8_t> bytes = encode_model(f);
  if (!f.fit.empty()) {
    if (f.fit.size() + kSectionOverhead > kSectionsMax)
      throw PipelineError("the fit (" + std::to_string(f.fit.size()) + " bytes) does not fit the " +
                          std::to_string(kSectionsMax) + " bytes a model file keeps after its model");
    const std::vector<uint8_t> section = model_section(kSectionFit, f.fit);
    bytes.insert(bytes.end(), section.begin(), section.end());
  }
  return bytes;
}

namespace {

// The normalisation a file brings, before anything runs on it: a trained
// one scales each signal by the inverse of its span (dataset.cpp), so its
// scales lie within about 1e-12..1e12. A scale of 0, or one so large or
// small that a signal's span times it leaves float (3e38: every input
// saturates, the plant never moves, and nothing says why), is no model.
constexpr double kMaxNormalisation = 1e20;  // 1e20 * 1e18 stays below float's 3.4e38

void refuse_implausible_normalisation(const Model<HostCapacity>& m, const std::string& name) {
  auto check = [&](const char* what, const float* v, int count, bool scale) {
    for (int i = 0; i < count; ++i) {
      const double x = std::fabs(double(v[i]));
      const bool ok = std::isfinite(x) && x <= kMaxNormalisation && (!scale || x >= 1.0 / kMaxNormalisation);
      if (!ok)
        throw PipelineError("'" + name + "' is not a plausible model: its normalisation " + what + "[" +
                            std::to_string(i) + "] = " + fmt::format("{:g}", v[i]) +
                            (scale ? " (a scale must lie within 1e-20..1e20 in size: beyond, a signal's span "
                                     "times it leaves float's range and the controller sees nothing move)"
                                   : " (an offset must lie within +-1e20)"));
    }
  };
  check("in_offset", m.in_offset(), m.p(), false);
  check("in_scale", m.in_scale(), m.p(), true);
  check("out_offset", m.out_offset(), m.n, false);
  check("out_scale", m.out_scale(), m.n, true);
}

}  // namespace

ModelFile decode_model(const std::vector<uint8_t>& bytes, const std::string& name) {
  const ModelFileParts parts = split_model_file(bytes);
  if (parts.bad_trailer)
    throw PipelineError("'" + name + "' is not a valid model file: " + parts.fault);
  ModelFile f;
  f.fit = parts.fit;
  f.params.resize(HostCapacity::weights + 2 * Dims<HostCapacity>::p + 2 * HostCapacity::n);
  Model<HostCapacity> m;
  uint8_t platform = kNoPlatform;
  const Status s = parse_model(bytes.data(), parts.model_size, m, f.params.data(),
                               static_cast<uint32_t>(f.params.size()), &platform);
  if (s != Status::Ok) throw PipelineError("'" + name + "' is not a valid model file: " + status_name(s));
  refuse_implausible_normalisation(m, name);
  f.params.resize(m.param_count);
  f.shape = m;
  f.shape.params = nullptr;
  f.platform = platform;
  return f;
}

ModelFile load_model_file(const std::string& path) { return decode_model(read_model_bytes(path), path); }

void save_model_file(const std::string& path, ModelFile& f) { write_file_atomic(path, encode_model_file(f)); }

const char* layer_kind_name(LayerKind k) { return layer_kind_info(k).title; }

bool activation_from_name(const std::string& name, Activation* out) {
  for (uint8_t i = 0; activation_valid(i); ++i) {
    if (name == activation_name(Activation(i))) {
      *out = Activation(i);
      return true;
    }
  }
  return false;
}

}  // namespace nlsoft::model
