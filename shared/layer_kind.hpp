#pragma once
// A model layer's kind, one row per kind (LayerKindRow): its names, how
// many weight columns a unit has, whether it carries state, whether a file
// chooses its activation (else the kind's own, Keras' defaults: the image
// header writes such a layer as net_shape.hpp's KindLayer), and its
// enumerator's spelling for the image header. The model file and its
// loader, rig files, Keras import, the image generator, `train --arch` and
// the protocol's shape words all read the rows; a new kind is a row here,
// its number in AllLayerKinds, and its kernels: forward.hpp and rollout.hpp
// on the MCU, app/model/network.cpp for training (and, to take it from
// Keras, its weights' layout in app/model/keras_import.cpp; to run it in an
// image's shaped kernel, kernels.hpp, which refuses any kind but Dense and
// GRU there).
// Rows are types, not an array, so the MCU's code compiles a kind's facts
// to the comparisons it would write by hand and links none of the names.
#include <array>
#include <cstdint>

#include "shared/activation.hpp"

namespace nlsoft {

// The numbers are the model file's and RIG_INFO's shape words' (protocol/rig_shapes.hpp).
enum class LayerKind : uint8_t { Dense = 1, Gru = 2 };

template <LayerKind K>
struct LayerKindRow;

template <>
struct LayerKindRow<LayerKind::Dense> {
  static constexpr const char* name = "dense";          // rig files, --arch, --shape
  static constexpr const char* title = "Dense";         // model summaries, Keras' class name
  static constexpr const char* enumerator = "Dense";     // LayerKind::Dense, as the image header spells it
  static constexpr int gates = 1;                        // weight columns per unit
  static constexpr bool recurrent = false;               // a unit's previous output feeds it
  static constexpr bool free_activation = true;          // rig files, --activation and the image choose it
  static constexpr Activation act = Activation::Linear;  // the default
  static constexpr Activation rec_act = Activation::Linear;
};

template <>
struct LayerKindRow<LayerKind::Gru> {
  static constexpr const char* name = "gru";
  static constexpr const char* title = "GRU";
  static constexpr const char* enumerator = "Gru";
  static constexpr int gates = 3;  // z, r and the candidate h
  static constexpr bool recurrent = true;
  static constexpr bool free_activation = false;  // Keras' GRU defaults, read from the model at run time
  static constexpr Activation act = Activation::Tanh;
  static constexpr Activation rec_act = Activation::Sigmoid;
};

template <LayerKind... K>
struct LayerKindList {};
using AllLayerKinds = LayerKindList<LayerKind::Dense, LayerKind::Gru>;

namespace detail {
template <LayerKind... K>
constexpr int gates_of(uint8_t number, LayerKindList<K...>) {
  int g = 0;
  ((g = number == uint8_t(K) ? LayerKindRow<K>::gates : g), ...);
  return g;
}
template <LayerKind... K>
constexpr bool recurrent_of(uint8_t number, LayerKindList<K...>) {
  return ((number == uint8_t(K) && LayerKindRow<K>::recurrent) || ...);
}
}  // namespace detail

// Whether `number` is a layer kind's (a model file's layer table, a shape word).
constexpr bool layer_kind_known(uint8_t number) { return detail::gates_of(number, AllLayerKinds{}) != 0; }
// Weight columns per unit (a GRU's 3); an unknown number counts as Dense's 1.
constexpr int layer_gates(uint8_t number) {
  const int g = detail::gates_of(number, AllLayerKinds{});
  return g != 0 ? g : 1;
}
constexpr bool layer_recurrent(uint8_t number) { return detail::recurrent_of(number, AllLayerKinds{}); }

// A layer's weight columns: units times its gates (a GRU's 3 x units).
template <class T>
constexpr auto layer_columns(LayerKind kind, T units) {
  return units * T(layer_gates(uint8_t(kind)));
}

// Its weight and bias count from `in` inputs: the input weights, the
// recurrent ones, and one bias row, two for a recurrent layer that resets
// after its recurrent product (Keras' reset_after).
template <class T>
constexpr T layer_weights(LayerKind kind, T in, T units, bool reset_after) {
  const T cols = layer_columns(kind, units);
  const bool recurrent = layer_recurrent(uint8_t(kind));
  return in * cols + (recurrent ? units * cols : T(0)) + (recurrent && reset_after ? T(2) : T(1)) * cols;
}

// The rows as data, for the host's code that lists or names kinds.
struct LayerKindInfo {
  LayerKind kind;
  const char* name;
  const char* title;
  int gates;
  bool recurrent;
  const char* enumerator;
  bool free_activation;
  Activation act, rec_act;
};

namespace detail {
template <LayerKind... K>
constexpr std::array<LayerKindInfo, sizeof...(K)> layer_kind_infos(LayerKindList<K...>) {
  return {{{K, LayerKindRow<K>::name, LayerKindRow<K>::title, LayerKindRow<K>::gates, LayerKindRow<K>::recurrent,
            LayerKindRow<K>::enumerator, LayerKindRow<K>::free_activation, LayerKindRow<K>::act,
            LayerKindRow<K>::rec_act}...}};
}
constexpr bool same_text(const char* a, const char* b) {
  while (*a != '\0' && *a == *b) ++a, ++b;
  return *a == *b;
}
}  // namespace detail

inline constexpr auto kLayerKinds = detail::layer_kind_infos(AllLayerKinds{});

// The row of a kind's number, nullptr for none.
constexpr const LayerKindInfo* find_layer_kind(uint8_t number) {
  for (const LayerKindInfo& k : kLayerKinds)
    if (uint8_t(k.kind) == number) return &k;
  return nullptr;
}
// The row of a kind (one of kLayerKinds: a checked model's).
constexpr const LayerKindInfo& layer_kind_info(LayerKind kind) {
  const LayerKindInfo* k = find_layer_kind(uint8_t(kind));
  return k != nullptr ? *k : kLayerKinds[0];
}
// The row named `name` (rig files' "gru") or titled so (Keras' "GRU"), nullptr for none.
constexpr const LayerKindInfo* layer_kind_named(const char* name) {
  for (const LayerKindInfo& k : kLayerKinds)
    if (detail::same_text(k.name, name) || detail::same_text(k.title, name)) return &k;
  return nullptr;
}

}  // namespace nlsoft
