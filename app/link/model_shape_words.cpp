#include "app/link/model_shape_words.hpp"

#include <fmt/format.h>

#include <cstring>

#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::printable;

namespace p = nlsoft::protocol;

std::string shape_words(const p::WireShape& s, int input) {
  bool all_dense = true;
  for (uint8_t l = 0; l < s.layers; ++l) all_dense = all_dense && s.kind[l] == p::kShapeDense;
  std::string w = all_dense ? fmt::format("Dense {}", input) : std::to_string(input);
  for (uint8_t l = 0; l < s.layers; ++l) {
    if (all_dense) w += fmt::format("->{}", s.units[l]);
    else if (const LayerKindInfo* k = find_layer_kind(s.kind[l])) w += fmt::format("->{}({})", k->title, s.units[l]);
    else w += fmt::format("->?({})", s.units[l]);
  }
  return w;
}

namespace {

int input_length(const p::RigInfo& r) { return int(r.nd) * r.m + int(r.dd) * r.n + r.w; }

std::string limits_words(const p::RigInfo& r) {
  return fmt::format("any shape within {} layers, {} wide (a GRU layer 3 x its units), {} weights", r.max_layers,
                     r.max_width, r.max_weights);
}

}  // namespace

std::string accepted_words(const p::RigInfo& rig) {
  if (rig.accept == p::shape_accept::kAny) return limits_words(rig);
  if (!p::shapes_well_formed(rig.shapes, rig.shapes_size)) return "no model (its shape list is malformed)";
  std::string w;
  size_t pos = 0;
  p::WireShape s;
  while (p::next_shape(rig.shapes, rig.shapes_size, pos, s))
    w += (w.empty() ? "" : " or ") + shape_words(s, input_length(rig));
  return w.empty() ? "no model (it lists no shape)" : w + " only";
}

std::optional<std::string> shape_refusal(const std::string& file, const std::vector<uint8_t>& bytes,
                                         const p::RigInfo& rig) {
  p::ModelShape s;
  // Not a model header: the file's parser says what is wrong.
  if (bytes.size() < 5 || std::memcmp(bytes.data(), "NLSM", 4) != 0 || bytes[4] != kModelFormatVersion ||
      !p::model_shape(bytes.data(), bytes.size(), s))
    return std::nullopt;
  const p::ShapeVerdict v = p::accepts(rig, s);
  if (v == p::ShapeVerdict::OtherDims) return std::nullopt;  // the caller's dimension check names it
  if (v == p::ShapeVerdict::Accepted && (rig.accept == p::shape_accept::kAny ||
                                         p::shapes_well_formed(rig.shapes, rig.shapes_size)))
    return std::nullopt;
  const int input = int(s.nd) * s.m + int(s.dd) * s.n + s.w;
  std::string is = shape_words(s.layers, input);
  switch (v) {
    case p::ShapeVerdict::TooManyLayers: is += fmt::format(" ({} layers)", s.layers.layers); break;
    case p::ShapeVerdict::TooWide: is += fmt::format(" (a layer {} wide)", s.widest); break;
    case p::ShapeVerdict::TooManyWeights: is += fmt::format(" ({} weights)", s.weights); break;
    default:
      if (s.nd != rig.nd || s.dd != rig.nd) is += fmt::format(" (history nd={} dd={})", s.nd, s.dd);
      break;
  }
  const std::string name = rig.rig_name[0] ? printable(rig.rig_name) : std::string("unnamed");
  return fmt::format("{} is {}; this firmware (rig {}) accepts {}", printable(file), is, name, accepted_words(rig));
}

}  // namespace nlsoft::console
