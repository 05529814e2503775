#pragma once
// RIG_INFO's model shapes (PROTOCOL.md 7, "RIG_INFO"): the shape list's
// bytes, the list an image's compile-time kernels make (Cap::Shapes), a
// model file's shape read from its header, and the one verdict both ends
// give on it: the console before it sends a byte of a model, the firmware
// at XFER_BEGIN and at the chunk that carries the header.
//
// A shape is what picks a kernel (shared/kernels.hpp): the layer count and
// each layer's kind and units, for the rig's m, n, w and nd = dd.
// Activations are run-time data of every kernel and not part of it.
//
//   shapes := { L u8, L x (kind u8, units u16) }     kind: 1 Dense, 2 GRU
//
// the kind codes of the model file's layer table (shared/model_file.hpp).
#include <cstddef>
#include <cstdint>

#include "protocol/messages.hpp"
#include "shared/model_file.hpp"
#include "shared/net_shape.hpp"

namespace nlsoft::protocol {

constexpr uint8_t kShapeDense = 1;
constexpr uint8_t kShapeGru = 2;
// A shape word's kind is the layer kind's number (shared/layer_kind.hpp).
static_assert(kShapeDense == uint8_t(LayerKind::Dense) && kShapeGru == uint8_t(LayerKind::Gru));
constexpr size_t kShapeLayerBytes = 3;
// The most layers one listed shape can have in kMaxShapeBytes.
constexpr uint8_t kMaxShapeLayers = (kMaxShapeBytes - 1) / kShapeLayerBytes;  // 25

struct WireShape {
  uint8_t layers = 0;
  uint8_t kind[kMaxShapeLayers] = {};
  uint16_t units[kMaxShapeLayers] = {};
};

// ------------------------------------------------ list from Cap::Shapes

namespace detail {

template <class Layer>
constexpr size_t put_layer(uint8_t* out, size_t at) {
  out[at] = uint8_t(Layer::kind);
  out[at + 1] = uint8_t(Layer::units & 0xFF);
  out[at + 2] = uint8_t(Layer::units >> 8);
  return at + kShapeLayerBytes;
}

template <class S>
struct ShapeBytes;
template <int M, int N, int W, int ND, class First, class... Rest>
struct ShapeBytes<NetShape<M, N, W, ND, First, Rest...>> {
  static constexpr size_t size = 1 + kShapeLayerBytes * (1 + sizeof...(Rest));
  // Appends the shape when it is one for these dimensions; returns the new end,
  // or cap + 1 when it does not fit.
  static constexpr size_t put(int m, int n, int w, int nd, uint8_t* out, size_t at, size_t cap) {
    if (M != m || N != n || W != w || ND != nd || at > cap) return at;
    if (at + size > cap) return cap + 1;
    out[at++] = uint8_t(1 + sizeof...(Rest));
    at = put_layer<First>(out, at);
    ((at = put_layer<Rest>(out, at)), ...);
    return at;
  }
};

}  // namespace detail

// The wire list of the shapes in `list` that are shapes for dimensions m, n,
// w, nd (a capacity may carry kernels for other rigs: HostCapacity does).
// Returns the byte count, or 0 when they do not fit in cap; constexpr so an
// image can check its list at compile time.
// (An empty list reads none of its arguments.)
template <class... S>
constexpr size_t write_shapes(ShapeList<S...>, [[maybe_unused]] int m, [[maybe_unused]] int n,
                              [[maybe_unused]] int w, [[maybe_unused]] int nd, [[maybe_unused]] uint8_t* out,
                              size_t cap) {
  size_t at = 0;
  ((at = detail::ShapeBytes<S>::put(m, n, w, nd, out, at, cap)), ...);
  return at > cap ? 0 : at;
}

// Fills RIG_INFO's accepted shapes from a capacity: a generic kernel takes
// any shape within its limits, else the list of its shaped kernels for the
// rig's dimensions. `as_list` serves the list even with a generic kernel (a
// simulator standing in for an MCU image). Returns false when that list does
// not fit the message. The limits are the capacity's either way.
template <class Cap>
constexpr bool fill_accepted_shapes(RigInfo& r, bool as_list = false) {
  static_assert(Cap::layers <= kMaxShapeLayers, "max_layers beyond what a header check can name (rig_reply.hpp)");
  r.max_layers = uint8_t(Cap::layers);
  r.max_width = uint16_t(Cap::width);
  r.max_weights = uint32_t(Cap::weights);
  if (Cap::generic && !as_list) {
    r.accept = shape_accept::kAny;
    r.shapes_size = 0;
    return true;
  }
  r.accept = shape_accept::kList;
  const size_t size = write_shapes(typename Cap::Shapes{}, r.m, r.n, r.w, r.nd, r.shapes, kMaxShapeBytes);
  r.shapes_size = uint8_t(size);
  return size != 0;
}

// ---------------------------------------------------------- reading the list

// The next shape of a list at `pos`; false at its end or on a malformed entry
// (shapes_well_formed tells which).
constexpr bool next_shape(const uint8_t* bytes, size_t size, size_t& pos, WireShape& out) {
  if (pos >= size) return false;
  const uint8_t L = bytes[pos];
  if (L == 0 || L > kMaxShapeLayers || pos + 1 + kShapeLayerBytes * L > size) return false;
  out.layers = L;
  for (uint8_t l = 0; l < L; ++l) {
    const size_t at = pos + 1 + kShapeLayerBytes * l;
    out.kind[l] = bytes[at];
    out.units[l] = uint16_t(bytes[at + 1] | (bytes[at + 2] << 8));
  }
  pos += 1 + kShapeLayerBytes * L;
  return true;
}

// Whether the list parses to its last byte with layer counts >= 1, known
// kinds and units >= 1.
constexpr bool shapes_well_formed(const uint8_t* bytes, size_t size) {
  size_t pos = 0;
  WireShape s;
  while (next_shape(bytes, size, pos, s))
    for (uint8_t l = 0; l < s.layers; ++l)
      if (!layer_kind_known(s.kind[l]) || s.units[l] == 0) return false;
  return pos == size;
}

constexpr int shape_count(const RigInfo& r) {
  size_t pos = 0;
  int count = 0;
  WireShape s;
  while (next_shape(r.shapes, r.shapes_size, pos, s)) ++count;
  return count;
}

// ----------------------------------------------------- a model's shape

// What of a model file decides whether an image takes it.
struct ModelShape {
  uint8_t m = 0, n = 0, w = 0, nd = 0, dd = 0;
  WireShape layers;
  uint32_t weights = 0;  // weights and biases (the model file's GRU reset_after counted)
  uint16_t widest = 0;   // widest layer buffer: units, 3 x units for a GRU
};

// The shape from a model file's first bytes: its header and layer table
// (24 + 8 L bytes, shared/model_file.hpp). False when they are not all there,
// or name no layer or more than kMaxShapeLayers.
inline bool model_shape(const uint8_t* file, size_t len, ModelShape& out) {
  namespace at = model_offset;
  if (len < kModelHeaderSize) return false;
  const uint8_t L = file[at::kLayers];
  if (L == 0 || L > kMaxShapeLayers || len < kModelHeaderSize + kModelLayerSize * L) return false;
  ModelShape s;
  s.m = file[at::kM], s.n = file[at::kN], s.w = file[at::kW], s.nd = file[at::kNd], s.dd = file[at::kDd];
  s.layers.layers = L;
  uint64_t in = uint64_t(s.nd) * s.m + uint64_t(s.dd) * s.n + s.w, weights = 0;
  for (uint8_t l = 0; l < L; ++l) {
    const uint8_t* e = file + kModelHeaderSize + kModelLayerSize * l;
    const uint64_t u = uint64_t(e[6] | (e[7] << 8));
    const LayerKind kind = LayerKind(e[0]);  // an unknown number sized as Dense (the file's check refuses it)
    s.layers.kind[l] = e[0];
    s.layers.units[l] = uint16_t(u);
    const uint64_t cols = layer_columns(kind, u);
    weights += layer_weights(kind, in, u, e[3] != 0);
    if (cols > s.widest) s.widest = uint16_t(cols > 0xFFFF ? 0xFFFF : cols);
    in = u;
  }
  s.weights = weights > 0xFFFFFFFFu ? 0xFFFFFFFFu : uint32_t(weights);
  out = s;
  return true;
}

enum class ShapeVerdict : uint8_t {
  Accepted,
  OtherDims,      // m, n or w not the rig's (a model for another plant)
  NotListed,      // accept = list: not one of the shapes listed
  TooManyLayers,  // accept = any: beyond the limits
  TooWide,
  TooManyWeights,
};

constexpr bool same_shape(const WireShape& a, const WireShape& b) {
  if (a.layers != b.layers) return false;
  for (uint8_t l = 0; l < a.layers; ++l)
    if (a.kind[l] != b.kind[l] || a.units[l] != b.units[l]) return false;
  return true;
}

// Whether a firmware that sent `rig` takes a model of shape `s`.
constexpr ShapeVerdict accepts(const RigInfo& rig, const ModelShape& s) {
  if (s.m != rig.m || s.n != rig.n || s.w != rig.w) return ShapeVerdict::OtherDims;
  if (rig.accept == shape_accept::kAny) {
    if (s.layers.layers > rig.max_layers) return ShapeVerdict::TooManyLayers;
    if (s.widest > rig.max_width) return ShapeVerdict::TooWide;
    if (s.weights > rig.max_weights) return ShapeVerdict::TooManyWeights;
    return ShapeVerdict::Accepted;
  }
  if (s.nd != rig.nd || s.dd != rig.nd) return ShapeVerdict::NotListed;
  size_t pos = 0;
  WireShape listed;
  while (next_shape(rig.shapes, rig.shapes_size, pos, listed))
    if (same_shape(listed, s.layers)) return ShapeVerdict::Accepted;
  return ShapeVerdict::NotListed;
}

// The file sizes a model of listed shape `s` can have on a rig with these
// dimensions: a GRU layer has one or two bias rows (reset_after), so a range.
struct SizeRange {
  uint32_t min = 0, max = 0;
};
constexpr SizeRange model_file_sizes(const RigInfo& rig, const WireShape& s) {
  const uint32_t p = uint32_t(rig.nd) * rig.m + uint32_t(rig.nd) * rig.n + rig.w;
  uint32_t params = 2 * p + 2 * uint32_t(rig.n), extra = 0, in = p;
  for (uint8_t l = 0; l < s.layers; ++l) {
    const uint32_t u = s.units[l];
    const LayerKind kind = LayerKind(s.kind[l]);
    // One bias row at the least; a second (reset_after) at the most.
    params += layer_weights(kind, in, u, false);
    if (layer_recurrent(s.kind[l])) extra += layer_columns(kind, u);
    in = u;
  }
  const uint32_t base = uint32_t(model_file_size(s.layers, params));
  return {base, base + 4 * extra};
}

// XFER_BEGIN's share of the check: with a shape list, a model file size no
// listed shape can have. (The header, which names the shape, arrives with the
// first chunk; with accept = any the size tells nothing a limit does not.)
constexpr bool size_fits_a_shape(const RigInfo& rig, uint32_t total_size) {
  if (rig.accept != shape_accept::kList) return true;
  size_t pos = 0;
  WireShape s;
  while (next_shape(rig.shapes, rig.shapes_size, pos, s)) {
    const SizeRange r = model_file_sizes(rig, s);
    if (total_size >= r.min && total_size <= r.max) return true;
  }
  return false;
}

}  // namespace nlsoft::protocol
